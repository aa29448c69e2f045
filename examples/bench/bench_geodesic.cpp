// Benchmark section "geodesic": FlipOut geodesic paths (intrinsic/geodesic/flip_geodesic.h) on
// icospheres of growing size, from vertex 0 to the farthest vertex within chord 1.6 (a unique
// geodesic, about 106° of arc). Times: the signpost triangulation's construction, then
// Dijkstra + shortening, then tracing the path over the input (medians over --repeat runs);
// the length is compared with the great-circle arc (the mesh is inscribed: slightly shorter).
//
//   ifem_bench geodesic [--repeat 5] [--max-n 128]
#include <cmath>
#include <cstdio>
#include <vector>

#include "bench_util.h"
#include "intrinsic/generators/mesh_generators.h"
#include "intrinsic/geodesic/flip_geodesic.h"

namespace ifem::bench {
namespace {

Index far_vertex(const Positions& x, double* chord) {
  Index b = 1;
  *chord = -1.0;
  for (Index v = 1; v < x.rows(); ++v) {
    const double d = (x.row(v) - x.row(0)).norm();
    if (d < 1.6 && d > *chord) *chord = d, b = v;
  }
  return b;
}

void run_case(int n, int repeat) {
  using namespace intrinsic;
  const TriangleMesh m = icosphere(n);
  double chord = 0.0;
  const Index b = far_vertex(m.positions, &chord);
  std::vector<double> tb, ts, tt;
  FlipOutReport rep;
  for (int k = 0; k < repeat; ++k) {
    double t0 = seconds_now();
    SignpostTriangulation st(m.faces, m.positions);
    tb.push_back(seconds_now() - t0);
    t0 = seconds_now();
    EdgePath path = shortest_edge_path(st, 0, b);
    rep = shorten(st, path);
    ts.push_back(seconds_now() - t0);
    t0 = seconds_now();
    const std::vector<Eigen::Vector3d> line = path_polyline(st, path);
    tt.push_back(seconds_now() - t0);
  }
  const double arc = 2.0 * std::asin(chord / 2.0);
  std::printf("| icosphere(%3d) | %8zu | %8.4f | %8.4f | %8.5f | %7d | %7d | %.6f | %.6f | %s |\n",
              n, m.faces.size(), median(tb), median(ts), median(tt), rep.flips, rep.iterations,
              rep.initial_length / arc, rep.final_length / arc,
              rep.stopped_by == FlipOutStop::kConverged ? "yes" : "no");
}

}  // namespace

int geodesic(int argc, char** argv) {
  const int repeat = int(int_option(argc, argv, "--repeat", 5));
  const int max_n = int(int_option(argc, argv, "--max-n", 128));
  std::printf("## FlipOut geodesic paths (median of %d runs)\n\n", repeat);
  std::printf(
      "| mesh | faces | build s | path s | trace s | flips | reroutes | "
      "Dijkstra/arc | FlipOut/arc | converged |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|---|\n");
  for (int n = 8; n <= max_n; n *= 2) run_case(n, repeat);
  return 0;
}

}  // namespace ifem::bench
