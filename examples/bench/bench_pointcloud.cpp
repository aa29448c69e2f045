// Benchmark section "pointcloud": the tufted-cover Laplacian on nonmanifold and big meshes, and
// the point-cloud Laplacian with each stage timed (kNN, local Delaunay, tufted cover +
// mollification, intrinsic Delaunay, assembly of L + M) on points sampled from icospheres.
//
//   ifem_bench pointcloud [--repeat 3] [--max-points 1000000] [--data ../shared/data/meshes]
//   ifem_bench pointcloud --points N   (one cloud of ≈N points; for a clean peak-RSS figure)
//   --merge none|half|union            (pointcloud::PointCloudOptions::merge; default half)
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include "bench_util.h"
#include "fem/operators.h"
#include "intrinsic/generators/mesh_generators.h"
#include "intrinsic/io/mesh_io.h"
#include "intrinsic/surface/tufted_cover.h"
#include "pointcloud/pointcloud_laplacian.h"

namespace ifem::bench {
namespace {

using intrinsic::IntrinsicTriangulation;

struct MeshRow {
  double cover = 0, mollify = 0, flip = 0, assemble = 0;
  std::size_t flips = 0;
  Index nonmanifold = 0;
};

MeshRow run_mesh(const std::vector<Triangle>& faces, const Positions& positions, int repeat) {
  std::vector<double> tc, tm, tf, ta;
  MeshRow r;
  for (int k = 0; k < repeat; ++k) {
    double t0 = seconds_now();
    intrinsic::TuftedCoverReport rep;
    IntrinsicTriangulation tri = intrinsic::tufted_cover(faces, positions, &rep);
    tc.push_back(seconds_now() - t0);
    t0 = seconds_now();
    tri.mollify();
    tm.push_back(seconds_now() - t0);
    t0 = seconds_now();
    r.flips = tri.flip_to_delaunay().flips;
    tf.push_back(seconds_now() - t0);
    t0 = seconds_now();
    const fem::SparseMatrix L = fem::cotan_laplacian(tri);
    const Eigen::VectorXd m = fem::lumped_mass(tri);
    ta.push_back(seconds_now() - t0);
    r.nonmanifold = rep.nonmanifold_edges;
    if (L.rows() != m.size()) std::printf("size mismatch\n");
  }
  r.cover = median(tc);
  r.mollify = median(tm);
  r.flip = median(tf);
  r.assemble = median(ta);
  return r;
}

void print_mesh_row(const std::string& name, long faces, const MeshRow& r) {
  std::printf("| %-22s | %9ld | %6d | %8.4f | %8.4f | %8.4f | %8.4f | %8.4f | %8zu |\n",
              name.c_str(), faces, r.nonmanifold, r.cover, r.mollify, r.flip, r.assemble,
              r.cover + r.mollify + r.flip + r.assemble, r.flips);
  std::fflush(stdout);
}

// ≈n points on the unit sphere: icosphere vertices, jittered tangentially (deterministic) so
// that no four neighbours are exactly cocircular.
Positions sphere_points(long n) {
  const int sub = std::max(1, static_cast<int>(std::lround(std::sqrt((n - 2) / 10.0))));
  intrinsic::TriangleMesh m = intrinsic::icosphere(sub);
  std::mt19937 rng(7);
  std::normal_distribution<double> g(0.0, 1.0);
  const double h = 1.0 / sub;
  for (Eigen::Index i = 0; i < m.positions.rows(); ++i) {
    Eigen::RowVector3d x = m.positions.row(i);
    x += 0.15 * h * Eigen::RowVector3d(g(rng), g(rng), g(rng));
    m.positions.row(i) = x.normalized();
  }
  return m.positions;
}

pointcloud::PointCloudOptions g_cloud_options;

void run_cloud(long n, int repeat) {
  const Positions p = sphere_points(n);
  std::vector<double> tk, tl, tc, ti, ta, tt;
  pointcloud::Report rep;
  for (int k = 0; k < repeat; ++k) {
    const double t0 = seconds_now();
    const IntrinsicTriangulation tri =
        pointcloud::pointcloud_triangulation(p, g_cloud_options, nullptr, &rep);
    const double t1 = seconds_now();
    const fem::SparseMatrix L = fem::cotan_laplacian(tri);
    const Eigen::VectorXd m = fem::lumped_mass(tri);
    const double t2 = seconds_now();
    tk.push_back(rep.seconds_knn);
    tl.push_back(rep.seconds_local);
    tc.push_back(rep.seconds_cover);
    ti.push_back(rep.seconds_idt);
    ta.push_back(t2 - t1);
    tt.push_back(t2 - t0);
    if (L.rows() != m.size()) std::printf("size mismatch\n");
  }
  std::printf(
      "| %9ld | %9d | %7.3f | %7.3f | %7.3f | %7.3f | %7.3f | %7.3f | %8zu | %5d | %7.0f |\n",
      static_cast<long>(p.rows()), rep.local_triangles, median(tk), median(tl), median(tc),
      median(ti), median(ta), median(tt), rep.flips.flips, rep.isolated_points, peak_rss_mib());
  std::fflush(stdout);
}

void cloud_header() {
  std::printf(
      "| points    | local tri | kNN s   | local s | cover s | IDT s   | L+M s   | total s "
      "| flips    | isol. | peak MiB |\n");
  std::printf(
      "|-----------|-----------|---------|---------|---------|---------|---------|---------"
      "|----------|-------|----------|\n");
}

}  // namespace

int pointcloud(int argc, char** argv) {
  const int repeat = static_cast<int>(int_option(argc, argv, "--repeat", 3));
  const long only = int_option(argc, argv, "--points", 0);
  const std::string merge = string_option(argc, argv, "--merge", "half");
  g_cloud_options.merge = merge == "none"    ? pointcloud::PointCloudOptions::Merge::kNone
                          : merge == "union" ? pointcloud::PointCloudOptions::Merge::kUnion
                                             : pointcloud::PointCloudOptions::Merge::kHalf;
  if (only > 0) {
    cloud_header();
    run_cloud(only, repeat);
    return 0;
  }
  const long max_points = int_option(argc, argv, "--max-points", 1000000);
  const std::string data = string_option(argc, argv, "--data", IFEM_SHARED_MESHES);

  std::printf("## Tufted-cover Laplacian (cover, mollify, intrinsic Delaunay, L + M)\n\n");
  std::printf(
      "| mesh                   | faces     | nm e.  | cover s  | mollify  | IDT s    "
      "| L+M s    | total s  | flips    |\n");
  std::printf(
      "|------------------------|-----------|--------|----------|----------|----------"
      "|----------|----------|----------|\n");
  for (const char* name :
       {"fan3.obj", "triple_vierbein.obj", "moebius.obj", "beetle_sutherland.obj", "truck.obj",
        "conrod.off", "thingi10k_138207.obj", "thingi10k_49220.obj", "thingi10k_73342.obj",
        "thingi10k_90225.obj", "cgal_all_degen.off", "cgal_fused_vertices.off", "rocketship.ply",
        "igea_268k.ply"}) {
    const std::string path = data + "/" + name;
    if (!std::filesystem::exists(path)) continue;
    const io::SurfaceInput in = io::read_surface(path);
    print_mesh_row(name, static_cast<long>(in.triangles.size()),
                   run_mesh(in.triangles, in.positions, repeat));
  }
  {
    const intrinsic::TriangleMesh m = intrinsic::icosphere(224);
    print_mesh_row("icosphere(224)", static_cast<long>(m.faces.size()),
                   run_mesh(m.faces, m.positions, repeat));
  }

  std::printf(
      "\n## Point-cloud Laplacian, k = 30 (jittered icosphere vertices; peak RSS is the "
      "process's so far)\n\n");
  cloud_header();
  for (const long n : {10000L, 100000L, 134000L, 500000L, 1000000L}) {
    if (n > max_points) break;
    run_cloud(n, n >= 500000 ? 1 : repeat);
  }
  return 0;
}

}  // namespace ifem::bench
