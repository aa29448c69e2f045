// Benchmark section `field`: smoothest and aligned n-direction fields
// (solvers/vector/direction_field.h) for n = 1 and 4 on icospheres of 10k..1M faces, rocketship and
// igea: seconds (connection Laplacian, factorization and iterations; the tangent frames are built
// before the clock starts), LOBPCG steps, energy and the sum of the singularities' indices.
//
//   ifem_bench field [--repeat N] [--max-n 224] [--data DIR]
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "bench_util.h"
#include "fem/connection.h"
#include "intrinsic/core/triangulation.h"
#include "intrinsic/generators/mesh_generators.h"
#include "intrinsic/io/mesh_io.h"
#include "solvers/recipes/pipeline.h"
#include "solvers/vector/direction_field.h"

namespace ifem::bench {
namespace {

// One row per (n, kind): median seconds over `repeat` runs; steps, energy and indices of the last.
void field_rows(const std::string& name, const intrinsic::IntrinsicTriangulation& tri, int repeat) {
  const fem::TangentFrames frames = fem::tangent_frames(tri);
  const Index nv = tri.n_vertices();
  const std::vector<solvers::DirectionConstraint> held = {
      {0, 0.0}, {nv / 3, 0.0}, {(2 * nv) / 3, 0.0}};
  for (const int n : {1, 4}) {
    for (const bool aligned : {false, true}) {
      solvers::DirectionFieldOptions o;
      o.symmetry = n;
      solvers::DirectionField f;
      const double t = time_median(repeat, [&] {
        f = aligned ? solvers::aligned_field(tri, frames, held, o)
                    : solvers::smoothest_field(tri, frames, o);
      });
      const Eigen::VectorXi index = solvers::face_indices(tri, frames, f.u, n);
      std::printf("| %s | %ld | %d | %s | %.3f | %d | %.10g | %d/%d | %.0f |\n", name.c_str(),
                  long(tri.n_faces()), n, aligned ? "aligned (3 vertices)" : "smoothest", t,
                  f.iterations, f.energy, index.sum(), n, peak_rss_mib());
      std::fflush(stdout);
    }
  }
}

}  // namespace

int field(int argc, char** argv) {
  const int repeat = int(int_option(argc, argv, "--repeat", 3));
  const int max_n = int(int_option(argc, argv, "--max-n", 224));
  const std::string data = string_option(argc, argv, "--data", IFEM_SHARED_MESHES);
  print_load_average();
  std::printf("## direction fields (median of %d runs)\n\n", repeat);
  std::printf(
      "| mesh | faces | n | field | seconds | LOBPCG steps | energy | index sum | peak MiB |\n"
      "|---|---|---|---|---|---|---|---|---|\n");
  for (const int n : {23, 71, 224}) {
    if (n > max_n) continue;
    const auto m = intrinsic::icosphere(n);
    auto tri = intrinsic::IntrinsicTriangulation::from_positions(m.faces, m.positions);
    tri.mollify();
    tri.flip_to_delaunay();
    field_rows("icosphere(" + std::to_string(n) + ")", tri, repeat);
  }
  for (const char* f : {"rocketship.ply", "igea_268k.ply"}) {
    const std::string path = data + "/" + f;
    if (!std::filesystem::exists(path)) continue;
    const solvers::PreparedSurface s = solvers::prepare_surface(io::read_mesh(path));
    field_rows(f, s.tri, repeat);
  }
  return 0;
}

}  // namespace ifem::bench
