// Benchmark section "foundation": load, build, mollify, flip to intrinsic Delaunay, assemble
// cotan L + lumped M, on generated icospheres from 10k to 2M faces and on the shared meshes.
//
//   ifem_bench foundation [--repeat 5] [--max-faces 2100000] [--data ../shared/data/meshes]
//   ifem_bench foundation --peak FILE   (one pass on FILE; prints peak RSS, for a clean process)
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "bench_util.h"
#include "fem/operators.h"
#include "intrinsic/core/triangulation.h"
#include "intrinsic/generators/mesh_generators.h"
#include "intrinsic/io/mesh_io.h"

namespace ifem::bench {
namespace {

using intrinsic::IntrinsicTriangulation;

void write_obj(const std::string& path, const intrinsic::TriangleMesh& m) {
  std::FILE* f = std::fopen(path.c_str(), "w");
  for (Eigen::Index i = 0; i < m.positions.rows(); ++i) {
    std::fprintf(f, "v %.17g %.17g %.17g\n", m.positions(i, 0), m.positions(i, 1),
                 m.positions(i, 2));
  }
  for (const auto& t : m.faces) std::fprintf(f, "f %d %d %d\n", t[0] + 1, t[1] + 1, t[2] + 1);
  std::fclose(f);
}

struct Row {
  std::string name;
  long faces = 0;
  double load = 0, build = 0, mollify = 0, flip = 0, assemble = 0;
  std::size_t flips = 0;
};

Row run_file(const std::string& name, const std::string& path, int repeat) {
  Row r;
  r.name = name;
  io::SurfaceInput in;
  r.load = time_median(repeat, [&] { in = io::read_mesh(path); });
  r.faces = static_cast<long>(in.triangles.size());
  IntrinsicTriangulation tri;
  r.build = time_median(
      repeat, [&] { tri = IntrinsicTriangulation::from_positions(in.triangles, in.positions); });
  // mollify and flip mutate: time each on a fresh copy
  std::vector<double> tm, tf;
  for (int k = 0; k < repeat; ++k) {
    IntrinsicTriangulation t = tri;
    double t0 = seconds_now();
    t.mollify();
    tm.push_back(seconds_now() - t0);
    t0 = seconds_now();
    r.flips = t.flip_to_delaunay().flips;
    tf.push_back(seconds_now() - t0);
    if (k + 1 == repeat) tri = std::move(t);
  }
  r.mollify = median(tm);
  r.flip = median(tf);
  r.assemble = time_median(repeat, [&] {
    const fem::SparseMatrix L = fem::cotan_laplacian(tri);
    const Eigen::VectorXd M = fem::lumped_mass(tri);
    if (L.rows() != M.size()) std::abort();
  });
  return r;
}

int peak(const std::string& path) {
  const io::SurfaceInput in = io::read_mesh(path);
  auto tri = IntrinsicTriangulation::from_positions(in.triangles, in.positions);
  tri.mollify();
  tri.flip_to_delaunay();
  const fem::SparseMatrix L = fem::cotan_laplacian(tri);
  const Eigen::VectorXd M = fem::lumped_mass(tri);
  std::printf("%s: %zu faces, L nnz %ld, peak RSS %.0f MiB\n", path.c_str(), in.triangles.size(),
              long(L.nonZeros()), peak_rss_mib());
  return 0;
}

}  // namespace

int foundation(int argc, char** argv) {
  const std::string peak_file = string_option(argc, argv, "--peak", "");
  if (!peak_file.empty()) return peak(peak_file);
  const int repeat = static_cast<int>(int_option(argc, argv, "--repeat", 5));
  const long max_faces = int_option(argc, argv, "--max-faces", 2100000);
  const std::string data = string_option(argc, argv, "--data", IFEM_SHARED_MESHES);
  const auto tmp = std::filesystem::temp_directory_path() / "ifem_bench_foundation";
  std::filesystem::create_directories(tmp);

  std::vector<Row> rows;
  for (const int n : {23, 71, 224, 320}) {
    if (20L * n * n > max_faces) continue;
    const std::string path = (tmp / ("icosphere_" + std::to_string(n) + ".obj")).string();
    if (!std::filesystem::exists(path)) write_obj(path, intrinsic::icosphere(n));
    rows.push_back(run_file("icosphere(" + std::to_string(n) + ") .obj", path, repeat));
    std::fprintf(stderr, "done %s\n", rows.back().name.c_str());
  }
  for (const char* name : {"rocketship.ply", "igea_268k.ply", "armadillo.obj"}) {
    const auto p = std::filesystem::path(data) / name;
    if (!std::filesystem::exists(p)) continue;
    rows.push_back(run_file(name, p.string(), repeat));
    std::fprintf(stderr, "done %s\n", name);
  }
  std::printf("| mesh | faces | load s | build s | mollify s | flip to IDT s | flips | L+M s |\n");
  std::printf("|---|---:|---:|---:|---:|---:|---:|---:|\n");
  for (const Row& r : rows) {
    std::printf("| %s | %ld | %.4f | %.4f | %.4f | %.4f | %zu | %.4f |\n", r.name.c_str(), r.faces,
                r.load, r.build, r.mollify, r.flip, r.flips, r.assemble);
  }
  std::printf("\nmedian of %d runs; build = gluing map + lengths from positions\n", repeat);
  return 0;
}

}  // namespace ifem::bench
