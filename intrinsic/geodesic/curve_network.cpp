#include "intrinsic/geodesic/curve_network.h"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <limits>
#include <optional>
#include <sstream>
#include <string>
#include <utility>

#include "intrinsic/core/geometry.h"
#include "intrinsic/core/triangle_formulas.h"

namespace ifem::intrinsic {
namespace {

using T = IntrinsicTriangulation;

std::string curve_name(std::size_t c) { return "curve " + std::to_string(c); }

// Runs f, prefixing an InvalidInput's message with the curve's name.
template <class F>
auto for_curve(std::size_t c, F&& f) {
  try {
    return f();
  } catch (const InvalidInput& e) {
    throw InvalidInput(curve_name(c) + ": " + e.what());
  }
}

// Arc length from the path's start at each joint (#steps + 1 entries).
std::vector<double> joint_arclength(const T& tri, const EdgePath& p) {
  std::vector<double> s{0.0};
  for (const PathStep& st : p.steps) s.push_back(s.back() + tri.length(st.edge));
  return s;
}

// A loop's steps rotated so that joint 0 is the pinned joint at `start` from which the pinned
// joints visit `given` in order (cyclically); pinned indices rotated with them.
void rotate_loop_to(const T& tri, EdgePath& p, const std::vector<Index>& given, std::size_t c) {
  const std::vector<Index> pv = path_vertices(tri, p);
  const std::size_t n = p.pinned.size();
  for (std::size_t k = 0; k < n; ++k) {
    bool match = true;
    for (std::size_t i = 0; i < n && match; ++i) {
      match = pv[p.pinned[(k + i) % n]] == given[i];
    }
    if (!match) continue;
    const Index shift = p.pinned[k];
    std::rotate(p.steps.begin(), p.steps.begin() + shift, p.steps.end());
    const Index m = static_cast<Index>(p.steps.size());
    for (Index& j : p.pinned) j = (j - shift + m) % m;
    std::sort(p.pinned.begin(), p.pinned.end());
    return;
  }
  throw InvalidInput(curve_name(c) + ": the loop lost its order through the given vertices");
}

// Arc lengths at the control points of a path or loop through `given` (pinned at the inner
// ones / all of them), after FlipOut.
std::vector<double> control_arclengths(const T& tri, EdgePath& p, const CurveSpec& spec,
                                       std::size_t c) {
  const std::size_t k = spec.vertices.size();
  const bool loop = spec.shape == CurveShape::kLoop;
  if (p.pinned.size() != (loop ? k : k - 2)) {
    throw InvalidInput(curve_name(c) + ": FlipOut kept " + std::to_string(p.pinned.size()) +
                       " of the given vertices as joints");
  }
  if (loop) rotate_loop_to(tri, p, spec.vertices, c);
  const std::vector<double> s = joint_arclength(tri, p);
  std::vector<double> out{0.0};
  for (const Index j : p.pinned) {
    if (j != 0) out.push_back(s[j]);
  }
  out.push_back(s.back());
  return out;
}

// Records curve c's steps in the network (edges, arc lengths, links).
void record_curve(const T& tri, Index n_input, CurveNetwork& net, const EdgePath& p, Index c) {
  double s = 0.0;
  Index prev = kInvalidIndex;
  for (const PathStep& st : p.steps) {
    CurveEdge& r = net.edges[st.edge];
    if (r.curve != kInvalidIndex) {
      const Index h = tri.edge_halfedge(st.edge), a = tri.tail(h), b = tri.head(h);
      auto name = [&](Index v) {
        return v < n_input ? "input vertex " + std::to_string(v) : std::string("a Bézier point");
      };
      const std::string edge = "the edge between " + name(a) + " and " + name(b);
      if (r.curve == c) {
        throw InvalidInput(curve_name(c) + " runs twice along " + edge +
                           " (its geodesic pieces overlap there: a waypoint the curve must turn "
                           "back at); choose other vertices");
      }
      throw InvalidInput(curve_name(c) + " and " + curve_name(r.curve) + " share " + edge +
                         ": curves may meet and cross at vertices, not overlap");
    }
    const double l = tri.length(st.edge);
    r = {c, st.forward, st.forward ? s : s + l, st.forward ? s + l : s, prev, kInvalidIndex};
    if (prev != kInvalidIndex) net.edges[prev].next = st.edge;
    if (prev == kInvalidIndex) net.first_edge[c] = st.edge;
    net.constrained[st.edge] = 1;
    prev = st.edge;
    s += l;
  }
  if (p.closed && prev != kInvalidIndex) {
    net.edges[prev].next = net.first_edge[c];
    net.edges[net.first_edge[c]].prev = prev;
  }
  net.length[c] = s;
}

// Bézier curves one by one, each with the curves before it fixed.
void insert_beziers(SignpostTriangulation& st, const std::vector<CurveSpec>& specs,
                    const FlipOutOptions& options, std::vector<EdgePath>& paths,
                    CurveNetwork& net) {
  std::vector<char> fixed;
  for (std::size_t c = 0; c < specs.size(); ++c) {
    if (specs[c].shape != CurveShape::kBezier) continue;
    fixed.resize(static_cast<std::size_t>(st.intrinsic().n_edges()), 0);
    BezierCurve b = for_curve(c, [&] {
      return bezier_curve(st, specs[c].vertices, specs[c].bezier_rounds, options, &fixed);
    });
    net.bezier_midpoints += b.inserted_vertices;
    fixed.resize(static_cast<std::size_t>(st.intrinsic().n_edges()), 0);
    for (const PathStep& s : b.path.steps) fixed[s.edge] = 1;
    paths[c] = std::move(b.path);
  }
}

// What can be checked before any flip (components: when joined).
void check_specs(const T& tri, const std::vector<CurveSpec>& specs) {
  for (std::size_t c = 0; c < specs.size(); ++c) {
    const CurveSpec& sp = specs[c];
    const std::size_t k = sp.vertices.size();
    for_curve(c, [&] {
      if (k < 2) throw InvalidInput("needs at least 2 vertices, got " + std::to_string(k));
      for (std::size_t i = 0; i < k; ++i) {
        const Index v = sp.vertices[i];
        if (v < 0 || v >= tri.n_vertices()) {
          throw InvalidInput("vertex " + std::to_string(v) + " out of range [0, " +
                             std::to_string(tri.n_vertices()) + ")");
        }
        const Index w = sp.vertices[(i + 1) % k];
        if ((i + 1 < k || sp.shape == CurveShape::kLoop) && v == w) {
          throw InvalidInput("vertex " + std::to_string(v) + " twice in a row");
        }
      }
      if (sp.shape == CurveShape::kBezier && (sp.bezier_rounds < 0 || sp.bezier_rounds > 16)) {
        throw InvalidInput("Bézier rounds must be in [0, 16], got " +
                           std::to_string(sp.bezier_rounds));
      }
    });
  }
}

// A Bézier curve's added vertices and final segment length with `rounds` rounds, its control
// polygon (edge path) being `polygon` long.
double bezier_vertices(std::size_t d, int rounds) {
  return 0.5 * double(d) * double(d + 1) * (std::ldexp(1.0, rounds) - 1.0);
}
double bezier_segment(double polygon, std::size_t d, int rounds) {
  return polygon / (double(d) * std::ldexp(1.0, rounds));
}

std::string figure(double x) {
  std::ostringstream m;
  m << std::setprecision(3) << x;
  return m.str();
}

}  // namespace

void check_curve_budget(const T& tri, const std::vector<CurveSpec>& specs, double max_bytes) {
  const CurveEstimate e = estimate_curves(tri, specs, max_bytes);
  const double floor = kMinBezierSegment * e.mean_edge_length;
  for (std::size_t c = 0; c < specs.size(); ++c) {
    if (specs[c].shape != CurveShape::kBezier) continue;
    const double others = e.vertices - e.added_vertices[c];  // #V and the other curves
    const bool fine = e.segment_length[c] >= floor;
    if (fine && e.bytes <= e.budget) continue;
    const std::size_t d = specs[c].vertices.size() - 1;
    const double polygon =
        e.segment_length[c] * double(d) * std::ldexp(1.0, specs[c].bezier_rounds);
    int fit = specs[c].bezier_rounds;
    while (fit > 0 && (bezier_segment(polygon, d, fit) < floor ||
                       (others + bezier_vertices(d, fit)) * kRefineBytesPerVertex > e.budget)) {
      --fit;
    }
    std::ostringstream m;
    m << curve_name(c) << ": a Bézier curve of degree " << d << " with " << specs[c].bezier_rounds
      << " rounds adds up to " << figure(e.added_vertices[c]) << " vertices, segments of about "
      << figure(e.segment_length[c]) << " (" << figure(e.segment_length[c] / e.mean_edge_length)
      << " × the mesh's mean edge length " << figure(e.mean_edge_length) << "); ";
    if (!fine) {
      m << "below " << figure(kMinBezierSegment) << " × it the mesh cannot show the difference "
        << "and the midpoints come a round-off apart";
    } else {
      m << "about " << figure(e.bytes / 1e9) << " GB at " << kRefineBytesPerVertex / 1024
        << " KiB per vertex, above the memory budget of " << figure(e.budget / 1e9)
        << " GB (`--memory-budget GB` in the CLI)";
    }
    if ((others + bezier_vertices(d, fit)) * kRefineBytesPerVertex > e.budget) {
      m << ". The mesh alone (" << figure(others) << " vertices) is over that budget: raise it";
    } else {
      m << ". Use at most " << fit << " rounds";
    }
    throw InvalidInput(m.str());
  }
}

std::string iteration_cap_message(const FlipOutReport& fo, const std::string& accept) {
  std::ostringstream m;
  m << "FlipOut stopped at its iteration cap (" << fo.iterations << " reroutes, " << fo.flips
    << " flips) before the curves were geodesic: total length " << fo.initial_length << " -> "
    << fo.final_length << " so far, not a geodesic network. Raise the cap "
    << "(FlipOutOptions::max_iterations, `--max-iterations N` in `ifem geodesic`) or accept the "
    << "partial result (" << accept << ")";
  return m.str();
}

CurveEstimate estimate_curves(const IntrinsicTriangulation& tri,
                              const std::vector<CurveSpec>& specs, double max_memory_bytes) {
  check_specs(tri, specs);
  CurveEstimate e;
  std::vector<double> lengths(static_cast<std::size_t>(tri.n_edges()));
  for (Index i = 0; i < tri.n_edges(); ++i) lengths[i] = tri.length(i);
  e.mean_edge_length = lengths.empty() ? 0.0 : robust_mean_length(std::move(lengths));
  e.budget = max_memory_bytes > 0.0 ? max_memory_bytes : default_memory_budget();
  e.added_vertices.assign(specs.size(), 0.0);
  e.segment_length.assign(specs.size(), 0.0);
  e.vertices = double(tri.n_vertices());
  std::optional<EdgePathFinder> finder;
  for (std::size_t c = 0; c < specs.size(); ++c) {
    const CurveSpec& sp = specs[c];
    if (sp.shape != CurveShape::kBezier) continue;
    if (!finder) finder.emplace(tri);
    const EdgePath p = for_curve(c, [&] { return finder->through(sp.vertices, false, true); });
    const std::size_t d = sp.vertices.size() - 1;
    e.added_vertices[c] = bezier_vertices(d, sp.bezier_rounds);
    e.segment_length[c] = bezier_segment(path_length(tri, p), d, sp.bezier_rounds);
    e.vertices += e.added_vertices[c];
  }
  e.bytes = e.vertices * kRefineBytesPerVertex;
  return e;
}

CurveNetwork insert_curves(SignpostTriangulation& st, const std::vector<CurveSpec>& specs,
                           const FlipOutOptions& options, double max_memory_bytes) {
  options.validate();
  const T& tri = st.intrinsic();
  CurveNetwork net;
  std::vector<EdgePath> paths(specs.size());
  check_specs(tri, specs);
  check_curve_budget(tri, specs, max_memory_bytes);
  insert_beziers(st, specs, options, paths, net);
  std::vector<EdgePath> geodesics;
  std::vector<std::size_t> which;
  EdgePathFinder finder(tri);  // one edge graph for all of them (no flips until shorten)
  for (std::size_t c = 0; c < specs.size(); ++c) {
    if (specs[c].shape == CurveShape::kBezier) continue;
    geodesics.push_back(for_curve(c, [&] {
      return finder.through(specs[c].vertices, specs[c].shape == CurveShape::kLoop, true);
    }));
    which.push_back(c);
  }
  std::vector<char> fixed(static_cast<std::size_t>(tri.n_edges()), 0);
  for (const EdgePath& p : paths) {
    for (const PathStep& s : p.steps) fixed[s.edge] = 1;
  }
  if (!geodesics.empty()) net.flipout = shorten(st, geodesics, options, &fixed);
  const std::size_t n = specs.size();
  net.constrained.assign(static_cast<std::size_t>(tri.n_edges()), 0);
  net.edges.assign(static_cast<std::size_t>(tri.n_edges()), CurveEdge{});
  net.first_edge.assign(n, kInvalidIndex);
  net.closed.assign(n, 0);
  net.length.assign(n, 0.0);
  net.control_arclength.resize(n);
  for (std::size_t i = 0; i < which.size(); ++i) paths[which[i]] = std::move(geodesics[i]);
  for (std::size_t c = 0; c < n; ++c) {
    net.closed[c] = specs[c].shape == CurveShape::kLoop ? 1 : 0;
    if (specs[c].shape == CurveShape::kBezier) {
      net.control_arclength[c] = {0.0, path_length(tri, paths[c])};
    } else {
      net.control_arclength[c] = control_arclengths(tri, paths[c], specs[c], c);
    }
    record_curve(tri, st.n_input_vertices(), net, paths[c], static_cast<Index>(c));
  }
  return net;
}

EdgeConstraints CurveNetwork::constraints(const IntrinsicTriangulation& tri) {
  EdgeConstraints ec;
  ec.flags = &constrained;
  ec.on_split = [this, &tri](Index e, Index new_edge, Index v, double t) {
    if (static_cast<Index>(edges.size()) <= new_edge) edges.resize(new_edge + 1);
    CurveEdge& r = edges[e];
    if (r.curve == kInvalidIndex) return;  // constrained, but on no curve
    const double sm = r.s_tail + t * (r.s_head - r.s_tail);
    const double s_old_head = r.s_head;
    r.s_head = sm;  // e now runs from its tail to v
    CurveEdge n;
    n.curve = r.curve;
    const bool same = tri.tail(tri.edge_halfedge(new_edge)) == v;  // new edge runs v → old head
    n.forward = same ? r.forward : !r.forward;
    n.s_tail = same ? sm : s_old_head;
    n.s_head = same ? s_old_head : sm;
    if (r.forward) {  // the curve runs tail → v → old head: e, then new_edge
      n.prev = e;
      n.next = r.next;
      if (r.next != kInvalidIndex) edges[r.next].prev = new_edge;
      r.next = new_edge;
    } else {  // old head → v → tail: new_edge, then e
      n.next = e;
      n.prev = r.prev;
      if (r.prev != kInvalidIndex) edges[r.prev].next = new_edge;
      if (first_edge[r.curve] == e) first_edge[r.curve] = new_edge;
      r.prev = new_edge;
    }
    edges[new_edge] = n;
  };
  return ec;
}

CurveChain curve_chain(const IntrinsicTriangulation& tri, const CurveNetwork& net, Index c) {
  if (c < 0 || c >= net.n_curves()) {
    throw InvalidInput("curve_chain: curve " + std::to_string(c) + " out of range [0, " +
                       std::to_string(net.n_curves()) + ")");
  }
  CurveChain out;
  const Index first = net.first_edge[c];
  for (Index e = first, guard = 0; e != kInvalidIndex && guard <= tri.n_edges(); ++guard) {
    const CurveEdge& r = net.edges[e];
    const Index h = tri.edge_halfedge(e);
    const Index along = r.forward ? h : tri.twin(h);
    if (out.vertices.empty()) {
      out.vertices.push_back(r.forward ? tri.tail(h) : tri.head(h));
      out.arclength.push_back(r.forward ? r.s_tail : r.s_head);
    }
    out.vertices.push_back(r.forward ? tri.head(h) : tri.tail(h));
    out.arclength.push_back(r.forward ? r.s_head : r.s_tail);
    out.left_halfedges.push_back(along);
    out.edges.push_back(e);
    e = r.next;
    if (e == first) break;
  }
  return out;
}

FlipReport flip_to_constrained_delaunay(SignpostTriangulation& st, const CurveNetwork& net) {
  return st.flip_to_delaunay(net.constrained);
}

CotanSigns cotan_signs(const IntrinsicTriangulation& tri, const std::vector<char>& constrained) {
  CotanSigns out;
  out.min_weight = std::numeric_limits<double>::infinity();
  for (Index e = 0; e < tri.n_edges(); ++e) {
    const Index h = tri.edge_halfedge(e), t = tri.twin(h);
    const double a = halfedge_cotan(tri, h), b = t == kInvalidIndex ? 0.0 : halfedge_cotan(tri, t);
    const double w = 0.5 * (a + b);
    out.min_weight = std::min(out.min_weight, w);
    if (!(w < -1e-12 * std::max(std::abs(a), std::abs(b)))) continue;
    const bool c = is_flagged(&constrained, e);
    ++(c ? out.negative_constrained : out.negative_unconstrained);
  }
  if (tri.n_edges() == 0) out.min_weight = 0.0;
  return out;
}

}  // namespace ifem::intrinsic
