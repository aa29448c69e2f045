// FlipOut geodesic paths (flip_geodesic.h). Walks are by halfedge identity throughout: in a
// Δ-complex a vertex can appear several times around a wedge, so no vertex comparison decides
// anything here.
#include "intrinsic/geodesic/flip_geodesic.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <queue>
#include <string>
#include <utility>

#include "intrinsic/core/errors.h"
#include "intrinsic/core/geometry.h"

namespace ifem::intrinsic {

namespace {

using T = IntrinsicTriangulation;
constexpr double kInf = std::numeric_limits<double>::infinity();

PathStep reversed(const PathStep& s) { return {s.edge, !s.forward}; }

// The step that traverses halfedge h forward (along h) or backward (against h).
PathStep step_of(const T& tri, Index h, bool along) {
  const Index e = tri.edge(h);
  const bool is_rep = tri.edge_halfedge(e) == h;
  return {e, along ? is_rep : !is_rep};
}

// The faces swept counter-clockwise around a vertex b from the edge of `start` (a halfedge
// leaving b) to the edge of `end` (a halfedge entering b), each given by its halfedge x leaving
// b (face(x) spans from x to prev(x)). Empty if either is invalid, a boundary side is met
// first, or the walk does not close.
std::vector<Index> wedge_faces(const T& tri, Index start, Index end) {
  if (start == kInvalidIndex || end == kInvalidIndex) return {};
  std::vector<Index> w{start};
  for (Index x = start; T::prev(x) != end;) {
    x = tri.twin(T::prev(x));
    if (x == kInvalidIndex || static_cast<Index>(w.size()) > tri.n_halfedges()) return {};
    w.push_back(x);
  }
  return w;
}

double wedge_angle(const T& tri, const std::vector<Index>& w) {
  if (w.empty()) return kInf;
  double a = 0.0;
  for (const Index x : w) a += corner_angle(tri, x);
  return a;
}

bool is_backtrack(const EdgePath& path, Index i) {
  const PathStep& a = path.steps[i - 1];
  const PathStep& b = path.steps[i];
  return a.edge == b.edge && a.forward != b.forward;
}

// The wedge of side `side` at path vertex i (see wedge_angles()): side 0 sweeps from the
// outgoing step to the incoming one, side 1 from the reversed incoming step to the reversed
// outgoing one.
std::vector<Index> path_wedge(const T& tri, const EdgePath& path, Index i, int side) {
  const PathStep& in = path.steps[i - 1];
  const PathStep& out = path.steps[i];
  if (side == 0) return wedge_faces(tri, step_halfedge(tri, out), step_halfedge(tri, in));
  return wedge_faces(tri, step_halfedge(tri, reversed(in)), step_halfedge(tri, reversed(out)));
}

struct FlipOutState {
  SignpostTriangulation& st;
  EdgePath& path;
  std::vector<int> uses;  // #E: how many steps of the path run along each edge
  Index flips = 0;
};

// Angle inside the wedge at the far end of its interior edge w[i] (0 < i < #w).
double beta(const T& tri, const std::vector<Index>& w, std::size_t i) {
  return corner_angle(tri, T::prev(w[i - 1])) + corner_angle(tri, T::next(w[i]));
}

// Flips the wedge's interior edges whose angle β at their far end is < π (their diamonds are
// then convex: the wedge angle is < π too) until none is left. Returns the final wedge, or an
// empty one when an edge with β < π is blocked (a path edge, or refused by flip_edge).
std::vector<Index> flip_wedge(FlipOutState& s, Index i, int side) {
  const T& tri = s.st.intrinsic();
  for (Index guard = 0; guard <= tri.n_edges(); ++guard) {
    const std::vector<Index> w = path_wedge(tri, s.path, i, side);
    if (w.empty()) return {};
    bool flipped = false, blocked = false;
    for (std::size_t j = 1; j < w.size() && !flipped; ++j) {
      if (beta(tri, w, j) >= kPi) continue;
      const Index e = tri.edge(w[j]);
      if (s.uses[e] == 0 && s.st.flip_edge(e)) {
        flipped = true;
        ++s.flips;
      } else {
        blocked = true;
      }
    }
    if (!flipped) return blocked ? std::vector<Index>{} : w;
  }
  return {};
}

// Replaces steps i−1 and i by the outer boundary of wedge w (side `side`).
void reroute(FlipOutState& s, Index i, int side, const std::vector<Index>& w) {
  const T& tri = s.st.intrinsic();
  std::vector<PathStep> chain;
  for (const Index x : w) chain.push_back(step_of(tri, T::next(x), true));
  if (side == 0) {  // the chain runs from the outgoing step's head to the incoming step's tail
    std::reverse(chain.begin(), chain.end());
    for (PathStep& c : chain) c = reversed(c);
  }
  auto& st = s.path.steps;
  --s.uses[st[i - 1].edge];
  --s.uses[st[i].edge];
  for (const PathStep& c : chain) ++s.uses[c.edge];
  st.erase(st.begin() + (i - 1), st.begin() + (i + 1));
  st.insert(st.begin() + (i - 1), chain.begin(), chain.end());
}

// Removes a back-and-forth along one edge (steps i−1, i are one edge both ways).
bool remove_backtrack(FlipOutState& s, Index i) {
  if (!is_backtrack(s.path, i)) return false;
  --s.uses[s.path.steps[i].edge];
  --s.uses[s.path.steps[i].edge];
  s.path.steps.erase(s.path.steps.begin() + (i - 1), s.path.steps.begin() + (i + 1));
  return true;
}

struct Bend {
  double angle;
  Index vertex;
  int side;
  bool operator>(const Bend& o) const { return angle > o.angle; }
};

// Wedges bent by more than ε, smallest angle first.
std::vector<Bend> bends(const T& tri, const EdgePath& path, double limit) {
  std::vector<Bend> out;
  for (Index i = 1; i < static_cast<Index>(path.steps.size()); ++i) {
    const Eigen::Vector2d a = wedge_angles(tri, path, i);
    for (int side = 0; side < 2; ++side) {
      if (a[side] < limit) out.push_back({a[side], i, side});
    }
  }
  std::sort(out.begin(), out.end(), [](const Bend& x, const Bend& y) { return x.angle < y.angle; });
  return out;
}

// One FlipOut at the smallest bend that can be straightened; false if every bend is blocked.
bool flip_out_once(FlipOutState& s, const std::vector<Bend>& todo) {
  for (const Bend& b : todo) {
    if (remove_backtrack(s, b.vertex)) return true;
    const std::vector<Index> w = flip_wedge(s, b.vertex, b.side);
    if (w.empty()) continue;
    reroute(s, b.vertex, b.side, w);
    return true;
  }
  return false;
}

void check_consecutive(const T& tri, const EdgePath& path) {
  for (std::size_t i = 0; i < path.steps.size(); ++i) {
    const PathStep& s = path.steps[i];
    if (s.edge < 0 || s.edge >= tri.n_edges()) {
      throw InvalidInput("shorten: path step " + std::to_string(i) + " has no edge " +
                         std::to_string(s.edge));
    }
    if (i > 0 && step_head(tri, path.steps[i - 1]) != step_tail(tri, s)) {
      throw InvalidInput("shorten: path steps " + std::to_string(i - 1) + " and " +
                         std::to_string(i) + " are not consecutive");
    }
  }
}

}  // namespace

Index step_halfedge(const IntrinsicTriangulation& tri, const PathStep& step) {
  const Index h = tri.edge_halfedge(step.edge);
  return step.forward ? h : tri.twin(h);
}

Index step_tail(const IntrinsicTriangulation& tri, const PathStep& step) {
  const Index h = tri.edge_halfedge(step.edge);
  return step.forward ? tri.tail(h) : tri.head(h);
}

Index step_head(const IntrinsicTriangulation& tri, const PathStep& step) {
  const Index h = tri.edge_halfedge(step.edge);
  return step.forward ? tri.head(h) : tri.tail(h);
}

double path_length(const IntrinsicTriangulation& tri, const EdgePath& path) {
  double l = 0.0;
  for (const PathStep& s : path.steps) l += tri.length(s.edge);
  return l;
}

EdgePath shortest_edge_path(const SignpostTriangulation& st, Index a, Index b) {
  const T& tri = st.intrinsic();
  const Index nv = tri.n_vertices();
  if (a < 0 || a >= nv || b < 0 || b >= nv || a == b) {
    throw InvalidInput("shortest_edge_path: need two distinct vertices in [0, " +
                       std::to_string(nv) + "), got " + std::to_string(a) + " and " +
                       std::to_string(b));
  }
  // adjacency over oriented edges: every edge both ways (boundary edges included)
  std::vector<std::vector<PathStep>> out(nv);
  for (Index e = 0; e < tri.n_edges(); ++e) {
    const Index h = tri.edge_halfedge(e);
    out[tri.tail(h)].push_back({e, true});
    out[tri.head(h)].push_back({e, false});
  }
  std::vector<double> dist(nv, kInf);
  std::vector<PathStep> via(nv);
  using Item = std::pair<double, Index>;
  std::priority_queue<Item, std::vector<Item>, std::greater<Item>> queue;
  dist[a] = 0.0;
  queue.push({0.0, a});
  while (!queue.empty()) {
    const auto [d, v] = queue.top();
    queue.pop();
    if (d > dist[v]) continue;
    if (v == b) break;
    for (const PathStep& s : out[v]) {
      const Index u = step_head(tri, s);
      const double du = d + tri.length(s.edge);
      if (du < dist[u]) {
        dist[u] = du;
        via[u] = s;
        queue.push({du, u});
      }
    }
  }
  if (!std::isfinite(dist[b])) {
    throw InvalidInput("shortest_edge_path: vertex " + std::to_string(b) +
                       " is not reachable from vertex " + std::to_string(a) +
                       " (different connected components)");
  }
  EdgePath path;
  for (Index v = b; v != a; v = step_tail(tri, via[v])) path.steps.push_back(via[v]);
  std::reverse(path.steps.begin(), path.steps.end());
  return path;
}

Eigen::Vector2d wedge_angles(const IntrinsicTriangulation& tri, const EdgePath& path, Index i) {
  if (is_backtrack(path, i)) return {0.0, 0.0};
  return {wedge_angle(tri, path_wedge(tri, path, i, 0)),
          wedge_angle(tri, path_wedge(tri, path, i, 1))};
}

double min_wedge_angle(const IntrinsicTriangulation& tri, const EdgePath& path) {
  double m = kInf;
  for (Index i = 1; i < static_cast<Index>(path.steps.size()); ++i) {
    m = std::min(m, wedge_angles(tri, path, i).minCoeff());
  }
  return m;
}

void FlipOutOptions::validate() const {
  if (!(angle_epsilon >= 0.0 && angle_epsilon < kPi)) {
    throw InvalidInput("FlipOutOptions::angle_epsilon must be in [0, π), got " +
                       std::to_string(angle_epsilon));
  }
  if (max_iterations < -1) {
    throw InvalidInput("FlipOutOptions::max_iterations must be ≥ −1 (−1: automatic), got " +
                       std::to_string(max_iterations));
  }
  if (!(min_relative_decrease >= 0.0) || !std::isfinite(min_relative_decrease)) {
    throw InvalidInput("FlipOutOptions::min_relative_decrease must be finite and ≥ 0, got " +
                       std::to_string(min_relative_decrease));
  }
}

FlipOutReport shorten(SignpostTriangulation& st, EdgePath& path, const FlipOutOptions& options) {
  options.validate();
  const T& tri = st.intrinsic();
  check_consecutive(tri, path);
  FlipOutState s{st, path, std::vector<int>(tri.n_edges(), 0)};
  for (const PathStep& p : path.steps) ++s.uses[p.edge];
  const Index cap =
      options.max_iterations >= 0 ? options.max_iterations : 10 * tri.n_edges() + 1000;
  FlipOutReport rep;
  rep.initial_length = path_length(tri, path);
  double length = rep.initial_length;
  for (;;) {
    const std::vector<Bend> todo = bends(tri, path, kPi - options.angle_epsilon);
    if (todo.empty()) {
      rep.stopped_by = FlipOutStop::kConverged;
      break;
    }
    if (rep.iterations >= cap) {
      rep.stopped_by = FlipOutStop::kIterationCap;
      break;
    }
    if (!flip_out_once(s, todo)) {
      rep.stopped_by = FlipOutStop::kNoProgress;
      break;
    }
    ++rep.iterations;
    const double next = path_length(tri, path);
    const bool small = length - next < options.min_relative_decrease * length;
    length = next;
    if (small) {
      rep.stopped_by = FlipOutStop::kNoProgress;
      break;
    }
  }
  rep.final_length = length;
  rep.flips = s.flips;
  return rep;
}

std::vector<Eigen::Vector3d> path_polyline(const SignpostTriangulation& st, const EdgePath& path) {
  const T& tri = st.intrinsic();
  std::vector<Eigen::Vector3d> line;
  if (path.steps.empty()) return line;
  for (const PathStep& s : path.steps) {
    std::vector<SurfacePoint> pts = st.trace_halfedge(tri.edge_halfedge(s.edge));
    if (!s.forward) std::reverse(pts.begin(), pts.end());
    for (std::size_t k = line.empty() ? 0 : 1; k < pts.size(); ++k) {
      line.push_back(st.position(pts[k]));
    }
  }
  return line;
}

}  // namespace ifem::intrinsic
