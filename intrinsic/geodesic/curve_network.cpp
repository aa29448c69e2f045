#include "intrinsic/geodesic/curve_network.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <utility>

#include "intrinsic/core/geometry.h"

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
void record_curve(const T& tri, CurveNetwork& net, const EdgePath& p, Index c) {
  double s = 0.0;
  Index prev = kInvalidIndex;
  for (const PathStep& st : p.steps) {
    CurveEdge& r = net.edges[st.edge];
    if (r.curve != kInvalidIndex) {
      const Index h = tri.edge_halfedge(st.edge);
      const std::string edge = "the edge between intrinsic vertices " +
                               std::to_string(tri.tail(h)) + " and " + std::to_string(tri.head(h));
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

}  // namespace

CurveNetwork insert_curves(SignpostTriangulation& st, const std::vector<CurveSpec>& specs,
                           const FlipOutOptions& options) {
  options.validate();
  const T& tri = st.intrinsic();
  CurveNetwork net;
  std::vector<EdgePath> paths(specs.size());
  for (std::size_t c = 0; c < specs.size(); ++c) {  // what can be checked before any flip
    const CurveSpec& sp = specs[c];                 // (components: when joined, below)
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
    record_curve(tri, net, paths[c], static_cast<Index>(c));
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
