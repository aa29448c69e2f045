// What FlipOut is used for (flip_geodesic.h): surface points as path ends, geodesic Bézier
// curves by de Casteljau subdivision, and single-source geodesics.
#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <queue>
#include <string>
#include <unordered_map>

#include "intrinsic/core/errors.h"
#include "intrinsic/core/geometry.h"
#include "intrinsic/geodesic/flip_geodesic.h"
#include "intrinsic/geodesic/flip_network.h"

namespace ifem::intrinsic {

namespace {

using T = IntrinsicTriangulation;
constexpr double kInf = std::numeric_limits<double>::infinity();

// Vertices with more than one fan (an edge-manifold surface pinched at a vertex): a walk around
// one fan misses the others. Flips never change how many fans a vertex has.
std::vector<char> pinched_vertices(const T& tri) {
  std::vector<Index> outgoing(tri.n_vertices(), 0), in_fan(tri.n_vertices(), 0);
  for (Index h = 0; h < tri.n_halfedges(); ++h) ++outgoing[tri.tail(h)];
  for (Index v = 0; v < tri.n_vertices(); ++v) {
    const Index h0 = tri.vertex_halfedge(v);
    for (Index x = h0; x != kInvalidIndex && in_fan[v] <= outgoing[v];) {
      ++in_fan[v];
      x = tri.twin(T::prev(x));
      if (x == h0) break;
    }
  }
  std::vector<char> pinched(tri.n_vertices(), 0);
  for (Index v = 0; v < tri.n_vertices(); ++v) pinched[v] = in_fan[v] != outgoing[v] ? 1 : 0;
  return pinched;
}

// Calls f(edge, neighbour) for every edge at v: around its fan (both boundary edges included),
// or, at a pinched vertex, by a scan of all halfedges (rare: O(#H) there).
template <typename F>
void for_each_edge_at(const T& tri, Index v, bool pinched, F&& f) {
  if (pinched) {
    for (Index h = 0; h < tri.n_halfedges(); ++h) {
      if (tri.tail(h) == v) f(tri.edge(h), tri.head(h));
      if (tri.head(h) == v && tri.twin(h) == kInvalidIndex) f(tri.edge(h), tri.tail(h));
    }
    return;
  }
  const Index h0 = tri.vertex_halfedge(v);
  if (h0 == kInvalidIndex) return;
  Index x = h0;
  for (Index guard = 0; guard <= tri.n_halfedges(); ++guard) {
    f(tri.edge(x), tri.head(x));
    const Index n = tri.twin(T::prev(x));
    if (n == kInvalidIndex) {  // the fan's last side enters v along the boundary
      f(tri.edge(T::prev(x)), tri.tail(T::prev(x)));
      return;
    }
    if (n == h0) return;
    x = n;
  }
}

// The outgoing intrinsic halfedge of input vertex v whose wedge holds signpost direction phi.
Index wedge_holding(const SignpostTriangulation& st, Index v, double phi) {
  const T& tri = st.intrinsic();
  Index best = kInvalidIndex;
  double gap = kInf;
  const Index h0 = tri.vertex_halfedge(v);
  Index x = h0;
  for (Index guard = 0; x != kInvalidIndex && guard <= tri.n_halfedges(); ++guard) {
    const double a0 = st.halfedge_direction(x), a1 = a0 + corner_angle(tri, x);
    if (phi >= a0 && phi < a1) return x;
    const double g = phi < a0 ? a0 - phi : phi - a1;
    if (g < gap) gap = g, best = x;
    x = tri.twin(T::prev(x));
    if (x == h0) break;
  }
  return best;
}

}  // namespace

SurfacePoint locate_input_point(const SignpostTriangulation& st, Index f,
                                const Eigen::Vector3d& b) {
  Eigen::Vector2d p[3];
  face_layout(st.input(), f, p);
  const Eigen::Vector2d x = b[0] * p[0] + b[1] * p[1] + b[2] * p[2];
  int k = 0;
  for (int j = 1; j < 3; ++j) {
    if ((x - p[j]).squaredNorm() < (x - p[k]).squaredNorm()) k = j;
  }
  const Index v = st.input().tail(3 * f + k);
  const Eigen::Vector2d w = x - p[k], e = p[(k + 1) % 3] - p[k];
  const double alpha = std::atan2(cross2(e, w), e.dot(w));
  const double phi = st.wrap_direction(v, st.input_halfedge_direction(3 * f + k) + alpha);
  const Index h = wedge_holding(st, v, phi);
  if (h == kInvalidIndex) throw InvalidInput("input vertex " + std::to_string(v) + " has no faces");
  const T& tri = st.intrinsic();
  Eigen::Vector2d q[3];
  face_layout(tri, T::face(h), q);
  const int s = static_cast<int>(T::side(h));
  const Eigen::Vector2d ed = (q[(s + 1) % 3] - q[s]).normalized();
  const double turn = std::clamp(phi - st.halfedge_direction(h), 0.0, corner_angle(tri, h));
  SurfacePoint start;
  start.face = T::face(h);
  start.bary[s] = 1.0;
  TraceOptions o;
  o.start_corner = s;
  const Eigen::Vector2d dir =
      std::cos(turn) * ed + std::sin(turn) * Eigen::Vector2d(-ed.y(), ed.x());
  return trace_straight(tri, start, dir, w.norm(), o).end;
}

Index insert_surface_point(SignpostTriangulation& st, const SurfacePoint& p, double snap) {
  const T& in = st.input();
  if (p.face < 0 || p.face >= in.n_faces()) {
    throw InvalidInput("surface point: face " + std::to_string(p.face) + " is out of range [0, " +
                       std::to_string(in.n_faces()) + ")");
  }
  const Eigen::Vector3d& b = p.bary;
  if (!b.allFinite() || b.minCoeff() < -1e-12 || std::abs(b.sum() - 1.0) > 1e-9) {
    throw InvalidInput("surface point in face " + std::to_string(p.face) +
                       ": barycentric coordinates must be ≥ 0 and sum to 1");
  }
  const Eigen::Vector3d bc = b.cwiseMax(0.0) / b.cwiseMax(0.0).sum();
  Eigen::Index k = 0;
  if (bc.maxCoeff(&k) >= 1.0 - snap) return in.tail(3 * p.face + k);
  const SurfacePoint at = locate_input_point(st, p.face, bc);
  const T& tri = st.intrinsic();
  const Eigen::Vector3d& q = at.bary;
  Eigen::Index c = 0;
  if (q.maxCoeff(&c) >= 1.0 - snap) return tri.tail(3 * at.face + c);
  if (q.minCoeff(&c) <= snap) {  // on the side opposite corner c
    const Index hs = 3 * at.face + (c + 1) % 3;
    const double u = q[(c + 1) % 3], w = q[(c + 2) % 3];
    const Index e = tri.edge(hs);
    const double t = tri.edge_halfedge(e) == hs ? w / (u + w) : u / (u + w);
    if (tri.can_split_edge(e)) return st.split_edge(e, t);
  }
  return st.insert_vertex(at.face, q.cwiseMax(snap) / q.cwiseMax(snap).sum());
}

namespace {

// Edges a Bézier construction must not flip or split (other curves), grown with the
// triangulation's edges (new edges are free); empty: none.
struct FixedEdges {
  std::vector<char> flags;
  bool any = false;
  const std::vector<char>* grown(const IntrinsicTriangulation& tri) {
    if (!any) return nullptr;
    flags.resize(static_cast<std::size_t>(tri.n_edges()), 0);
    return &flags;
  }
  bool operator()(Index e) const { return any && is_flagged(&flags, e); }
};

// The shortest edge path a → b by a Dijkstra search that stops at b and walks each vertex's
// fan, so its cost is that of the ball it explores, not of the whole triangulation: Bézier
// subdivision asks for thousands of paths between nearby points on a triangulation that grows
// with every midpoint, and a whole-graph search per path made that quadratic. At a pinched
// vertex only one fan is walked; when that misses b, the whole-graph search answers.
EdgePath local_edge_path(const T& tri, Index a, Index b) {
  struct Reached {
    double d = kInf;
    PathStep via;
  };
  std::unordered_map<Index, Reached> reached;
  using Item = std::pair<double, Index>;
  std::priority_queue<Item, std::vector<Item>, std::greater<Item>> queue;
  reached[a].d = 0.0;
  queue.push({0.0, a});
  while (!queue.empty()) {
    const double d = queue.top().first;  // not a structured binding: the lambda captures both
    const Index v = queue.top().second;
    queue.pop();
    if (d > reached[v].d) continue;
    if (v == b) break;
    for_each_edge_at(tri, v, false, [&](Index e, Index u) {
      Reached& r = reached[u];
      const double du = d + tri.length(e);
      if (du >= r.d) return;
      r.d = du;
      r.via = {e, tri.tail(tri.edge_halfedge(e)) == v && tri.head(tri.edge_halfedge(e)) == u};
      queue.push({du, u});
    });
  }
  const auto it = reached.find(b);
  if (it == reached.end() || !std::isfinite(it->second.d)) return shortest_edge_path(tri, a, b);
  EdgePath path;
  for (Index v = b; v != a; v = step_tail(tri, reached[v].via)) {
    path.steps.push_back(reached[v].via);
  }
  std::reverse(path.steps.begin(), path.steps.end());
  return path;
}

// A FlipOut geodesic between two vertices (on the current triangulation; flips it).
EdgePath geodesic_between(SignpostTriangulation& st, Index a, Index b, const FlipOutOptions& o,
                          FixedEdges& fixed) {
  std::vector<EdgePath> p{local_edge_path(st.intrinsic(), a, b)};
  shorten(st, p, o, fixed.grown(st.intrinsic()));
  return p[0];
}

// The vertex halfway along the geodesic from a to b: an existing vertex within 1e-9 of the
// length, else a new one splitting the edge there (counted in *inserted).
// A fixed edge is never split: the midpoint snaps to its nearer end.
Index midpoint(SignpostTriangulation& st, Index a, Index b, const FlipOutOptions& o,
               FixedEdges& fixed, Index* inserted) {
  if (a == b) return a;
  const EdgePath p = geodesic_between(st, a, b, o, fixed);
  const T& tri = st.intrinsic();
  const double half = 0.5 * path_length(tri, p);
  double before = 0.0;
  for (const PathStep& s : p.steps) {
    const double l = tri.length(s.edge);
    if (before + l < half) {
      before += l;
      continue;
    }
    const double t = (half - before) / l;
    if (t <= 1e-9 || (fixed(s.edge) && t < 0.5)) return step_tail(tri, s);
    if (t >= 1.0 - 1e-9 || !tri.can_split_edge(s.edge) || fixed(s.edge)) return step_head(tri, s);
    ++*inserted;
    return st.split_edge(s.edge, s.forward ? t : 1.0 - t);
  }
  return b;
}

// One de Casteljau step at t = 1/2 of the piece `c` (d + 1 points): its two halves, joined
// (2d + 1 points).
std::vector<Index> split_piece(SignpostTriangulation& st, std::vector<Index> c,
                               const FlipOutOptions& o, FixedEdges& fixed, Index* inserted) {
  std::vector<Index> left{c.front()}, right{c.back()};
  while (c.size() > 1) {
    std::vector<Index> next;
    for (std::size_t i = 0; i + 1 < c.size(); ++i) {
      next.push_back(midpoint(st, c[i], c[i + 1], o, fixed, inserted));
    }
    c = std::move(next);
    left.push_back(c.front());
    right.push_back(c.back());
  }
  left.insert(left.end(), right.rbegin() + 1, right.rend());
  return left;
}

// Rounds of "shorten, then take a shorter accepted prefix" per vertex in single-source
// geodesics.
constexpr int kMaxSplices = 8;

// If the path passes an accepted vertex y whose geodesic is shorter than the path's part up to
// y, replaces that part by y's geodesic (the best such y) and returns true. A path held up at a
// wedge by an earlier geodesic (it cannot cross it) usually has such a y: the vertex where it
// meets that geodesic. *spliced_at: y.
bool splice_shorter_prefix(const T& tri, const SingleSourceGeodesics& g,
                           const std::vector<char>& accepted, EdgePath* path, Index* spliced_at) {
  const std::vector<Index> pv = path_vertices(tri, *path);
  const double total = path_length(tri, *path);
  double prefix = 0.0, best_gain = -1e-12 * total;  // equal lengths too: the other side of a cone
  std::size_t best = 0;
  for (std::size_t k = 1; k + 1 < pv.size(); ++k) {
    prefix += tri.length(path->steps[k - 1].edge);
    const double gain = prefix - g.length[pv[k]];
    if (!accepted[pv[k]] || gain < best_gain) continue;
    const std::vector<PathStep>& to = g.paths[pv[k]].steps;
    const bool same =
        to.size() == k && std::equal(to.begin(), to.end(), path->steps.begin(),
                                     [](const PathStep& a, const PathStep& b) {
                                       return a.edge == b.edge && a.forward == b.forward;
                                     });
    if (!same) best_gain = gain, best = k;
  }
  if (best == 0) return false;
  *spliced_at = pv[best];
  EdgePath spliced = g.paths[pv[best]];
  spliced.steps.insert(spliced.steps.end(), path->steps.begin() + best, path->steps.end());
  *path = std::move(spliced);
  return true;
}

}  // namespace

BezierCurve bezier_curve(SignpostTriangulation& st, const std::vector<Index>& control, int rounds,
                         const FlipOutOptions& options, const std::vector<char>* fixed_edges) {
  options.validate();
  FixedEdges fixed;
  if (fixed_edges) fixed.flags = *fixed_edges, fixed.any = true;
  if (rounds < 0 || rounds > 16) {
    throw InvalidInput("bezier_curve: rounds must be in [0, 16], got " + std::to_string(rounds));
  }
  // validates the points (range, consecutive repeats, components) before anything is flipped
  (void)edge_path_through(st.intrinsic(), control, false, true);
  const std::size_t d = control.size() - 1;
  BezierCurve out;
  std::vector<Index> pts = control;
  for (int r = 0; r < rounds; ++r) {
    std::vector<Index> next{pts.front()};
    for (std::size_t k = 0; k + d < pts.size(); k += d) {
      const std::vector<Index> piece(pts.begin() + k, pts.begin() + k + d + 1);
      const std::vector<Index> halves =
          split_piece(st, piece, options, fixed, &out.inserted_vertices);
      next.insert(next.end(), halves.begin() + 1, halves.end());
    }
    pts = std::move(next);
  }
  pts.erase(std::unique(pts.begin(), pts.end()), pts.end());
  out.controls = pts;
  std::vector<EdgePath> paths{edge_path_through(st.intrinsic(), pts, false, true)};
  out.report = shorten(st, paths, options, fixed.grown(st.intrinsic()));
  out.path = std::move(paths[0]);
  return out;
}

SingleSourceGeodesics single_source_geodesics(SignpostTriangulation& st, Index source,
                                              const FlipOutOptions& options,
                                              const ProgressCallback& on_progress) {
  options.validate();
  const T& tri = st.intrinsic();
  const Index nv = tri.n_vertices();
  if (source < 0 || source >= nv) {
    throw InvalidInput("single_source_geodesics: source " + std::to_string(source) +
                       " is out of range [0, " + std::to_string(nv) + ")");
  }
  SingleSourceGeodesics out;
  out.length = Eigen::VectorXd::Constant(nv, kInf);
  out.paths.resize(nv);
  std::vector<char> accepted(nv, 0);
  struct Entry {
    double d;
    Index v, parent, edge;
    bool operator>(const Entry& o) const { return d > o.d; }
  };
  std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> queue;
  auto offer = [&](Index e, Index from, Index to) {
    if (accepted[from] && !accepted[to])
      queue.push({out.length[from] + tri.length(e), to, from, e});
  };
  std::vector<int> uses(tri.n_edges(), 0);
  detail::FlipNetwork net(st, uses, nullptr);
  // per accepted vertex, the joints of its path left bent (blocked) by its run
  std::vector<std::vector<std::pair<Index, Eigen::Vector2d>>> bent(nv);
  detail::FlipNetwork::KnownJoints known;
  net.on_flip = [&](Index e) {  // a flip may join the accepted region to a new vertex
    const Index h = tri.edge_halfedge(e);
    offer(e, tri.tail(h), tri.head(h));
    offer(e, tri.head(h), tri.tail(h));
  };
  const std::vector<char> pinched = pinched_vertices(tri);
  auto accept = [&](Index v, double length) {
    accepted[v] = 1;
    out.length[v] = length;
    for_each_edge_at(tri, v, pinched[v] != 0, [&](Index e, Index u) { offer(e, v, u); });
  };
  accept(source, 0.0);
  ProgressMeter meter(on_progress, "single-source geodesics", double(nv));
  double n_accepted = 1.0;
  FlipOutReport rep;
  while (!queue.empty()) {
    const Entry top = queue.top();
    queue.pop();
    if (accepted[top.v]) continue;
    const Index h = tri.edge_halfedge(top.edge);
    const bool along = tri.tail(h) == top.parent && tri.head(h) == top.v;
    if (!along && !(tri.head(h) == top.parent && tri.tail(h) == top.v)) continue;  // flipped
    EdgePath path = out.paths[top.parent];
    path.steps.push_back({top.edge, along});
    Index prefix_from = top.parent;  // the accepted vertex whose path starts this one
    for (int attempt = 0; attempt < kMaxSplices; ++attempt) {
      // the prefix's joints are as its run left them: only their bent ones need a look
      known.straight_below = static_cast<Index>(out.paths[prefix_from].steps.size());
      known.bent = bent[prefix_from];
      net.add(path, top.v, &known);
      rep = {};
      net.run(options, rep);
      path = net.extract(0);
      out.iterations += rep.iterations;
      if (!splice_shorter_prefix(tri, out, accepted, &path, &prefix_from)) break;
      net.drop_curves();
    }
    bent[top.v] = net.known_joints(0).bent;
    net.release_curves();  // the accepted path stays counted: an obstacle from now on
    if (rep.stopped_by != FlipOutStop::kConverged) ++out.blocked;
    out.paths[top.v] = std::move(path);
    accept(top.v, rep.final_length);
    meter.update(++n_accepted);
  }
  meter.finish();
  out.flips = rep.flips;
  out.tree_edges.assign(tri.n_edges(), 0);
  for (Index e = 0; e < tri.n_edges(); ++e) out.tree_edges[e] = uses[e] > 0 ? 1 : 0;
  return out;
}

}  // namespace ifem::intrinsic
