// Benchmark section "curves": boundary-value problems with data on curves
// (solvers/recipes/curves.h) on icospheres of about 10k, 100k and 1M faces, with 1, 10 and 100
// geodesic paths through 3 vertices each and 1 and 10 closed loops through 3 vertices each (medians
// over --repeat runs):
//  - insertion (prepare_curve_surface without refinement): its wall time, surface.seconds_build
//    (the input's triangulation and the signpost one; the signposts alone are timed once per
//    mesh), seconds_curves (FlipOut + marking) and surface.seconds_flip (the constrained Delaunay
//    flips);
//  - constrained refinement (--min-angle 25, --resolution 1.0: triangles larger than the
//    equilateral one of side h are split): surface.seconds_refine, and what the report counts;
//  - the solves, on the constrained and on the refined triangulation: curve_poisson (curve c
//    holds the constant c mod 2, f = z) against solvers::solve_poisson on the same triangulation
//    with the same Dirichlet vertices and values (the target: the constrained solve
//    costs at most 1.2× the unconstrained one), and curve_distance against a HeatDistanceSolver
//    on the same triangulation with the same sources (every curve vertex). The two of each pair
//    run alternately within a repeat; max |Δ| compares their results.
// Curves: centers on a Fibonacci lattice of the unit sphere, radius 0.3 × the lattice spacing,
// each turned by a pseudo-random angle (splitmix64, fixed seed); the points are snapped to the
// nearest vertex, so the same curves are drawn on every mesh. A path bends at its middle vertex
// (offset sideways by a quarter of the radius); a loop is the geodesic triangle through three
// points at 120°. If two curves share an edge, the layout is drawn again with the next seed.
// Progress goes to stderr, the tables to stdout at the end.
//
//   ifem_bench curves [--repeat 3] [--min-faces 0] [--max-faces 1100000]
//                     [--max-refine-faces 1100000] [--min-angle 25] [--resolution 1.0]
//                     [--curves N (only the cases with N curves)] [--solves 0|1]
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdarg>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include "bench_util.h"
#include "intrinsic/core/errors.h"
#include "intrinsic/generators/mesh_generators.h"
#include "intrinsic/geodesic/curve_network.h"
#include "intrinsic/refine/signpost.h"
#include "solvers/recipes/curves.h"

namespace ifem::bench {
namespace {

using solvers::CurveCondition;
using solvers::CurveSurface;
using Vec3 = Eigen::Vector3d;

constexpr double kPi = 3.14159265358979323846;

// splitmix64: the same numbers on every platform (std's distributions are not portable).
struct Random {
  std::uint64_t state;
  double uniform() {  // in [0, 1)
    std::uint64_t z = (state += 0x9e3779b97f4a7c15ULL);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return static_cast<double>((z ^ (z >> 31)) >> 11) * 0x1.0p-53;
  }
};

// The point at angle a from p (unit) towards the unit tangent t: the sphere's exponential map.
Vec3 walk(const Vec3& p, const Vec3& t, double a) { return std::cos(a) * p + std::sin(a) * t; }

// Waypoints (on the unit sphere) of n curves, as the header comment describes.
std::vector<std::vector<Vec3>> curve_points(int n, bool loops, std::uint64_t seed) {
  Random rng{seed};
  const double r = 0.3 * std::sqrt(4.0 * kPi / n), golden = kPi * (3.0 - std::sqrt(5.0));
  std::vector<std::vector<Vec3>> out;
  for (int i = 0; i < n; ++i) {
    const double z = 1.0 - (2.0 * i + 1.0) / n, rho = std::sqrt(1.0 - z * z);
    const Vec3 c(rho * std::cos(golden * i), rho * std::sin(golden * i), z);
    const Vec3 e1 = c.unitOrthogonal(), e2 = c.cross(e1);
    const double th = 2.0 * kPi * rng.uniform();
    auto dir = [&](double a) -> Vec3 { return std::cos(th + a) * e1 + std::sin(th + a) * e2; };
    if (loops) {
      out.push_back(
          {walk(c, dir(0), r), walk(c, dir(2 * kPi / 3), r), walk(c, dir(4 * kPi / 3), r)});
    } else {
      const double side = rng.uniform() < 0.5 ? -0.25 : 0.25;
      out.push_back({walk(c, dir(kPi), r), walk(c, dir(kPi / 2), side * r), walk(c, dir(0), r)});
    }
  }
  return out;
}

// Smallest angle between two different curves (their great-circle arcs, sampled).
double smallest_gap(const std::vector<std::vector<Vec3>>& pts, bool loops) {
  std::vector<std::vector<Vec3>> samples(pts.size());
  for (std::size_t c = 0; c < pts.size(); ++c) {
    const std::size_t k = pts[c].size(), arcs = loops ? k : k - 1;
    for (std::size_t a = 0; a < arcs; ++a) {
      const Vec3 &p = pts[c][a], &q = pts[c][(a + 1) % k];
      for (int s = 0; s <= 32; ++s) {
        samples[c].push_back((p + (q - p) * (s / 32.0)).normalized());
      }
    }
  }
  double best = kPi;
  for (std::size_t a = 0; a < samples.size(); ++a) {
    for (std::size_t b = a + 1; b < samples.size(); ++b) {
      for (const Vec3& p : samples[a]) {
        for (const Vec3& q : samples[b]) best = std::min(best, 2.0 * std::asin((p - q).norm() / 2));
      }
    }
  }
  return best;
}

// The curves on mesh m: each point snapped to its nearest vertex; curve c holds c mod 2.
std::vector<CurveCondition> snap_curves(const intrinsic::TriangleMesh& m,
                                        const std::vector<std::vector<Vec3>>& pts, bool loops) {
  std::vector<CurveCondition> out;
  for (std::size_t c = 0; c < pts.size(); ++c) {
    CurveCondition cc;
    for (const Vec3& p : pts[c]) {
      Index best = 0;
      double d = 1e300;
      for (Index v = 0; v < m.positions.rows(); ++v) {
        const double e = (m.positions.row(v).transpose() - p).squaredNorm();
        if (e < d) d = e, best = v;
      }
      cc.vertices.push_back(best);
    }
    cc.shape = loops ? intrinsic::CurveShape::kLoop : intrinsic::CurveShape::kPath;
    cc.values = {static_cast<double>(c % 2)};
    out.push_back(std::move(cc));
  }
  return out;
}

io::SurfaceInput as_input(const intrinsic::TriangleMesh& m) {
  io::SurfaceInput in;
  in.positions = m.positions;
  in.triangles = m.faces;
  return in;
}

// One benchmark case: n curves, paths or loops, on one mesh.
struct Case {
  int n = 1;
  bool loops = false;
  std::string name() const {
    return std::to_string(n) +
           (loops ? (n == 1 ? " loop" : " loops") : (n == 1 ? " path" : " paths"));
  }
};

// A layout whose curves share no edge: the first seed for which prepare_curve_surface accepts it
// (that run is a warm-up, not timed). `tries` counts the layouts drawn, `gap` is the smallest
// angle between two curves of the accepted one.
std::vector<CurveCondition> accepted_curves(const intrinsic::TriangleMesh& m, const Case& k,
                                            int* tries, double* gap) {
  for (int t = 0; t < 20; ++t) {
    const auto pts = curve_points(k.n, k.loops, 2026 + static_cast<std::uint64_t>(t));
    std::vector<CurveCondition> curves = snap_curves(m, pts, k.loops);
    try {
      (void)solvers::prepare_curve_surface(as_input(m), curves);
    } catch (const InvalidInput& e) {
      if (std::string(e.what()).find("share the edge") == std::string::npos) throw;
      std::fprintf(stderr, "  %s, seed %d: %s; next seed\n", k.name().c_str(), 2026 + t, e.what());
      continue;
    }
    *tries = t + 1;
    *gap = k.n > 1 ? smallest_gap(pts, k.loops) : 0.0;
    return curves;
  }
  throw InvalidInput("bench curves: no layout without shared edges in 20 seeds");
}

struct PrepareTimes {
  std::vector<double> wall, build, curves, flip, refine;
};

// prepare_curve_surface `repeat` times; returns the last surface.
CurveSurface prepare_timed(const intrinsic::TriangleMesh& m,
                           const std::vector<CurveCondition>& curves,
                           const solvers::CurveSurfaceOptions& opt, int repeat, PrepareTimes& t) {
  CurveSurface s;
  for (int r = 0; r < repeat; ++r) {
    s = CurveSurface{};  // the previous one freed first: peak memory of one surface
    io::SurfaceInput in = as_input(m);
    const double t0 = seconds_now();
    s = solvers::prepare_curve_surface(std::move(in), curves, opt);
    t.wall.push_back(seconds_now() - t0);
    t.build.push_back(s.surface.seconds_build);
    t.curves.push_back(s.seconds_curves);
    t.flip.push_back(s.surface.seconds_flip);
    t.refine.push_back(s.surface.seconds_refine);
  }
  return s;
}

// Every vertex of every curve (sorted, unique) and the value its curve holds there.
void curve_vertices(const CurveSurface& s, std::vector<Index>& ids, Eigen::VectorXd& values) {
  std::vector<std::pair<Index, double>> vs;
  for (Index c = 0; c < s.network.n_curves(); ++c) {
    const intrinsic::CurveChain ch = intrinsic::curve_chain(s.surface.tri, s.network, c);
    for (const Index v : ch.vertices) vs.emplace_back(v, s.curves[c].values.front());
  }
  std::sort(vs.begin(), vs.end());
  vs.erase(std::unique(vs.begin(), vs.end(),
                       [](const auto& a, const auto& b) { return a.first == b.first; }),
           vs.end());
  ids.clear();
  values.resize(static_cast<Eigen::Index>(vs.size()));
  for (std::size_t i = 0; i < vs.size(); ++i) {
    ids.push_back(vs[i].first);
    values[static_cast<Eigen::Index>(i)] = vs[i].second;
  }
}

// Medians of two timed calls and of their per-run ratio a / b.
struct PairTimes {
  double a = 0, b = 0, ratio = 0;
};

// Times a() and b() `repeat` times each, alternating which of the two runs first (the first of
// a pair may pay for memory the second gets back from the allocator).
template <class A, class B>
PairTimes time_pair(int repeat, A&& a, B&& b) {
  std::vector<double> ta, tb, q;
  for (int r = 0; r < repeat; ++r) {
    double x = 0.0, y = 0.0;
    auto run_a = [&] {
      const double t0 = seconds_now();
      a();
      x = seconds_now() - t0;
    };
    auto run_b = [&] {
      const double t0 = seconds_now();
      b();
      y = seconds_now() - t0;
    };
    if (r % 2 == 0) {
      run_a(), run_b();
    } else {
      run_b(), run_a();
    }
    ta.push_back(x), tb.push_back(y), q.push_back(x / y);
  }
  return {median(ta), median(tb), median(q)};
}

struct SolveTimes {
  PairTimes poisson, distance;
  double poisson_diff = 0, distance_diff = 0;
  Index vertices = 0, dirichlet = 0;
};

// The constrained solves against the unconstrained ones on the same triangulation.
SolveTimes solve_timed(const CurveSurface& s, int repeat) {
  const solvers::PreparedSurface& p = s.surface;
  const Eigen::VectorXd f_in = p.input.positions.col(2);
  const Eigen::VectorXd f_all = solvers::from_input_vertices(p, f_in);
  std::vector<Index> ids;
  Eigen::VectorXd g;
  curve_vertices(s, ids, g);
  solvers::CurvePoissonResult res;
  Eigen::VectorXd u, d1, d2;
  SolveTimes out;
  out.poisson = time_pair(
      repeat, [&] { res = solvers::curve_poisson(s, f_in); },
      [&] { u = solvers::solve_poisson(p.tri, f_all, ids, g); });
  out.distance = time_pair(
      repeat, [&] { d1 = solvers::curve_distance(s); },
      [&] {
        const solvers::HeatDistanceSolver heat(p.tri, solvers::distance_options(p));
        d2 = solvers::on_input_vertices(p, heat.compute_distance(ids));
      });
  out.poisson_diff = (res.u_intrinsic - u).cwiseAbs().maxCoeff();
  out.distance_diff = (d1 - d2).cwiseAbs().maxCoeff();
  out.dirichlet = res.dirichlet_vertices;
  out.vertices = p.tri.n_vertices();
  return out;
}

std::string format(const char* fmt, ...) __attribute__((format(printf, 1, 2)));
std::string format(const char* fmt, ...) {
  char buf[512];
  va_list ap;
  va_start(ap, fmt);
  std::vsnprintf(buf, sizeof buf, fmt, ap);
  va_end(ap);
  return buf;
}

// 1234567 → "1,234,567".
std::string grouped(long x) {
  std::string d = std::to_string(x), out;
  for (std::size_t i = 0; i < d.size(); ++i) {
    if (i > 0 && (d.size() - i) % 3 == 0) out += ',';
    out += d[i];
  }
  return out;
}

Index curve_edge_count(const CurveSurface& s) {
  Index n = 0;
  for (const intrinsic::CurveEdge& e : s.network.edges) n += e.curve != kInvalidIndex ? 1 : 0;
  return n;
}

struct Settings {
  int repeat = 3;
  int only_curves = 0;  // run only the cases with this many curves (0: all)
  bool solves = true;
  long max_refine_faces = 1100000;
  solvers::SurfaceRefineOptions refine;
};

// The tables' rows, filled case by case (and echoed to stderr as they come).
struct Tables {
  std::vector<std::string> insert, refine, solve, notes;
  void add(std::vector<std::string>& to, const std::string& row) {
    to.push_back(row);
    std::fprintf(stderr, "%s\n", row.c_str());
  }
};

// The mesh's label and face count, the first columns of every row.
struct MeshInfo {
  std::string label;
  long faces = 0;
  double seconds_signposts = 0;  // median time of the signpost triangulation alone
};

std::string solve_row(const MeshInfo& mi, const Case& k, const char* tri, const SolveTimes& t) {
  return format(
      "| %s | %s | %s | %s | %s | %.4f | %.4f | **%.2f** | %.1e | %.4f | %.4f | **%.2f** | %.1e |",
      mi.label.c_str(), k.name().c_str(), tri, grouped(t.vertices).c_str(),
      grouped(t.dirichlet).c_str(), t.poisson.a, t.poisson.b, t.poisson.ratio, t.poisson_diff,
      t.distance.a, t.distance.b, t.distance.ratio, t.distance_diff);
}

void insertion_rows(const MeshInfo& mi, const Case& k, const CurveSurface& s, const PrepareTimes& t,
                    int tries, double gap, Tables& out) {
  const intrinsic::FlipOutReport& fo = s.network.flipout;
  const double curves = median(t.curves);
  std::string stop = intrinsic::to_string(fo.stopped_by);
  if (fo.blocked_joints) stop += ", " + std::to_string(fo.blocked_joints) + " bent";
  out.add(out.insert,
          format("| %s | %s | %s | %.4f | %.4f | %.4f | %.4f | %s | %s | %s | %s | %d | %.3f | "
                 "%.0f |",
                 mi.label.c_str(), grouped(mi.faces).c_str(), k.name().c_str(), median(t.wall),
                 median(t.build), curves, median(t.flip), grouped(fo.flips).c_str(),
                 grouped(s.constrained_flips.flips).c_str(), grouped(curve_edge_count(s)).c_str(),
                 stop.c_str(), tries, gap, peak_rss_mib()));
}

void refine_row(const MeshInfo& mi, const Case& k, const CurveSurface& s, const PrepareTimes& t,
                Tables& out) {
  const intrinsic::RefineReport& r = s.surface.refine_report;
  out.add(
      out.refine,
      format("| %s | %s | %s | %.4f | %.4f | %s → %s | %s | %s | %s | %.2f° | %d / %d / %d | %s | "
             "%.0f |",
             mi.label.c_str(), grouped(mi.faces).c_str(), k.name().c_str(), median(t.refine),
             median(t.wall), grouped(r.vertices_before).c_str(), grouped(r.vertices_after).c_str(),
             grouped(r.constrained_splits).c_str(), grouped(r.constrained_floor).c_str(),
             grouped(curve_edge_count(s)).c_str(), r.min_angle_after_excluding_needles,
             int(r.needle_faces), int(r.bad_faces_left), int(r.failed_traces),
             r.hit_insertion_cap ? "cap" : "no", peak_rss_mib()));
}

// One case on one mesh: insertion and solves, then refinement and solves on the refined one.
void run_case(const intrinsic::TriangleMesh& m, const MeshInfo& mi, const Case& k,
              const Settings& set, Tables& out) {
  int tries = 0;
  double gap = 0.0;
  const std::vector<CurveCondition> curves = accepted_curves(m, k, &tries, &gap);
  {
    PrepareTimes t;
    const CurveSurface s = prepare_timed(m, curves, {}, set.repeat, t);
    insertion_rows(mi, k, s, t, tries, gap, out);
    if (set.solves) out.add(out.solve, solve_row(mi, k, "constrained", solve_timed(s, set.repeat)));
  }
  if (mi.faces > set.max_refine_faces) return;
  solvers::CurveSurfaceOptions opt;
  opt.refine = set.refine;
  PrepareTimes t;
  const CurveSurface s = prepare_timed(m, curves, opt, set.repeat, t);
  refine_row(mi, k, s, t, out);
  if (set.solves) out.add(out.solve, solve_row(mi, k, "refined", solve_timed(s, set.repeat)));
}

void print_tables(const Settings& set, const Tables& t) {
  std::printf("## Inserting the curves (median of %d runs)\n\n", set.repeat);
  std::printf(
      "| mesh | faces | curves | prepare s | build s | curves s | constrained flips s "
      "| FlipOut flips | Delaunay flips | curve edges | FlipOut stop | layouts | gap rad | peak "
      "MiB |\n|---|---:|---|---:|---:|---:|---:|---:|---:|---:|---|---:|---:|---:|\n");
  for (const std::string& r : t.insert) std::printf("%s\n", r.c_str());
  std::printf("\n");
  for (const std::string& r : t.notes) std::printf("%s\n", r.c_str());
  std::printf("\n## Constrained refinement, %.0f° and resolution %.2g (median of %d runs)\n\n",
              set.refine.min_angle_degrees, set.refine.resolution, set.repeat);
  std::printf(
      "| mesh | faces | curves | refine s | prepare s | vertices | curve splits | below floor | "
      "curve edges | min angle | needles / bad / failed | cap | peak MiB |\n"
      "|---|---:|---|---:|---:|---|---:|---:|---:|---:|---|---|---:|\n");
  for (const std::string& r : t.refine) std::printf("%s\n", r.c_str());
  std::printf(
      "\n## Solves: constrained against unconstrained on the same triangulation (median "
      "of %d runs)\n\n",
      set.repeat);
  std::printf(
      "| mesh | curves | triangulation | vertices | Dirichlet | curve_poisson s | solve_poisson s "
      "| ratio | max Δu | curve_distance s | heat s | ratio | max Δd |\n"
      "|---|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
  for (const std::string& r : t.solve) std::printf("%s\n", r.c_str());
}

double signpost_seconds(const intrinsic::TriangleMesh& m, int repeat) {
  return time_median(repeat, [&] {
    const intrinsic::SignpostTriangulation st(m.faces, m.positions,
                                              intrinsic::kDefaultMollifyEpsilon);
  });
}

}  // namespace

int curves(int argc, char** argv) {
  Settings set;
  set.repeat = int(int_option(argc, argv, "--repeat", 3));
  const long min_faces = int_option(argc, argv, "--min-faces", 0);
  const long max_faces = int_option(argc, argv, "--max-faces", 1100000);
  set.max_refine_faces = int_option(argc, argv, "--max-refine-faces", 1100000);
  set.refine.min_angle_degrees = std::stod(string_option(argc, argv, "--min-angle", "25"));
  set.refine.resolution = std::stod(string_option(argc, argv, "--resolution", "1.0"));
  set.only_curves = int(int_option(argc, argv, "--curves", 0));
  set.solves = int_option(argc, argv, "--solves", 1) != 0;
  print_load_average();
  const Case cases[] = {{1, false}, {10, false}, {100, false}, {1, true}, {10, true}};
  Tables tables;
  for (const int n : {23, 71, 224}) {  // 10,580 / 100,820 / 1,003,520 faces
    const long faces = 20L * n * n;
    if (faces < min_faces || faces > max_faces) continue;
    const intrinsic::TriangleMesh m = intrinsic::icosphere(n);
    MeshInfo mi{"icosphere(" + std::to_string(n) + ")", faces, signpost_seconds(m, set.repeat)};
    tables.add(tables.notes, format("- %s: the signpost triangulation alone %.4f s",
                                    mi.label.c_str(), mi.seconds_signposts));
    for (const Case& k : cases) {
      if (set.only_curves == 0 || k.n == set.only_curves) run_case(m, mi, k, set, tables);
    }
  }
  print_tables(set, tables);
  return 0;
}

}  // namespace ifem::bench
