// Benchmark section `isolines`: the isolines of a heat distance (10 levels, marching triangles on
// the input mesh: solvers/recipes/isolines.h) against the heat query that made the field, timed
// interleaved on the same icosphere (ratios hold on a shared machine).
//
//   ifem_bench isolines [--repeat N] [--max-n 224] [--levels 10]
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "bench_util.h"
#include "intrinsic/core/triangulation.h"
#include "intrinsic/generators/mesh_generators.h"
#include "solvers/recipes/isolines.h"
#include "solvers/scalar/heat_distance.h"

namespace ifem::bench {

int isolines(int argc, char** argv) {
  int repeat = 5, max_n = 224, levels = 10;
  for (int i = 1; i + 1 < argc; i += 2) {
    if (!std::strcmp(argv[i], "--repeat")) repeat = std::atoi(argv[i + 1]);
    if (!std::strcmp(argv[i], "--max-n")) max_n = std::atoi(argv[i + 1]);
    if (!std::strcmp(argv[i], "--levels")) levels = std::atoi(argv[i + 1]);
  }
  print_load_average();
  std::printf(
      "isolines of a heat distance from vertex 0 (%d levels) vs that heat query, "
      "interleaved, median (min) of %d\n",
      levels, repeat);
  for (int n : {23, 71, 224}) {
    if (n > max_n) break;
    const intrinsic::TriangleMesh m = intrinsic::icosphere(n);
    auto tri = intrinsic::IntrinsicTriangulation::from_positions(m.faces, m.positions);
    tri.mollify();
    const solvers::HeatDistanceSolver solver(tri);
    const Eigen::VectorXd d = solver.compute_distance({0});
    const std::vector<double> c = recipes::isoline_levels(d, levels);
    std::size_t pieces = 0, points = 0;
    const InterleavedTimes t = time_interleaved(repeat, {[&] { solver.compute_distance({0}); },
                                                         [&] {
                                                           const auto lines = recipes::isolines(
                                                               m.positions, m.faces, d, c);
                                                           pieces = lines.size();
                                                           points = 0;
                                                           for (const auto& l : lines)
                                                             points += l.points.size();
                                                         }});
    std::printf(
        "icosphere(%d), %zu faces: heat query %.4f s (%.4f), isolines %.4f s (%.4f): %.3f× the "
        "query (min: %.3f×); %zu pieces, %zu points\n",
        n, m.faces.size(), t.median[0], t.min[0], t.median[1], t.min[1], t.median[1] / t.median[0],
        t.min[1] / t.min[0], pieces, points);
  }
  return 0;
}

}  // namespace ifem::bench
