#include "solvers/recipes/curves.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <optional>
#include <sstream>
#include <utility>

#include "intrinsic/core/errors.h"
#include "intrinsic/core/timer.h"
#include "intrinsic/core/triangle_formulas.h"
#include "intrinsic/core/union_find.h"
#include "intrinsic/integer/replay.h"

namespace ifem::solvers {
namespace {

using T = intrinsic::IntrinsicTriangulation;

void report(const CurveSurfaceOptions& o, const std::string& line) {
  if (o.progress) o.progress(line);
}

intrinsic::CurveSpec to_spec(const CurveCondition& c) {
  intrinsic::CurveSpec s;
  s.vertices = c.vertices;
  s.shape = c.shape;
  s.bezier_rounds = c.bezier_rounds;
  return s;
}

// A library message names curves by index ("curve 3"); for people, name them by where they were
// given ("curve at file:line") when known. Only the message changes, never a decision.
std::string with_origins(const std::string& what, const std::vector<CurveCondition>& curves) {
  std::string m = what;
  for (std::size_t i = curves.size(); i-- > 0;) {
    const std::string key = "curve " + std::to_string(i);
    for (std::size_t at = m.find(key); at != std::string::npos; at = m.find(key, at + 1)) {
      const std::size_t end = at + key.size();
      if (end < m.size() && std::isdigit(static_cast<unsigned char>(m[end]))) continue;
      if (!curves[i].origin.empty()) m.replace(at, key.size(), "curve at " + curves[i].origin);
      break;
    }
  }
  return m;
}

// The value of data `vals` (1 value, or one per control point, wrapping for a loop) at arc
// length s, linear in arc length between the control points' arc lengths `ctrl`.
double value_at(const std::vector<double>& vals, const std::vector<double>& ctrl, double s) {
  if (vals.size() == 1 || ctrl.size() < 2) return vals.front();
  // the first piece [ctrl[i], ctrl[i+1]] with ctrl[i+1] ≥ s (the last one beyond it)
  const auto it = std::lower_bound(ctrl.begin() + 1, ctrl.end() - 1, s);
  const std::size_t i = static_cast<std::size_t>(it - (ctrl.begin() + 1));
  const double a = vals[i % vals.size()], b = vals[(i + 1) % vals.size()];
  const double span = ctrl[i + 1] - ctrl[i];
  const double t = span > 0.0 ? std::clamp((s - ctrl[i]) / span, 0.0, 1.0) : 0.0;
  return t >= 1.0 ? b : a + t * (b - a);
}

// The triangulation cut open along the slits: every vertex whose corners fall apart into
// several fans once the slit edges are unglued gets one copy per fan (the first keeps its id,
// the others are appended; origin maps copies back).
struct CutOpen {
  const T* base = nullptr;  // the uncut triangulation
  std::optional<T> owned;   // the cut one, when something was cut apart
  const T& tri() const { return owned ? *owned : *base; }  // no copy when nothing was
  std::vector<Index> corner_vertex;  // #H: the (possibly copied) vertex at each corner
  std::vector<Index> origin;         // #V of tri: the vertex of the uncut triangulation
  Index copies = 0;
};

CutOpen cut_open(const T& base, const std::vector<char>& cut) {
  const Index nh = base.n_halfedges(), nv = base.n_vertices();
  CutOpen out;
  out.base = &base;
  out.origin.resize(nv);
  for (Index v = 0; v < nv; ++v) out.origin[v] = v;
  if (std::find(cut.begin(), cut.end(), 1) == cut.end()) {  // no slit: no copy, no search
    out.corner_vertex = base.tails();
    return out;
  }
  auto is_cut = [&](Index h) { return cut[base.edge(h)] != 0; };
  UnionFind corners(nh);
  for (Index h = 0; h < nh; ++h) {
    const Index t = base.twin(h);
    if (t == kInvalidIndex || is_cut(h)) continue;
    corners.unite(h, T::next(t));
    corners.unite(T::next(h), t);
  }
  std::vector<Index> id(nh, kInvalidIndex);
  std::vector<char> taken(nv, 0);
  out.corner_vertex.resize(nh);
  std::vector<Index> twin(nh);
  std::vector<double> length(nh);
  for (Index h = 0; h < nh; ++h) {
    const Index r = corners.find(h), v = base.tail(h);
    if (id[r] == kInvalidIndex) {
      id[r] = taken[v] ? static_cast<Index>(out.origin.size()) : v;
      if (taken[v]) out.origin.push_back(v), ++out.copies;
      taken[v] = 1;
    }
    out.corner_vertex[h] = id[r];
    twin[h] = is_cut(h) ? kInvalidIndex : base.twin(h);
    length[h] = base.halfedge_length(h);
  }
  if (out.copies == 0) return out;
  out.owned = T::from_gluing(out.corner_vertex, std::move(twin), length,
                             static_cast<Index>(out.origin.size()));
  return out;
}

// Dirichlet values gathered per vertex of the cut triangulation: every curve puts its value (per
// side) on the corners next to its edges; a value a curve gives a vertex several times (both
// sides, both edges at it) counts once, and vertices that get different values take the mean of
// them (a slit's tip: of its two sides; curves meeting: of their values).
struct CurveValues {
  struct Entry {
    Index vertex, curve;
    double value;
    bool operator<(const Entry& o) const {
      return vertex != o.vertex ? vertex < o.vertex
             : curve != o.curve ? curve < o.curve
                                : value < o.value;
    }
    bool operator==(const Entry& o) const {
      return vertex == o.vertex && curve == o.curve && value == o.value;
    }
  };
  std::vector<Entry> entries;
  std::vector<double> sum, lo, hi;
  std::vector<int> count;
  explicit CurveValues(Index n) : sum(n, 0.0), lo(n, 0.0), hi(n, 0.0), count(n, 0) {}
  void add(Index v, Index curve, double x) { entries.push_back({v, curve, x}); }
  // sums the distinct entries per vertex
  void finish() {
    std::sort(entries.begin(), entries.end());
    entries.erase(std::unique(entries.begin(), entries.end()), entries.end());
    for (const Entry& e : entries) {
      const Index v = e.vertex;
      lo[v] = count[v] ? std::min(lo[v], e.value) : e.value;
      hi[v] = count[v] ? std::max(hi[v], e.value) : e.value;
      sum[v] += e.value;
      ++count[v];
    }
  }
};

void gather_curve_values(const CurveSurface& s, const CutOpen& cut, CurveValues& cv) {
  const T& base = s.surface.tri;
  for (Index c = 0; c < s.network.n_curves(); ++c) {
    const CurveCondition& cc = s.curves[c];
    const std::vector<double>& ctrl = s.network.control_arclength[c];
    const std::vector<double>& right = cc.slit ? cc.right_values : cc.values;
    const intrinsic::CurveChain ch = intrinsic::curve_chain(base, s.network, c);
    for (std::size_t i = 0; i < ch.edges.size(); ++i) {
      const Index hl = ch.left_halfedges[i];
      const Index h0 = base.edge_halfedge(ch.edges[i]);
      const Index hr = hl == kInvalidIndex ? h0 : base.twin(hl);
      const double a = ch.arclength[i], b = ch.arclength[i + 1];
      if (hl != kInvalidIndex) {  // left face: its corners at the step's tail and head
        cv.add(cut.corner_vertex[hl], c, value_at(cc.values, ctrl, a));
        cv.add(cut.corner_vertex[T::next(hl)], c, value_at(cc.values, ctrl, b));
      }
      if (hr != kInvalidIndex) {  // right face runs head → tail
        cv.add(cut.corner_vertex[hr], c, value_at(right, ctrl, b));
        cv.add(cut.corner_vertex[T::next(hr)], c, value_at(right, ctrl, a));
      }
    }
  }
}

// Curves whose insertion left triangles of zero area (cotan weights that are not finite) are
// refused here, named by origin: later the Laplacian would name internal edge ids.
void require_nondegenerate(const T& tri, const CurveSurface& out) {
  std::vector<Index> curve_at(tri.n_vertices(), kInvalidIndex);
  for (Index e = 0; e < tri.n_edges(); ++e) {
    const Index c = out.network.edges[e].curve;
    if (c == kInvalidIndex) continue;
    const Index h = tri.edge_halfedge(e);
    curve_at[tri.tail(h)] = curve_at[tri.head(h)] = c;
  }
  Index bad = 0, culprit = kInvalidIndex;
  for (Index f = 0; f < tri.n_faces(); ++f) {
    const double a = tri.halfedge_length(3 * f), b = tri.halfedge_length(3 * f + 1),
                 c = tri.halfedge_length(3 * f + 2);
    if (intrinsic::triangle_area(a, b, c) > 0.0) continue;
    Index on = kInvalidIndex;  // a curve through a corner (others are the input's own faces)
    for (int k = 0; k < 3 && on == kInvalidIndex; ++k) on = curve_at[tri.tail(3 * f + k)];
    if (on == kInvalidIndex) continue;
    ++bad;
    if (culprit == kInvalidIndex) culprit = on;
  }
  if (bad == 0) return;
  const std::string who = out.curves[culprit].origin.empty()
                              ? "curve " + std::to_string(culprit)
                              : "the curve at " + out.curves[culprit].origin;
  throw InvalidInput(who + " left " + std::to_string(bad) +
                     " triangles of zero area in the triangulation (points too close together "
                     "for the mesh's resolution); a Bézier curve with fewer rounds, other "
                     "vertices or a larger --mollify");
}

// Inserts the curves, flips to the constrained Delaunay triangulation and refines (constrained)
// when asked; fills out.network, out.surface.tri / signposts and the reports.
void build_constrained(const CurveSurfaceOptions& opt, CurveSurface& out) {
  PreparedSurface& s = out.surface;
  Stopwatch watch;
  intrinsic::SignpostTriangulation st(s.input.triangles, s.input.positions,
                                      opt.mollify_relative_epsilon);
  // integer coordinates: FlipOut runs on the signposts, its operations are replayed (D-260)
  const bool integer =
      opt.refine && opt.refine->correspondence == intrinsic::Correspondence::kInteger;
  if (integer) st.start_operation_log();
  std::vector<intrinsic::CurveSpec> specs;
  for (const CurveCondition& c : out.curves) specs.push_back(to_spec(c));
  s.seconds_build += watch.restart();  // the signposts; seconds_curves: FlipOut and marking
  try {
    out.network = intrinsic::insert_curves(st, specs, opt.flipout, opt.max_memory_bytes);
  } catch (const InvalidInput& e) {
    throw InvalidInput(with_origins(e.what(), out.curves));
  }
  const intrinsic::FlipOutReport& fo = out.network.flipout;
  out.seconds_curves = watch.restart();
  if (fo.stopped_by == intrinsic::FlipOutStop::kIterationCap && !opt.accept_partial) {
    throw InvalidInput(intrinsic::iteration_cap_message(
        fo, "CurveSurfaceOptions::accept_partial, `--accept-partial` in the CLI"));
  }
  std::ostringstream m;
  m << "curves: " << out.curves.size() << " inserted (" << fo.flips << " FlipOut flips, "
    << out.network.bezier_midpoints << " Bézier midpoints; " << intrinsic::to_string(fo.stopped_by)
    << (fo.blocked_joints ? ", " + std::to_string(fo.blocked_joints) + " bent joints left" : "")
    << ") in " << out.seconds_curves << " s";
  report(opt, m.str());
  out.constrained_flips = intrinsic::flip_to_constrained_delaunay(st, out.network);
  std::optional<intrinsic::NormalCoordinateTriangulation> nc;
  if (integer) nc.emplace(intrinsic::replay_on_integer(st)), st.end_operation_log();
  s.seconds_flip = watch.restart();
  report(opt, "constrained Delaunay: " + std::to_string(out.constrained_flips.flips) + " flips");
  if (opt.refine) {
    s.target_edge_length = opt.refine->resolution * s.input_mean_edge_length;
    intrinsic::EdgeConstraints ec = out.network.constraints(nc ? nc->intrinsic() : st.intrinsic());
    intrinsic::RefineOptions ro = refine_options(*opt.refine, s.target_edge_length);
    ro.on_progress = opt.on_progress;
    s.refine_report =
        nc ? intrinsic::delaunay_refine(*nc, ro, &ec) : intrinsic::delaunay_refine(st, ro, &ec);
    s.refined = true;
    s.seconds_refine = watch.restart();
    report(opt, describe(s.refine_report) + " in " + std::to_string(s.seconds_refine) + " s");
  }
  const T& tri = nc ? nc->intrinsic() : st.intrinsic();
  const std::size_t ne = static_cast<std::size_t>(tri.n_edges());
  out.network.constrained.resize(ne, 0);
  out.network.edges.resize(ne);
  out.signs = intrinsic::cotan_signs(tri, out.network.constrained);
  require_nondegenerate(tri, out);
  s.tri = tri;
  if (nc) {
    s.integer = std::move(*nc);
  } else {
    s.signposts = std::move(st);
  }
}

}  // namespace

void CurveSurfaceOptions::validate() const {
  if (!(mollify_relative_epsilon >= 0.0 && std::isfinite(mollify_relative_epsilon))) {
    throw InvalidInput(
        "CurveSurfaceOptions: mollify_relative_epsilon must be finite and ≥ 0, got " +
        std::to_string(mollify_relative_epsilon));
  }
  if (!(max_memory_bytes >= 0.0)) {
    throw InvalidInput("CurveSurfaceOptions: max_memory_bytes must be ≥ 0 (0: automatic), got " +
                       std::to_string(max_memory_bytes));
  }
  flipout.validate();
  if (refine) refine->validate();
}

CurveSurface prepare_curve_surface(io::SurfaceInput input, std::vector<CurveCondition> curves,
                                   const CurveSurfaceOptions& options) {
  options.validate();
  if (options.refine) {
    options.refine->validate();
    if (options.refine->relax_iterations > 0) {
      throw InvalidInput(
          "curves: relaxation is not offered with curves (it would move vertices off them)");
    }
  }
  if (!input.has_faces()) {
    throw InvalidInput("curves need a triangle mesh: this input has no faces (a point cloud)");
  }
  validate_curves(curves, static_cast<Index>(input.positions.rows()), false);
  PrepareOptions po;
  po.mollify_relative_epsilon = options.mollify_relative_epsilon;
  po.intrinsic_delaunay = false;
  po.progress = options.progress;
  CurveSurface out;
  out.surface = prepare_surface(std::move(input), po);
  PreparedSurface& s = out.surface;
  if (!s.supports_signposts()) {
    throw InvalidInput(std::string("curves need an edge-manifold, orientable mesh (they are drawn "
                                   "with signposts): this input took the ") +
                       intrinsic::to_string(s.path) + " path (" + s.reason_detail + ")");
  }
  s.path = intrinsic::SurfacePath::kManifold;  // signposts on the input's own faces
  s.reason = intrinsic::PathReason::kEdgeManifoldOrientable;
  s.boundary_vertex.clear();
  out.curves = std::move(curves);
  build_constrained(options, out);
  return out;
}

CurvePoissonResult curve_poisson(const CurveSurface& s, const Eigen::VectorXd& f,
                                 const std::vector<Index>& dirichlet_vertices,
                                 const Eigen::VectorXd& dirichlet_values,
                                 const PoissonOptions& options) {
  const Index n_in = s.n_input_vertices();
  validate_curves(s.curves, n_in, true);
  if (dirichlet_values.size() != static_cast<Eigen::Index>(dirichlet_vertices.size())) {
    throw InvalidInput("curve_poisson: " + std::to_string(dirichlet_values.size()) +
                       " Dirichlet values for " + std::to_string(dirichlet_vertices.size()) +
                       " vertices");
  }
  const T& base = s.surface.tri;
  std::vector<char> slit(base.n_edges(), 0);
  for (Index e = 0; e < base.n_edges(); ++e) {
    const Index c = s.network.edges[e].curve;
    slit[e] = c != kInvalidIndex && s.curves[c].slit ? 1 : 0;
  }
  const CutOpen cut = cut_open(base, slit);
  const Index nc = cut.tri().n_vertices();
  CurveValues cv(nc);
  gather_curve_values(s, cut, cv);
  cv.finish();
  CurvePoissonResult out;
  out.slit_copies = cut.copies;
  std::vector<Index> dv;
  std::vector<double> dval;
  for (Index v = 0; v < nc; ++v) {
    if (!cv.count[v]) continue;
    dv.push_back(v);
    dval.push_back(cv.sum[v] / cv.count[v]);
    const double scale = std::max({1.0, std::abs(cv.lo[v]), std::abs(cv.hi[v])});
    if (cv.hi[v] - cv.lo[v] > 1e-12 * scale) ++out.conflicting_vertices;
  }
  std::vector<char> on_curve(base.n_vertices(), 0);
  for (Index x = 0; x < nc; ++x) on_curve[cut.origin[x]] |= cv.count[x] ? 1 : 0;
  for (std::size_t i = 0; i < dirichlet_vertices.size(); ++i) {
    const Index v = dirichlet_vertices[i];
    if (v < 0 || v >= n_in) {
      throw InvalidInput("curve_poisson: Dirichlet vertex " + std::to_string(v) +
                         " out of range [0, " + std::to_string(n_in) + ")");
    }
    if (on_curve[v]) {
      throw InvalidInput("curve_poisson: Dirichlet vertex " + std::to_string(v) +
                         " lies on a curve, which already holds it");
    }
    dv.push_back(v);
    dval.push_back(dirichlet_values[static_cast<Eigen::Index>(i)]);
  }
  const Eigen::VectorXd f_in = f.size() == 0 ? Eigen::VectorXd::Zero(n_in) : f;
  const Eigen::VectorXd f_base = from_input_vertices(s.surface, f_in);
  Eigen::VectorXd f_cut(nc);
  for (Index v = 0; v < nc; ++v) f_cut[v] = f_base[cut.origin[v]];
  const Eigen::VectorXd g =
      Eigen::Map<const Eigen::VectorXd>(dval.data(), Eigen::Index(dval.size()));
  const Eigen::VectorXd u = solve_poisson(cut.tri(), f_cut, dv, g, options);
  out.dirichlet_vertices =
      static_cast<Index>(dv.size()) - static_cast<Index>(dirichlet_vertices.size());
  Eigen::VectorXd sum = Eigen::VectorXd::Zero(base.n_vertices());
  Eigen::VectorXd cnt = Eigen::VectorXd::Zero(base.n_vertices());
  for (Index v = 0; v < nc; ++v) sum[cut.origin[v]] += u[v], cnt[cut.origin[v]] += 1.0;
  out.u_intrinsic = sum.cwiseQuotient(cnt.cwiseMax(1.0));
  out.u = on_input_vertices(s.surface, out.u_intrinsic);
  if (!out.u.allFinite()) throw SolverError("curve_poisson: the solution is not finite");
  return out;
}

Eigen::VectorXd curve_distance(const CurveSurface& s, const DistanceOptions& settings,
                               HeatDistanceReport* report) {
  std::vector<Index> sources;
  for (Index c = 0; c < s.network.n_curves(); ++c) {
    const intrinsic::CurveChain ch = intrinsic::curve_chain(s.surface.tri, s.network, c);
    sources.insert(sources.end(), ch.vertices.begin(), ch.vertices.end());
  }
  std::sort(sources.begin(), sources.end());
  sources.erase(std::unique(sources.begin(), sources.end()), sources.end());
  if (sources.empty()) throw InvalidInput("curve_distance: no curve");
  HeatDistanceOptions options = distance_options(s.surface, settings);
  // the sources stand for whole curves, which pass closer than the chord to their vertices: the
  // path bound (to the curves' vertices) holds, the straight-line lower bound does not (D-141)
  options.vertex_positions.resize(0, 3);
  const HeatDistanceSolver solver(s.surface.tri, options);
  Eigen::VectorXd d = on_input_vertices(s.surface, solver.compute_distance(sources, report));
  for (Eigen::Index i = 0; i < d.size(); ++i) {
    if (std::isnan(d[i])) throw SolverError("curve_distance: the distance is not a number");
  }
  return d;
}

std::vector<std::vector<Eigen::Vector3d>> curve_polylines(const CurveSurface& s) {
  const T& tri = s.surface.tri;
  const intrinsic::SignpostTriangulation* st =
      s.surface.signposts ? &*s.surface.signposts : nullptr;
  const intrinsic::NormalCoordinateTriangulation* nc =
      s.surface.integer ? &*s.surface.integer : nullptr;
  if (!st && !nc) throw InvalidInput("curve_polylines: the surface has no correspondence");
  const Positions where = nc ? intrinsic::CorrespondenceView(*nc).vertex_positions() : Positions();
  // halfedge h over the input, tail to head (integer: its ends and the input edges it crosses)
  auto trace = [&](Index h) {
    std::vector<Eigen::Vector3d> pts;
    if (st) {
      for (const intrinsic::SurfacePoint& p : st->trace_halfedge(h)) pts.push_back(st->position(p));
      return pts;
    }
    pts.push_back(where.row(tri.tail(h)).transpose());
    for (const intrinsic::InputCrossing& c : nc->trace_halfedge(h)) {
      pts.push_back(nc->crossing_position(c));
    }
    pts.push_back(where.row(tri.head(h)).transpose());
    return pts;
  };
  std::vector<std::vector<Eigen::Vector3d>> out;
  for (Index c = 0; c < s.network.n_curves(); ++c) {
    const intrinsic::CurveChain ch = intrinsic::curve_chain(tri, s.network, c);
    std::vector<Eigen::Vector3d> line;
    for (std::size_t i = 0; i < ch.edges.size(); ++i) {
      const Index hl = ch.left_halfedges[i];
      std::vector<Eigen::Vector3d> pts =
          trace(hl != kInvalidIndex ? hl : tri.edge_halfedge(ch.edges[i]));
      if (hl == kInvalidIndex) std::reverse(pts.begin(), pts.end());
      for (std::size_t k = line.empty() ? 0 : 1; k < pts.size(); ++k) line.push_back(pts[k]);
    }
    if (line.empty() && !ch.vertices.empty()) {
      const Index v = ch.vertices.front();
      line.push_back(st ? st->position(st->vertex_location(v)) : Eigen::Vector3d(where.row(v)));
    }
    out.push_back(std::move(line));
  }
  return out;
}

}  // namespace ifem::solvers
