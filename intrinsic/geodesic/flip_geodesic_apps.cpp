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

// Whether a path through vertex w (entering along halfedge `in`, leaving along `out_h`, both
// at w: in arrives at w, out_h leaves it) goes straight there: one of its two wedge angles is π
// within kStraightTol (radians), read from the signposts. False at a boundary or pinched vertex
// (there the signposts measure no wedge): a turn.
constexpr double kStraightTol = 1e-5;
bool straight_at(const SignpostTriangulation& st, Index in, Index out_h,
                 const std::vector<char>& pinched) {
  const T& tri = st.intrinsic();
  const Index w = tri.tail(out_h);
  if (pinched[w] || st.is_boundary_vertex(w) || tri.twin(in) == kInvalidIndex) return false;
  const double theta = st.vertex_angle_sum(w);
  double a = st.halfedge_direction(out_h) - st.halfedge_direction(tri.twin(in));
  if (a < 0.0) a += theta;
  return std::abs(a - kPi) <= kStraightTol || std::abs(theta - a - kPi) <= kStraightTol;
}

// The length of the path's last straight run: back from its end to the last vertex where it
// turns (or to its start).
double straight_run(const SignpostTriangulation& st, const EdgePath& path,
                    const std::vector<char>& pinched) {
  const T& tri = st.intrinsic();
  double r = 0.0;
  for (std::size_t i = path.steps.size(); i-- > 0;) {
    r += tri.length(path.steps[i].edge);
    if (i == 0) break;
    const Index in = step_halfedge(tri, path.steps[i - 1]);
    const Index out_h = step_halfedge(tri, path.steps[i]);
    if (in == kInvalidIndex || out_h == kInvalidIndex || !straight_at(st, in, out_h, pinched)) {
      break;
    }
  }
  return r;
}

// What the search keeps of an accepted vertex for unfolded_key(), in one place (it is read at
// every offer: two per flip).
struct Reached {
  double length = 0.0;  // of its geodesic
  double run = 0.0;     // of its geodesic's last straight run (0: the source)
  PathStep last;        // its geodesic's last step (edge kInvalidIndex: the source)
};

// The priority of reaching a vertex over edge e from accepted vertex u: the straight distance
// from the start p of u's last straight run (ending at u) to it, laid out across the smaller
// wedge at u between the run and e (the length of the geodesic from p in that wedge when no
// vertex lies between them), plus the length up to p. A wedge ≥ π, or a vertex whose signposts
// measure no wedge (boundary, pinched): the edge path's length through u. A better order and
// choice of parent than the edge path's length alone: behind a vertex of positive curvature it
// tells the side (docs/decisions.md D-144).
double unfolded_key(const SignpostTriangulation& st, const std::vector<char>& pinched, Index e,
                    Index u, const Reached& at) {
  const T& tri = st.intrinsic();
  const double l = tri.length(e), d = at.length, r = at.run;
  if (at.last.edge == kInvalidIndex || r <= 0.0 || pinched[u] || st.is_boundary_vertex(u)) {
    return d + l;
  }
  const Index back = step_halfedge(tri, {at.last.edge, !at.last.forward});
  const Index h = tri.edge_halfedge(e);
  const Index out_h = tri.tail(h) == u ? h : tri.twin(h);
  if (back == kInvalidIndex || out_h == kInvalidIndex) return d + l;
  const double theta = st.vertex_angle_sum(u);
  double a = st.halfedge_direction(out_h) - st.halfedge_direction(back);
  if (a < 0.0) a += theta;
  a = std::min(a, theta - a);
  if (!(a < kPi)) return d + l;
  return d - r + std::sqrt(std::max(0.0, r * r + l * l - 2.0 * r * l * std::cos(a)));
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

namespace {

// Other starts tried for a vertex (docs/decisions.md D-144): when its run ends blocked, the
// geodesics of up to kOtherStarts other accepted neighbours (best unfolded key first), each
// followed by the edge to the vertex, until one converges; when it converges, the neighbours
// whose key is within kTieRelative of the length found (the other side of a vertex of positive
// curvature, a near-tie the first start cannot tell). The shortest result wins.
constexpr int kOtherStarts = 8;
constexpr double kTieRelative = 1e-5;

// single_source_geodesics()'s state: the search's queue and the accepted vertices' paths.
class SingleSource {
 public:
  SingleSource(SignpostTriangulation& st, Index source, const FlipOutOptions& options)
      : st_(st),
        tri_(st.intrinsic()),
        options_(options),
        source_(source),
        accepted_(tri_.n_vertices(), 0),
        reached_(tri_.n_vertices()),
        pinched_(pinched_vertices(tri_)),
        bent_(tri_.n_vertices()),
        uses_(tri_.n_edges(), 0),
        net_(st, uses_, nullptr) {
    out_.length = Eigen::VectorXd::Constant(tri_.n_vertices(), kInf);
    out_.paths.resize(tri_.n_vertices());
    net_.on_flip = [this](Index e) {  // a flip may join the accepted region to a new vertex
      ++out_.flips;
      const Index h = tri_.edge_halfedge(e);
      offer(e, tri_.tail(h), tri_.head(h));
      offer(e, tri_.head(h), tri_.tail(h));
    };
  }

  SingleSourceGeodesics solve(const ProgressCallback& on_progress) {
    accept(source_, EdgePath{}, 0.0);
    ProgressMeter meter(on_progress, "single-source geodesics", double(tri_.n_vertices()));
    double n_accepted = 1.0;
    while (!queue_.empty()) {
      const Entry top = queue_.top();
      queue_.pop();
      if (accepted_[top.v]) continue;
      const PathStep last = step_from(top.edge, top.parent, top.v);
      if (last.edge == kInvalidIndex) continue;  // flipped since it was offered
      EdgePath path = out_.paths[top.parent];
      path.steps.push_back(last);
      FlipOutReport rep = shorten_from(top.parent, top.v, &path);
      try_other_starts(top.v, top.parent, &path, &rep);
      bent_[top.v] = net_.known_joints(0).bent;
      net_.release_curves();  // the accepted path stays counted: an obstacle from now on
      if (rep.stopped_by != FlipOutStop::kConverged) ++out_.blocked;
      accept(top.v, std::move(path), rep.final_length);
      meter.update(++n_accepted);
    }
    meter.finish();
    out_.tree_edges.assign(tri_.n_edges(), 0);
    for (Index e = 0; e < tri_.n_edges(); ++e) out_.tree_edges[e] = uses_[e] > 0 ? 1 : 0;
    return std::move(out_);
  }

 private:
  struct Entry {
    double d;
    Index v, parent, edge;
    bool operator>(const Entry& o) const { return d > o.d; }
  };

  void offer(Index e, Index from, Index to) {
    if (accepted_[from] && !accepted_[to]) {
      queue_.push({unfolded_key(st_, pinched_, e, from, reached_[from]), to, from, e});
    }
  }

  void accept(Index v, EdgePath path, double length) {
    Reached& at = reached_[v];
    at.length = length;
    at.run = straight_run(st_, path, pinched_);
    if (!path.steps.empty()) at.last = path.steps.back();
    out_.paths[v] = std::move(path);
    accepted_[v] = 1;
    out_.length[v] = length;
    for_each_edge_at(tri_, v, pinched_[v] != 0, [&](Index e, Index u) { offer(e, v, u); });
  }

  // The step along edge e from a to b, or edge kInvalidIndex when e no longer joins them.
  PathStep step_from(Index e, Index a, Index b) const {
    const Index h = tri_.edge_halfedge(e);
    if (tri_.tail(h) == a && tri_.head(h) == b) return {e, true};
    if (tri_.head(h) == a && tri_.tail(h) == b) return {e, false};
    return {kInvalidIndex, true};
  }

  // FlipOut of *path (the geodesic of accepted vertex `from` and one edge to v) with the accepted
  // paths as obstacles, then a shorter accepted prefix spliced in and shortened again (at most
  // kMaxSplices runs). The result is the network's curve 0, counted in uses_.
  FlipOutReport shorten_from(Index from, Index v, EdgePath* path) {
    FlipOutReport rep;
    detail::FlipNetwork::KnownJoints known;
    for (int attempt = 0; attempt < kMaxSplices; ++attempt) {
      // the prefix's joints are as its run left them: only their bent ones need a look
      known.straight_below = static_cast<Index>(out_.paths[from].steps.size());
      known.bent = bent_[from];
      net_.add(*path, v, &known);
      rep = {};
      net_.run(options_, rep);
      *path = net_.extract(0);
      out_.iterations += rep.iterations;
      // the last attempt's result stands (the network's curve, counted as an obstacle)
      if (attempt + 1 == kMaxSplices ||
          !splice_shorter_prefix(tri_, out_, accepted_, path, &from)) {
        break;
      }
      net_.drop_curves();
    }
    return rep;
  }

  // The other starts (see kOtherStarts) for v, whose geodesic from `parent` is *path (the
  // network's curve 0, counted); *path and *rep become the shortest result, left as curve 0.
  void try_other_starts(Index v, Index parent, EdgePath* path, FlipOutReport* rep) {
    const bool converged = rep->stopped_by == FlipOutStop::kConverged;
    std::vector<std::pair<double, Index>> starts;  // (unfolded key, index in edges)
    std::vector<Index> edges;                      // to v
    for_each_edge_at(tri_, v, pinched_[v] != 0, [&](Index e, Index u) {
      if (!accepted_[u] || u == parent) return;
      const double key = unfolded_key(st_, pinched_, e, u, reached_[u]);
      if (converged && !(key < rep->final_length * (1.0 + kTieRelative))) return;
      starts.push_back({key, static_cast<Index>(edges.size())});
      edges.push_back(e);
    });
    if (starts.empty()) return;
    std::sort(starts.begin(), starts.end());
    if (static_cast<int>(starts.size()) > kOtherStarts) starts.resize(kOtherStarts);
    net_.release_curves();  // the best path so far stays counted: an obstacle to the trials
    for (const auto& [key, k] : starts) {
      const Index e = edges[static_cast<std::size_t>(k)];
      const Index h = tri_.edge_halfedge(e);
      const Index u = tri_.tail(h) == v ? tri_.head(h) : tri_.tail(h);
      const PathStep last = step_from(e, u, v);
      if (last.edge == kInvalidIndex || !accepted_[u]) continue;  // flipped by a trial
      EdgePath trial = out_.paths[u];
      trial.steps.push_back(last);
      const FlipOutReport r = shorten_from(u, v, &trial);
      if (!(r.final_length < rep->final_length)) {
        net_.drop_curves();
        continue;
      }
      for (const PathStep& s : path->steps) --uses_[s.edge];  // the old best: no obstacle now
      *path = std::move(trial);
      *rep = r;
      net_.release_curves();
      if (r.stopped_by == FlipOutStop::kConverged) break;
    }
    for (const PathStep& s : path->steps) --uses_[s.edge];
    net_.add(*path, v);  // counted again, and the network's curve 0 for known_joints()
  }

  SignpostTriangulation& st_;
  const T& tri_;
  const FlipOutOptions& options_;
  Index source_;
  SingleSourceGeodesics out_;
  std::vector<char> accepted_;
  std::vector<Reached> reached_;  // per accepted vertex
  std::vector<char> pinched_;
  // per accepted vertex, the joints of its path left bent (blocked) by its run
  std::vector<std::vector<std::pair<Index, Eigen::Vector2d>>> bent_;
  std::vector<int> uses_;
  detail::FlipNetwork net_;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> queue_;
};

}  // namespace

SingleSourceGeodesics single_source_geodesics(SignpostTriangulation& st, Index source,
                                              const FlipOutOptions& options,
                                              const ProgressCallback& on_progress) {
  options.validate();
  const Index nv = st.intrinsic().n_vertices();
  if (source < 0 || source >= nv) {
    throw InvalidInput("single_source_geodesics: source " + std::to_string(source) +
                       " is out of range [0, " + std::to_string(nv) + ")");
  }
  return SingleSource(st, source, options).solve(on_progress);
}

}  // namespace ifem::intrinsic
