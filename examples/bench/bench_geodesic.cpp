// Benchmark section "geodesic": FlipOut (intrinsic/geodesic/flip_geodesic.h) on icospheres of
// about 10k, 100k and 1M faces (medians over --repeat runs):
//  - a path between vertex 0 and a far vertex (chord closest to 1.9, about 144° of arc: a unique
//    geodesic): the signpost triangulation's construction, the Dijkstra start path, the
//    shortening, and tracing the result over the input, as geometry-central's FlipEdgeNetwork
//    is timed (set-up = construction + Dijkstra); the length against the great-circle arc (the
//    mesh is inscribed: slightly shorter);
//  - single-source geodesics from vertex 0 (up to --max-ssad-faces faces);
//  - a cubic geodesic Bézier curve, 4 rounds of subdivision;
//  - the process's peak resident memory after each row (it only grows: rows run in size order).
//
//   ifem_bench geodesic [--repeat 5] [--max-faces 1100000] [--max-ssad-faces 110000]
//
// With --mesh FILE|icosphere:N, one mesh only, one line for scripts (scripts/bench_flipout.sh
// runs two builds side by side): the shortening of the path from vertex 0 to the vertex
// farthest from it in space (its median time, flips and µs per flip) and, unless --ssad 0,
// single-source geodesics from vertex 0 (median time, flips, blocked vertices). Times are the
// thread's CPU seconds, so that a loaded machine does not count other processes' time.
//
//   ifem_bench geodesic --mesh FILE|icosphere:N [--repeat 5] [--ssad 1]
#include <cmath>
#include <cstdio>
#include <ctime>
#include <string>
#include <vector>

#include "bench_util.h"
#include "intrinsic/generators/mesh_generators.h"
#include "intrinsic/geodesic/flip_geodesic.h"
#include "intrinsic/io/mesh_io.h"

namespace ifem::bench {
namespace {

using namespace intrinsic;

// The vertex whose chord from vertex 0 is closest to `chord`.
Index vertex_at_chord(const Positions& x, double chord, double* got) {
  Index b = 1;
  double best = 1e300;
  for (Index v = 1; v < x.rows(); ++v) {
    const double d = (x.row(v) - x.row(0)).norm();
    if (std::abs(d - chord) < best) best = std::abs(d - chord), b = v, *got = d;
  }
  return b;
}

void path_row(int n, int repeat) {
  const TriangleMesh m = icosphere(n);
  double chord = 0.0;
  const Index b = vertex_at_chord(m.positions, 1.9, &chord);
  std::vector<double> tb, td, ts, tt;
  FlipOutReport rep;
  for (int k = 0; k < repeat; ++k) {
    double t0 = seconds_now();
    SignpostTriangulation st(m.faces, m.positions);
    tb.push_back(seconds_now() - t0);
    t0 = seconds_now();
    EdgePath path = shortest_edge_path(st, 0, b);
    td.push_back(seconds_now() - t0);
    t0 = seconds_now();
    rep = shorten(st, path);
    ts.push_back(seconds_now() - t0);
    t0 = seconds_now();
    const std::vector<Eigen::Vector3d> line = path_polyline(st, path);
    tt.push_back(seconds_now() - t0);
  }
  const double arc = 2.0 * std::asin(chord / 2.0);
  std::printf(
      "| icosphere(%3d) | %8zu | %7.4f | %7.4f | %7.4f | %7.4f | %7.5f | %6d | %5d | %.4f | %.6f | "
      "%s | %6.0f |\n",
      n, m.faces.size(), median(tb), median(td), median(tb) + median(td), median(ts), median(tt),
      int(rep.flips), int(rep.iterations), rep.initial_length / arc, rep.final_length / arc,
      to_string(rep.stopped_by), peak_rss_mib());
}

void other_rows(int n, int repeat, bool ssad) {
  const TriangleMesh m = icosphere(n);
  double chord = 0.0;
  const Index b = vertex_at_chord(m.positions, 1.9, &chord);
  const Index c = vertex_at_chord(m.positions, 1.0, &chord);
  const Index d = vertex_at_chord(m.positions, 1.4, &chord);
  std::vector<double> t_ssad, t_bez;
  SingleSourceGeodesics g;
  BezierCurve bez;
  for (int k = 0; k < repeat; ++k) {
    if (ssad) {
      SignpostTriangulation st(m.faces, m.positions);
      const double t0 = seconds_now();
      g = single_source_geodesics(st, 0);
      t_ssad.push_back(seconds_now() - t0);
    }
    SignpostTriangulation st(m.faces, m.positions);
    const double t0 = seconds_now();
    bez = bezier_curve(st, {0, c, d, b}, 4);
    t_bez.push_back(seconds_now() - t0);
  }
  if (ssad) {
    double worst = 0.0;  // a geodesic on the inscribed sphere is never longer than the arc
    for (Index v = 1; v < m.positions.rows(); ++v) {
      const double ch = (m.positions.row(v) - m.positions.row(0)).norm();
      worst = std::max(worst, g.length[v] / (2.0 * std::asin(std::min(1.0, ch / 2.0))) - 1.0);
    }
    std::printf(
        "| single-source | icosphere(%3d) | %8zu | %7.3f s | %d flips, %d reroutes, %d "
        "blocked; worst length/arc − 1 = %.1e | %6.0f MiB |\n",
        n, m.faces.size(), median(t_ssad), int(g.flips), int(g.iterations), int(g.blocked), worst,
        peak_rss_mib());
  }
  std::printf(
      "| Bézier (cubic, 4 rounds) | icosphere(%3d) | %8zu | %7.3f s | %zu control points, "
      "%d inserted, length %.4f | %6.0f MiB |\n",
      n, m.faces.size(), median(t_bez), bez.controls.size(), int(bez.inserted_vertices),
      bez.report.final_length, peak_rss_mib());
}

// CPU time of this thread (the machine may be shared: wall time would count other processes).
double thread_seconds() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

// One mesh, one line: shortening (time, flips, µs per flip) and single-source geodesics.
void mesh_row(const std::string& spec, int repeat, bool ssad) {
  TriangleMesh m;
  const std::string ico = "icosphere:";
  if (spec.rfind(ico, 0) == 0) {
    m = icosphere(std::stoi(spec.substr(ico.size())));
  } else {
    const io::SurfaceInput in = io::read_mesh(spec);
    m.faces = in.triangles;
    m.positions = in.positions;
  }
  Index far = 1;
  for (Index v = 1; v < m.positions.rows(); ++v) {
    const auto d = [&](Index u) { return (m.positions.row(u) - m.positions.row(0)).norm(); };
    if (d(v) > d(far)) far = v;
  }
  std::vector<double> ts, t_ssad;
  FlipOutReport rep;
  SingleSourceGeodesics g;
  for (int k = 0; k < repeat; ++k) {
    SignpostTriangulation st(m.faces, m.positions);
    EdgePath path = shortest_edge_path(st, 0, far);
    const double t0 = thread_seconds();
    rep = shorten(st, path);
    ts.push_back(thread_seconds() - t0);
    if (!ssad) continue;
    SignpostTriangulation st2(m.faces, m.positions);
    const double t1 = thread_seconds();
    g = single_source_geodesics(st2, 0);
    t_ssad.push_back(thread_seconds() - t1);
  }
  double total = 0.0;
  for (Index v = 0; ssad && v < g.length.size(); ++v) total += g.length[v];
  std::printf(
      "flipout mesh %s faces %zu shorten_s %.6f flips %d us_per_flip %.4f length %.17g "
      "ssad_s %.4f ssad_flips %d ssad_blocked %d ssad_length_sum %.17g\n",
      spec.c_str(), m.faces.size(), median(ts), int(rep.flips),
      1e6 * median(ts) / std::max(1, int(rep.flips)), rep.final_length, ssad ? median(t_ssad) : 0.0,
      int(g.flips), int(g.blocked), total);
}

}  // namespace

int geodesic(int argc, char** argv) {
  const int repeat = int(int_option(argc, argv, "--repeat", 5));
  const std::string spec = string_option(argc, argv, "--mesh", "");
  if (!spec.empty()) {
    mesh_row(spec, repeat, int_option(argc, argv, "--ssad", 1) != 0);
    return 0;
  }
  const long max_faces = int_option(argc, argv, "--max-faces", 1100000);
  const long max_ssad = int_option(argc, argv, "--max-ssad-faces", 110000);
  const int sizes[] = {23, 71, 224};  // 10,580 / 100,820 / 1,003,520 faces
  std::printf("## FlipOut geodesic paths (median of %d runs)\n\n", repeat);
  std::printf(
      "| mesh | faces | build s | Dijkstra s | set-up s | shorten s | trace s | flips | "
      "reroutes | Dijkstra/arc | FlipOut/arc | stop | peak MiB |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
  for (const int n : sizes) {
    if (20L * n * n <= max_faces) path_row(n, repeat);
  }
  std::printf("\n## Single-source geodesics and Bézier curves (median of %d runs)\n\n", repeat);
  std::printf("| what | mesh | faces | time | result | peak |\n|---|---|---|---|---|---|\n");
  for (const int n : sizes) {
    if (20L * n * n <= max_faces) other_rows(n, repeat, 20L * n * n <= max_ssad);
  }
  return 0;
}

}  // namespace ifem::bench
