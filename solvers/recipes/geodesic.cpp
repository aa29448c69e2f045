// The geodesic recipe (geodesic.h): signposts of the input, face points inserted, FlipOut or de
// Casteljau, curves traced over the input.
#include "solvers/recipes/geodesic.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <memory>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "intrinsic/core/errors.h"
#include "intrinsic/core/timer.h"
#include "intrinsic/geodesic/curve_network.h"
#include "intrinsic/geodesic/exact_distance.h"
#include "intrinsic/geodesic/input_surface.h"
#include "solvers/recipes/exact_distance.h"
#include "solvers/recipes/pipeline.h"
#include "solvers/scalar/heat_distance.h"

namespace ifem::recipes {
namespace {

using intrinsic::EdgePath;
using intrinsic::SignpostTriangulation;

constexpr int kMaxBezierRounds = 16;

// Inputs up to this many vertices get the refined (accurate) guide; larger ones the heat method
// on the input's intrinsic Delaunay triangulation (the refinement's ~9× vertices cost tens of
// seconds there: docs/decisions.md D-124).
constexpr Index kRefinedGuideMaxVertices = 20000;

std::string range(Index n) { return "[0, " + std::to_string(n) + ")"; }

// The signpost triangulation of the input: refused without faces (a point cloud), without
// area, or when not edge-manifold and orientable (intrinsic::flipout_surface's messages).
SignpostTriangulation signposts(const io::SurfaceInput& in, double mollify) {
  if (!in.has_faces()) {
    throw InvalidInput("geodesic needs a triangle mesh (the input has no faces: a point cloud)");
  }
  return intrinsic::flipout_surface(in, mollify);
}

// The intrinsic vertex ids of every curve's points: input vertices as given, face points
// inserted (all before any path is built; the same face point twice is one vertex). Fills the
// curves' `points` and out.inserted.
std::vector<std::vector<Index>> insert_points(SignpostTriangulation& st, const io::SurfaceInput& in,
                                              const std::vector<GivenCurve>& curves,
                                              GeodesicCurves& out) {
  const std::vector<Index> input_face =
      intrinsic::given_face_map(st.input_face_origin(), in.triangles.size());
  std::map<std::tuple<Index, double, double, double>, Index> inserted;
  std::vector<std::vector<Index>> ids(curves.size());
  out.curves.resize(curves.size());
  for (std::size_t c = 0; c < curves.size(); ++c) {
    for (const GivenPoint& p : curves[c].points) {
      Index v = p.vertex;
      if (v == kInvalidIndex) {
        const auto key = std::make_tuple(p.face, p.bary[0], p.bary[1], p.bary[2]);
        auto it = inserted.find(key);
        if (it == inserted.end()) {
          const Eigen::Vector3d w(p.bary[0], p.bary[1], p.bary[2]);
          const intrinsic::SurfacePoint sp =
              intrinsic::given_face_point(st.input(), in.triangles, input_face, p.face, w, p.token);
          const Index before = st.intrinsic().n_vertices();
          const Index added = intrinsic::insert_surface_point(st, sp);
          it = inserted.emplace(key, added).first;
          out.inserted.push_back(
              {p.token, added, added < before, st.position(st.vertex_location(added))});
        }
        v = it->second;
      }
      ids[c].push_back(v);
      out.curves[c].points.push_back(st.position(st.vertex_location(v)));
    }
  }
  return ids;
}

// Lengths and traces of the shortened curves (tracing flips nothing: any order is fine).
void trace_curves(const SignpostTriangulation& st, const std::vector<EdgePath>& paths,
                  GeodesicCurves& run) {
  std::vector<char> collapsed(paths.size(), 0);
  for (const Index c : run.report.collapsed_loops) collapsed[static_cast<std::size_t>(c)] = 1;
  for (std::size_t c = 0; c < paths.size(); ++c) {
    GeodesicCurve& r = run.curves[c];
    r.closed = paths[c].closed;
    r.collapsed = collapsed[c] != 0;
    r.length = intrinsic::path_length(st.intrinsic(), paths[c]);
    if (!paths[c].steps.empty()) r.polyline = intrinsic::path_polyline(st, paths[c]);
  }
}

// The exact shortest path between the two points of a path, traced before FlipOut flips
// anything (the exact distance's faces are then the input's, split at inserted points: flat).
struct ExactPair {
  double length = std::numeric_limits<double>::infinity();
  std::vector<Eigen::Vector3d> polyline;  // from the path's first point to its last
};

// Points of st.intrinsic() (unflipped: every face lies in one input face) in 3D.
std::vector<Eigen::Vector3d> unflipped_polyline(const SignpostTriangulation& st,
                                                const std::vector<intrinsic::SurfacePoint>& pts) {
  return solvers::path_points_3d(st.intrinsic(), pts, [&](Index v) -> Eigen::Vector3d {
    return st.position(st.vertex_location(v));
  });
}

// The curves shortened as options.start says (GeodesicOptions::start): one open path between
// two points by intrinsic::shortest_geodesic, other curves together from Dijkstra edge paths.
// With the exact distance to the path's end, *exact gets the exact path.
intrinsic::FlipOutReport shorten_curves(SignpostTriangulation& st, const io::SurfaceInput& input,
                                        const std::vector<intrinsic::CurveThrough>& through,
                                        const GeodesicOptions& options,
                                        std::vector<EdgePath>* paths, std::vector<double>* initial,
                                        double* seconds_guide, std::string* won, ExactPair* exact) {
  const intrinsic::CurveThrough& c = through[0];
  intrinsic::FlipOutReport report;
  if (options.start != intrinsic::StartPath::kDijkstra && through.size() == 1 && !c.closed &&
      c.vertices.size() == 2) {
    StartGuide guide(input);
    intrinsic::ShortestGeodesicOptions o;
    o.start = options.start;
    o.flipout = options.flipout;
    paths->assign(1, EdgePath{});
    const Index a = c.vertices[0], b = c.vertices[1];
    try {
      const std::vector<intrinsic::ExactDistance> to_b = guide.exact_to_each(st, {b});
      if (!to_b.empty()) {  // the exact geodesics' strips (D-200); to a only when needed (D-206)
        if (std::isfinite(to_b[0].distance[a])) {  // (else shortest_geodesic refuses)
          exact->length = to_b[0].distance[a];
          exact->polyline = unflipped_polyline(st, to_b[0].path_to_source(a));
        }
        std::vector<intrinsic::ExactDistance> to_a;
        const auto lazy_to_a = [&]() -> const intrinsic::ExactDistance* {
          to_a = guide.exact_to_each(st, {a});
          return to_a.empty() ? nullptr : &to_a[0];
        };
        report = intrinsic::shortest_geodesic(st, a, b, to_b[0], lazy_to_a, o, &(*paths)[0], won);
      } else {
        const Eigen::MatrixXd phi = guide.to_each(st, {b, a});
        const Eigen::VectorXd heat_to_b = phi.col(0), heat_to_a = phi.col(1);
        report =
            intrinsic::shortest_geodesic(st, a, b, &heat_to_b, &heat_to_a, o, &(*paths)[0], won);
      }
    } catch (const InvalidInput& e) {
      throw InvalidInput(c.name + ": " + e.what());
    }
    initial->assign(1, report.initial_length);
    *seconds_guide = guide.seconds;
  } else {
    report = intrinsic::shorten_through(st, through, paths, initial, options.flipout);
  }
  return report;
}

}  // namespace

StartGuide::StartGuide(const io::SurfaceInput& input) : input_(input) {}
StartGuide::~StartGuide() = default;

Eigen::VectorXd StartGuide::to(const SignpostTriangulation& st, Index target) {
  return to_each(st, {target}).col(0);
}

Eigen::MatrixXd StartGuide::to_each(const SignpostTriangulation& st,
                                    const std::vector<Index>& targets) {
  Stopwatch watch;
  const Index nv = static_cast<Index>(input_.positions.rows());
  const std::vector<intrinsic::ExactDistance> exact = exact_to_each(st, targets);
  if (!exact.empty()) {
    Eigen::MatrixXd phi(st.intrinsic().n_vertices(), Eigen::Index(targets.size()));
    for (std::size_t k = 0; k < targets.size(); ++k) phi.col(Eigen::Index(k)) = exact[k].distance;
    return phi;
  }
  if (!solver_) build();
  std::vector<Index> sources;
  for (const Index target : targets) {
    Index source = target;
    if (source >= nv) {  // an inserted point: its input face's nearest corner
      const intrinsic::SurfacePoint& p = st.vertex_location(target);
      Eigen::Index k = 0;
      p.bary.maxCoeff(&k);
      source = st.input().tail(3 * p.face + k);
    }
    sources.push_back(source);
  }
  const Eigen::MatrixXd d =
      solvers::on_input_vertices(*surface_, solver_->compute_distances(sources));
  const intrinsic::IntrinsicTriangulation& tri = st.intrinsic();
  Eigen::MatrixXd phi(tri.n_vertices(), d.cols());
  phi.topRows(nv) = d;
  for (Index v = nv; v < tri.n_vertices(); ++v) {
    const intrinsic::SurfacePoint& p = st.vertex_location(v);
    phi.row(v).setZero();
    for (int i = 0; i < 3; ++i) phi.row(v) += p.bary[i] * d.row(st.input().tail(3 * p.face + i));
  }
  seconds += watch.seconds();
  return phi;
}

std::vector<intrinsic::ExactDistance> StartGuide::exact_to_each(const SignpostTriangulation& st,
                                                                const std::vector<Index>& targets) {
  if (exact_refused_) return {};
  Stopwatch watch;
  std::vector<intrinsic::ExactDistance> out;
  try {
    for (const Index target : targets) {
      out.push_back(intrinsic::exact_distance(st.intrinsic(), std::vector<Index>{target}));
    }
  } catch (const InvalidInput&) {  // over the memory budget: the heat method's guide
    exact_refused_ = true;
    out.clear();
  }
  seconds += watch.seconds();
  return out;
}

void StartGuide::build() {
  solvers::PrepareOptions o;
  if (input_.positions.rows() <= kRefinedGuideMaxVertices) {
    o.refine = solvers::accurate_distance_refinement();
  }
  try {
    surface_ = std::make_unique<solvers::PreparedSurface>(solvers::prepare_surface(input_, o));
  } catch (const Error&) {  // refinement refused: the guide needs no accuracy guarantee
    o.refine.reset();
    surface_ = std::make_unique<solvers::PreparedSurface>(solvers::prepare_surface(input_, o));
  }
  solver_ = std::make_unique<solvers::HeatDistanceSolver>(surface_->tri,
                                                          solvers::distance_options(*surface_));
}

void GeodesicOptions::validate() const {
  if (!(mollify_relative_epsilon >= 0.0 && mollify_relative_epsilon <= 1.0)) {
    throw InvalidInput(
        "GeodesicOptions::mollify_relative_epsilon must be in [0, 1] (relative to the mean "
        "edge length), got " +
        std::to_string(mollify_relative_epsilon));
  }
  if (bezier_rounds && (*bezier_rounds < 0 || *bezier_rounds > kMaxBezierRounds)) {
    throw InvalidInput("GeodesicOptions::bezier_rounds must be in [0, " +
                       std::to_string(kMaxBezierRounds) + "], got " +
                       std::to_string(*bezier_rounds));
  }
  if (!(max_memory_bytes >= 0.0)) {
    throw InvalidInput("GeodesicOptions::max_memory_bytes must be ≥ 0 (0: automatic), got " +
                       std::to_string(max_memory_bytes));
  }
  flipout.validate();
}

std::string point_problem(const GivenPoint& p, const io::SurfaceInput& input) {
  const Index nv = static_cast<Index>(input.positions.rows());
  const Index nf = static_cast<Index>(input.triangles.size());
  if (p.vertex != kInvalidIndex) {
    if (p.vertex >= 0 && p.vertex < nv) return "";
    return "vertex " + std::to_string(p.vertex) + " out of range " + range(nv) +
           " (the input has " + std::to_string(nv) + " vertices)";
  }
  if (input.n_non_triangles > 0) {
    return p.token + ": face points need a triangle mesh (the file has " +
           std::to_string(input.n_non_triangles) + " faces with more than 3 corners)";
  }
  if (p.face < 0 || p.face >= nf) {
    return p.token + ": face " + std::to_string(p.face) + " out of range " + range(nf) +
           " (the input has " + std::to_string(nf) + " faces)";
  }
  double sum = 0.0;
  for (const double b : p.bary) {
    if (!(std::isfinite(b) && b >= 0.0)) {
      return p.token + ": barycentric coordinates must be finite and ≥ 0";
    }
    sum += b;
  }
  if (std::abs(sum - 1.0) > 1e-9) return p.token + ": barycentric coordinates must sum to 1";
  return "";
}

void check_curves(const std::vector<GivenCurve>& curves, const io::SurfaceInput& input) {
  if (curves.empty()) throw InvalidInput("geodesic: no curves given");
  std::vector<char> on_a_face(static_cast<std::size_t>(input.positions.rows()), 0);
  for (const Triangle& t : input.triangles) {
    for (const Index v : t) on_a_face[static_cast<std::size_t>(v)] = 1;
  }
  for (const GivenCurve& c : curves) {
    if (c.points.size() < 2) {
      throw InvalidInput(c.origin + ": needs at least two points, got " +
                         std::to_string(c.points.size()));
    }
    for (const GivenPoint& p : c.points) {
      const std::string problem = point_problem(p, input);
      if (!problem.empty()) throw InvalidInput(c.origin + ": " + problem);
      // (no faces at all: a point cloud, refused later as such)
      if (p.vertex != kInvalidIndex && !input.triangles.empty() &&
          !on_a_face[static_cast<std::size_t>(p.vertex)]) {
        throw InvalidInput(c.origin + ": vertex " + std::to_string(p.vertex) +
                           " is used by no face (an isolated vertex, not on the surface)");
      }
    }
    const std::string repeated = repeated_point(c);
    if (!repeated.empty()) throw InvalidInput(c.origin + ": " + repeated);
  }
}

namespace {

// ===== Nonmanifold / non-orientable inputs: the exact distance on the tufted cover =====

// The input's tufted cover on its own faces (not flipped, not refined): the surface
// `ifem distance --exact` measures on such a mesh; each cover face copies an input face.
solvers::PreparedSurface tufted_surface(const io::SurfaceInput& in, double mollify) {
  solvers::PrepareOptions o;
  o.mollify_relative_epsilon = mollify;
  o.intrinsic_delaunay = false;
  o.force_tufted = true;
  return solvers::prepare_surface(in, o);
}

// The reason in a NonManifoldInput of the signposts (after "this mesh is not: ").
std::string nonmanifold_reason(const NonManifoldInput& e) {
  std::string why = e.what();
  const std::string mark = "this mesh is not: ";
  const std::size_t at = why.find(mark);
  return at == std::string::npos ? why : why.substr(at + mark.size());
}

// A given point on the cover: a vertex, or its place in each cover copy of its face.
struct CoverPoint {
  Index vertex = kInvalidIndex;
  Index given_face = kInvalidIndex;
  std::vector<intrinsic::SurfacePoint> copies;  // in cover faces (front and back copy)
  bool interior = false;                        // every barycentric coordinate > the snap
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
};

constexpr double kCoverSnap = 1e-9;  // as insert_surface_point()'s snap to a corner / a side

CoverPoint cover_point(const solvers::PreparedSurface& s, const GivenPoint& p,
                       const std::vector<std::vector<Index>>& copies_of) {
  CoverPoint c;
  const auto& x = s.input.positions;
  if (p.vertex != kInvalidIndex) {
    c.vertex = p.vertex;
    c.position = x.row(p.vertex).transpose();
    return c;
  }
  const Triangle& t = s.input.triangles[static_cast<std::size_t>(p.face)];
  for (int j = 0; j < 3; ++j) c.position += p.bary[j] * x.row(t[j]).transpose();
  for (int j = 0; j < 3; ++j) {
    if (p.bary[j] >= 1.0 - kCoverSnap) {
      c.vertex = t[j];
      c.position = x.row(t[j]).transpose();
      return c;
    }
  }
  const std::vector<Index>& faces = copies_of[static_cast<std::size_t>(p.face)];
  if (faces.empty()) {
    throw InvalidInput(p.token + ": face " + std::to_string(p.face) +
                       " repeats a vertex (dropped from the surface)");
  }
  c.given_face = p.face;
  c.interior = std::min({p.bary[0], p.bary[1], p.bary[2]}) > kCoverSnap;
  for (const Index f : faces) {
    intrinsic::SurfacePoint sp;
    sp.face = f;
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) {
        if (s.tri.tail(3 * f + i) == t[j]) sp.bary[i] = p.bary[j];
      }
    }
    c.copies.push_back(sp);
  }
  return c;
}

// Refuses what needs FlipOut on a mesh the signposts refuse (anything but one open curve
// through two points), saying what does run there.
void refuse_without_signposts(const std::vector<GivenCurve>& curves, const GeodesicOptions& options,
                              const NonManifoldInput& e) {
  if (!options.bezier_rounds && curves.size() == 1 && !curves[0].closed &&
      curves[0].points.size() == 2) {
    return;
  }
  const std::string what = options.bezier_rounds ? "a Bézier curve"
                           : curves.size() > 1   ? "a network of curves"
                           : curves[0].closed    ? "a loop"
                                                 : "a path through more than two points";
  throw NonManifoldInput(
      "geodesic: " + what +
      " needs FlipOut, whose signposts need an edge-manifold, orientable surface, and this "
      "mesh is not: " +
      nonmanifold_reason(e) +
      ". On such a mesh a path between two points (--path A,B) and single-source geodesics "
      "(--all-from S) run: exact shortest paths on its tufted cover");
}

// The cover edges under a face point on a side of its face (one per copy; a zipped boundary
// side is one edge for both), each with the fraction of the way from vertex `from`.
struct CoverSide {
  Index edge = kInvalidIndex, from = kInvalidIndex;
  double t = 0.0;
};

std::vector<CoverSide> cover_sides(const intrinsic::IntrinsicTriangulation& tri,
                                   const CoverPoint& p) {
  std::vector<CoverSide> sides;
  for (const intrinsic::SurfacePoint& sp : p.copies) {
    Eigen::Index k = 0;
    sp.bary.minCoeff(&k);  // the corner opposite the side
    const Index h = 3 * sp.face + Index((k + 1) % 3);
    const double wa = sp.bary[(k + 1) % 3], wb = sp.bary[(k + 2) % 3];
    const CoverSide side{tri.edge(h), tri.tail(h), wb / (wa + wb)};
    bool seen = false;
    for (const CoverSide& o : sides) seen = seen || o.edge == side.edge;
    if (!seen) sides.push_back(side);
  }
  return sides;
}

// True when splitting p's cover edges would rewrite a face that q's copies lie in.
bool split_touches(const intrinsic::IntrinsicTriangulation& tri, const CoverPoint& p,
                   const CoverPoint& q) {
  for (const CoverSide& side : cover_sides(tri, p)) {
    const Index h = tri.edge_halfedge(side.edge), t = tri.twin(h);
    for (const intrinsic::SurfacePoint& sp : q.copies) {
      if (tri.face(h) == sp.face || (t != kInvalidIndex && tri.face(t) == sp.face)) return true;
    }
  }
  return false;
}

// The exact shortest path on the cover between two points not in one face: the exact distance
// from one end (`source`), path_to_source() from the other (`target`: a vertex, or a face point
// inserted into both cover copies of its face, or split into the cover edges under it when on
// a side; the shortest path). Fills out.polyline (from `target` to `source`) and out.length;
// returns the windows.
std::size_t cover_path(solvers::PreparedSurface& s, const CoverPoint& source,
                       const CoverPoint& target, const GivenCurve& curve,
                       const GeodesicOptions& options, GeodesicCurve& out) {
  intrinsic::IntrinsicTriangulation& tri = s.tri;
  const Index nv = tri.n_vertices();
  std::vector<Index> ends;
  if (target.vertex != kInvalidIndex) {
    ends.push_back(target.vertex);
  } else if (target.interior) {
    for (const intrinsic::SurfacePoint& sp : target.copies) {
      ends.push_back(tri.insert_vertex_in_face(sp.face, sp.bary));
    }
  } else {
    for (const CoverSide& side : cover_sides(tri, target)) {
      if (!tri.can_split_edge(side.edge)) {
        throw InvalidInput(curve.origin +
                           ": the cover edge under a face point on a side is "
                           "glued to itself (give the point as a vertex or inside a face)");
      }
      const bool along = tri.tail(tri.edge_halfedge(side.edge)) == side.from;
      ends.push_back(tri.split_edge(side.edge, along ? side.t : 1.0 - side.t));
    }
  }
  intrinsic::ExactDistanceOptions eo;
  eo.max_memory_bytes = options.max_memory_bytes;
  intrinsic::ExactDistance d;
  try {
    d = source.vertex != kInvalidIndex
            ? intrinsic::exact_distance(tri, std::vector<Index>{source.vertex}, eo)
            : intrinsic::exact_distance(tri, source.copies, eo);
  } catch (const InvalidInput& e) {  // the points are valid: only the budget throws
    throw InvalidInput(curve.origin + ": " + e.what() +
                       " (on a nonmanifold mesh a path between two points is the exact "
                       "distance's, on the tufted cover: no heat-method alternative)");
  }
  Index end = ends[0];
  for (const Index v : ends) {
    if (d.distance[v] < d.distance[end]) end = v;
  }
  if (!std::isfinite(d.distance[end])) {
    throw InvalidInput(curve.origin + ": " + curve.points[0].token + " and " +
                       curve.points[1].token + " lie on different components (no path)");
  }
  const auto& x = s.input.positions;
  out.polyline = solvers::path_points_3d(  // target → source
      tri, d.path_to_source(end), [&](Index v) -> Eigen::Vector3d {
        return v < nv ? Eigen::Vector3d(x.row(v).transpose()) : target.position;
      });
  out.length = d.distance[end];
  return d.windows;
}

// One open path between two points on a mesh the signposts refuse: the exact shortest path on
// the tufted cover (cover_path; straight within one face). Anything else is refused with what
// does run on such a mesh.
GeodesicCurves tufted_cover_path(const io::SurfaceInput& input,
                                 const std::vector<GivenCurve>& curves,
                                 const GeodesicOptions& options, const NonManifoldInput& e) {
  refuse_without_signposts(curves, options, e);
  GeodesicCurves run;
  Stopwatch watch;
  solvers::PreparedSurface s = tufted_surface(input, options.mollify_relative_epsilon);
  run.seconds_signposts = watch.restart();
  std::vector<std::vector<Index>> copies_of(input.triangles.size());
  for (std::size_t f = 0; f < s.tufted.parent_face.size(); ++f) {
    copies_of[static_cast<std::size_t>(s.tufted.parent_face[f])].push_back(static_cast<Index>(f));
  }
  const GivenCurve& curve = curves[0];
  const CoverPoint a = cover_point(s, curve.points[0], copies_of);
  const CoverPoint b = cover_point(s, curve.points[1], copies_of);
  run.tufted_cover = true;
  run.start_won = "exact path (tufted cover)";
  run.curves.resize(1);
  GeodesicCurve& out = run.curves[0];
  out.points = {a.position, b.position};
  const std::string pair =
      curve.origin + ": " + curve.points[0].token + " and " + curve.points[1].token;
  if (a.vertex == b.vertex && a.vertex != kInvalidIndex) {
    throw InvalidInput(pair + " are the same point");
  }
  // The traced end: a vertex, else a face point inside its face, else one on a side whose
  // split leaves the other's faces alone. Both on sides, each splitting the other's faces:
  // they lie on one input face's sides (with its duplicates), joined straight as in one face.
  const bool sides =
      a.vertex == kInvalidIndex && b.vertex == kInvalidIndex && !a.interior && !b.interior;
  const bool b_touches = sides && split_touches(s.tri, b, a);
  if ((a.vertex == kInvalidIndex && a.given_face == b.given_face) ||
      (b_touches && split_touches(s.tri, a, b))) {  // one flat face: straight
    out.polyline = {a.position, b.position};
    out.length = (a.position - b.position).norm();
  } else {
    const bool from_b = b.vertex == kInvalidIndex &&
                        (a.vertex != kInvalidIndex || (!b.interior && a.interior) || b_touches);
    const CoverPoint& target = from_b ? a : b;
    run.windows = cover_path(s, from_b ? b : a, target, curve, options, out);
    if (!from_b) std::reverse(out.polyline.begin(), out.polyline.end());  // from a to b
  }
  out.initial_length = out.length;
  run.report.initial_length = run.report.final_length = out.length;
  run.report.lengths = {out.length};
  run.seconds_flipout = watch.seconds();
  return run;
}

}  // namespace

GeodesicCurves geodesic(const io::SurfaceInput& input, const std::vector<GivenCurve>& curves,
                        const GeodesicOptions& options) {
  options.validate();
  check_curves(curves, input);
  if (options.bezier_rounds && (curves.size() != 1 || curves[0].closed)) {
    throw InvalidInput("geodesic: a Bézier curve takes one open curve's points as control points");
  }
  GeodesicCurves run;
  ExactPair exact;
  Stopwatch watch;
  std::optional<SignpostTriangulation> built;
  try {
    built.emplace(signposts(input, options.mollify_relative_epsilon));
  } catch (const NonManifoldInput& e) {
    return tufted_cover_path(input, curves, options, e);
  }
  SignpostTriangulation& st = *built;
  run.seconds_signposts = watch.restart();
  const std::vector<std::vector<Index>> ids = insert_points(st, input, curves, run);
  std::vector<EdgePath> paths;
  if (options.bezier_rounds) {
    intrinsic::CurveSpec spec{ids[0], intrinsic::CurveShape::kBezier, *options.bezier_rounds};
    try {
      intrinsic::check_curve_budget(st.intrinsic(), {spec}, options.max_memory_bytes);
    } catch (const InvalidInput& e) {  // "curve 0: ..." → the curve as given
      throw InvalidInput(curves[0].origin +
                         std::string(e.what()).substr(std::string("curve 0").size()));
    }
    intrinsic::BezierCurve b =
        intrinsic::bezier_curve(st, ids[0], *options.bezier_rounds, options.flipout);
    run.report = b.report;
    run.curves[0].initial_length = b.report.initial_length;
    run.bezier_control_points = static_cast<Index>(b.controls.size());
    run.bezier_midpoints = b.inserted_vertices;
    paths.push_back(std::move(b.path));
  } else {
    std::vector<intrinsic::CurveThrough> through;
    for (std::size_t c = 0; c < curves.size(); ++c) {
      through.push_back({ids[c], curves[c].closed, curves[c].pin, curves[c].origin});
    }
    std::vector<double> initial;
    run.report = shorten_curves(st, input, through, options, &paths, &initial, &run.seconds_guide,
                                &run.start_won, &exact);
    for (std::size_t c = 0; c < curves.size(); ++c) run.curves[c].initial_length = initial[c];
  }
  if (run.report.stopped_by == intrinsic::FlipOutStop::kIterationCap && !options.accept_partial) {
    throw InvalidInput(intrinsic::iteration_cap_message(
        run.report, "GeodesicOptions::accept_partial, `--accept-partial` in the CLI"));
  }
  trace_curves(st, paths, run);
  // FlipOut keeps its start's class around saddle vertices (D-150, D-375): a kept geodesic
  // longer than the exact distance gives way to the exact path.
  if (run.curves.size() == 1 && std::isfinite(exact.length) &&
      run.curves[0].length > exact.length * (1.0 + kExactPairTolerance)) {
    char excess[64];
    std::snprintf(excess, sizeof excess, "%.2e", run.curves[0].length / exact.length - 1.0);
    run.start_won =
        "exact path (FlipOut's geodesic from " + run.start_won + " was " + excess + " longer)";
    run.curves[0].polyline = std::move(exact.polyline);
    run.curves[0].length = exact.length;
  }
  run.seconds_flipout = watch.seconds();
  return run;
}

namespace {

// Single-source geodesics from the exact distance on st's triangulation as built (its faces are
// the input's, so each path point's position is its barycentric mix of the corners). False when
// the windows exceed the memory budget.
bool exact_single_source(const SignpostTriangulation& st, const io::SurfaceInput& input,
                         Index source, const GeodesicOptions& options, SingleSourceResult& r) {
  intrinsic::ExactDistanceOptions eo;
  eo.max_memory_bytes = options.max_memory_bytes;
  eo.keep_paths = options.trace_paths;
  const intrinsic::IntrinsicTriangulation& tri = st.intrinsic();
  if (tri.vertex_halfedge(source) == kInvalidIndex) return false;  // FlipOut's message
  if (options.on_progress) options.on_progress(0.0, "single-source geodesics");
  intrinsic::ExactDistance d;
  try {
    d = intrinsic::exact_distance(tri, std::vector<Index>{source}, eo);
  } catch (const InvalidInput&) {  // the source is valid: only the budget throws
    return false;
  }
  const Index nv = static_cast<Index>(input.positions.rows());
  r.exact = true;
  r.windows = d.windows;
  r.length = d.distance.head(nv);
  if (options.on_progress) options.on_progress(1.0, "single-source geodesics");
  for (Index v = 0; options.trace_paths && v < nv; ++v) {
    std::vector<Eigen::Vector3d> line = solvers::path_points_3d(
        tri, d.path_to_source(v),
        [&](Index u) -> Eigen::Vector3d { return input.positions.row(u).transpose(); });
    std::reverse(line.begin(), line.end());  // from the source
    r.paths.push_back(std::move(line));
  }
  return true;
}

// A source vertex no face of tri uses is refused (as exact_distance() refuses it).
void refuse_isolated_source(const intrinsic::IntrinsicTriangulation& tri, Index source) {
  if (tri.vertex_halfedge(source) == kInvalidIndex) {
    throw InvalidInput("source = " + std::to_string(source) +
                       ": vertex used by no face (an isolated vertex, not on the surface)");
  }
}

// Single-source geodesics on a mesh the signposts refuse: the exact distance on the tufted
// cover (as `ifem distance --exact`), paths placed on the input's faces (exact_paths_3d).
SingleSourceResult tufted_single_source(const io::SurfaceInput& input, Index source,
                                        const GeodesicOptions& options) {
  const solvers::PreparedSurface s = tufted_surface(input, options.mollify_relative_epsilon);
  refuse_isolated_source(s.tri, source);
  const Stopwatch watch;
  if (options.on_progress) options.on_progress(0.0, "single-source geodesics");
  intrinsic::ExactDistanceOptions eo;
  eo.max_memory_bytes = options.max_memory_bytes;
  eo.keep_paths = options.trace_paths;
  intrinsic::ExactDistance full;
  SingleSourceResult r;
  r.length = solvers::exact_distance(s, {source}, eo, &full);
  r.exact = true;
  r.tufted_cover = true;
  r.windows = full.windows;
  if (options.trace_paths) {
    std::vector<Index> all(static_cast<std::size_t>(s.n_input_vertices()));
    for (std::size_t v = 0; v < all.size(); ++v) all[v] = static_cast<Index>(v);
    r.paths = solvers::exact_paths_3d(s, full, all);
    for (auto& line : r.paths) std::reverse(line.begin(), line.end());  // from the source
  }
  if (options.on_progress) options.on_progress(1.0, "single-source geodesics");
  r.seconds = watch.seconds();
  return r;
}

}  // namespace

SingleSourceResult geodesic(const io::SurfaceInput& input, Index source,
                            const GeodesicOptions& options) {
  options.validate();
  const Index nv = static_cast<Index>(input.positions.rows());
  if (source < 0 || source >= nv) {
    throw InvalidInput("source = " + std::to_string(source) + ": vertex out of range " + range(nv));
  }
  std::optional<SignpostTriangulation> built;
  try {
    built.emplace(signposts(input, options.mollify_relative_epsilon));
  } catch (const NonManifoldInput& e) {
    if (options.single_source_flipout) {
      throw NonManifoldInput(
          "single-source geodesics by FlipOut (GeodesicOptions::single_source_flipout, "
          "`--single-source-flipout`) need signposts, hence an edge-manifold, orientable "
          "surface, and this mesh is not: " +
          nonmanifold_reason(e) +
          ". Without it the exact distance runs on the mesh's tufted cover (shortest paths)");
    }
    return tufted_single_source(input, source, options);
  }
  SignpostTriangulation& st = *built;
  refuse_isolated_source(st.intrinsic(), source);
  const Stopwatch watch;
  SingleSourceResult r;
  if (!options.single_source_flipout && exact_single_source(st, input, source, options, r)) {
    r.seconds = watch.seconds();
    return r;
  }
  const intrinsic::SingleSourceGeodesics g =
      intrinsic::single_source_geodesics(st, source, {}, options.on_progress);
  r.seconds = watch.seconds();
  r.length = g.length.head(nv);
  r.flips = g.flips;
  r.iterations = g.iterations;
  r.blocked = g.blocked;
  for (Index v = 0; options.trace_paths && v < nv; ++v) {
    const EdgePath& p = g.paths[static_cast<std::size_t>(v)];
    if (!p.steps.empty()) {
      r.paths.push_back(intrinsic::path_polyline(st, p));
    } else if (v == source) {
      r.paths.push_back({st.position(st.vertex_location(v))});
    } else {
      r.paths.emplace_back();
    }
  }
  return r;
}

}  // namespace ifem::recipes
