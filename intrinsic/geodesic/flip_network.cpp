// The FlipOut engine (flip_network.h), and the entry points of flip_geodesic.h that run on it
// (shorten(), wedge_angles(), min_wedge_angle()). Walks are by halfedge identity throughout: in a
// Δ-complex a vertex can appear several times around a wedge, so no vertex comparison decides
// anything here.
#include "intrinsic/geodesic/flip_network.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <new>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "intrinsic/core/errors.h"
#include "intrinsic/core/geometry.h"
#include "intrinsic/core/triangle_formulas.h"

namespace ifem::intrinsic::detail {

namespace {

using T = IntrinsicTriangulation;
constexpr double kInf = std::numeric_limits<double>::infinity();

PathStep reversed(const PathStep& s) { return {s.edge, !s.forward}; }

// A wedge edge is flipped when the angle β at its far end is below π by more than this
// (radians): a diamond whose β is π up to round-off (collinear corners, as along a straight
// boundary) would flip into a triangle of zero area, and lengths laid out from it drift.
constexpr double kFlatSlack = 1e-12;

// The step that traverses halfedge h along it.
PathStep step_along(const T& tri, Index h) {
  const Index e = tri.edge(h);
  return {e, tri.edge_halfedge(e) == h};
}

// Sum of corner(x) over the wedge wedge_faces(tri, start, end) would give, in its order (+∞ if
// it would be empty).
// With max_faces > 0, NaN once the walk passes that many faces.
template <class Corner>
double sum_wedge(const T& tri, Index start, Index end, Corner&& corner, Index max_faces = 0) {
  if (start == kInvalidIndex || end == kInvalidIndex) return kInf;
  double a = corner(start);
  Index n = 1;
  for (Index x = start; T::prev(x) != end; ++n) {
    if (max_faces > 0 && n >= max_faces) return std::numeric_limits<double>::quiet_NaN();
    x = tri.twin(T::prev(x));
    if (x == kInvalidIndex || n > tri.n_halfedges()) return kInf;
    a += corner(x);
  }
  return a;
}

}  // namespace

void wedge_faces(const IntrinsicTriangulation& tri, Index start, Index end, std::vector<Index>* w) {
  w->clear();
  if (start == kInvalidIndex || end == kInvalidIndex) return;
  w->push_back(start);
  for (Index x = start; T::prev(x) != end;) {
    x = tri.twin(T::prev(x));
    if (x == kInvalidIndex || static_cast<Index>(w->size()) > tri.n_halfedges()) {
      w->clear();
      return;
    }
    w->push_back(x);
  }
}

double wedge_angle(const IntrinsicTriangulation& tri, Index start, Index end) {
  return sum_wedge(tri, start, end, [&tri](Index h) { return corner_angle(tri, h); });
}

std::pair<Index, Index> joint_wedge_ends(const IntrinsicTriangulation& tri, const PathStep& in,
                                         const PathStep& out, int side) {
  if (side == 0) return {step_halfedge(tri, out), step_halfedge(tri, in)};
  return {step_halfedge(tri, reversed(in)), step_halfedge(tri, reversed(out))};
}

FlipNetwork::FlipNetwork(SignpostTriangulation& st, std::vector<int>& uses,
                         const std::vector<char>* fixed)
    : st_(st), uses_(uses), fixed_(fixed) {
  uses_.resize(st.intrinsic().n_edges(), 0);
  // calloc'ed: zero (not yet computed) and touched only where the curves go
  const auto nh = static_cast<std::size_t>(st.intrinsic().n_halfedges());
  corner_.reset(static_cast<double*>(std::calloc(std::max<std::size_t>(nh, 1), sizeof(double))));
  const auto nv = static_cast<std::size_t>(st.intrinsic().n_vertices());
  fan_.reset(static_cast<unsigned char*>(std::calloc(std::max<std::size_t>(nv, 1), 1)));
  if (!corner_ || !fan_) throw std::bad_alloc();
}

// 0 marks "not computed" (a corner of exactly 0, in a flat face, is merely recomputed).
double FlipNetwork::corner(Index h) {
  double& c = corner_.get()[h];
  if (c == 0.0) c = corner_angle(st_.intrinsic(), h);
  return c;
}

void FlipNetwork::forget_corners(Index e) {
  const T& tri = st_.intrinsic();
  const Index h = tri.edge_halfedge(e);
  for (const Index f : {T::face(h), T::face(tri.twin(h))}) {
    std::fill_n(corner_.get() + 3 * f, 3, 0.0);
  }
}

// Whether v's edges make one closed fan (not on the boundary, not pinched): only then do its
// signposts measure wedges (a pinched vertex's fans share one angle range). Flips keep a
// vertex's fans, so the answer is kept per vertex, from one walk around v the first time:
// the fan closes, and across its largest signpost the directions wrap by exactly that
// halfedge's corner (in one fan of several they jump by the other fans' angles too).
bool FlipNetwork::one_closed_fan(Index v) {
  unsigned char& known = fan_.get()[v];
  if (known == 0) {
    known = 2;
    const T& tri = st_.intrinsic();
    const Index h0 = tri.vertex_halfedge(v);
    if (!st_.is_boundary_vertex(v) && h0 != kInvalidIndex) {
      Index x = h0, top = h0;
      for (Index n = 0; n <= tri.n_halfedges() && x != kInvalidIndex; ++n) {
        if (st_.halfedge_direction(x) > st_.halfedge_direction(top)) top = x;
        x = tri.twin(T::prev(x));
        if (x == h0) break;
      }
      const double theta = st_.vertex_angle_sum(v);
      const double gap =
          st_.halfedge_direction(tri.twin(T::prev(top))) - st_.halfedge_direction(top) + theta;
      if (x == h0 && std::abs(gap - corner(top)) <= 1e-9 * theta) known = 1;
    }
  }
  return known == 1;
}

double FlipNetwork::beta(const std::vector<Index>& w, std::size_t i) {
  return corner(T::prev(w[i - 1])) + corner(T::next(w[i]));
}

// beta(w, i) >= π − kFlatSlack, the same answer, mostly without atan2: from the atan2
// arguments (x_k, y_k) of the two corners (y_k ≥ 0, so each
// corner θ_k = atan2(y_k, x_k) is in [0, π]): sin(θ1 + θ2) = (y1 x2 + x1 y2) / (r1 r2). When
// that cross term, less its rounding bound, exceeds kSure·r1 r2 (r_k ≤ |x_k| + y_k), the sum is
// in (kSure, π − kSure) and beta() (atan2 within an ulp, one rounded add) is below π − kFlatSlack;
// below −kSure·r1 r2 the sum is in (π + kSure, 2π − kSure). In between (within 1e-9 rad of 0 or
// π, or NaN) beta() decides. Measured (callgrind, the icosphere(71) path of ifem_bench
// geodesic): 427 → 242 instructions per test, no test left to beta() (D-147). The corner cache
// is not read first: both corners were cached in 106 of 30,463 tests, and its two loads cost
// more than those tests save (its sum answers as the arguments do where they are sure; D-385).
bool FlipNetwork::beta_at_least_flat(const std::vector<Index>& w, std::size_t i) {
  const Index h1 = T::prev(w[i - 1]), h2 = T::next(w[i]);
  constexpr double kSure = 1e-9, kRound = 1e-15;  // kRound > 4 unit roundoffs
  const T& tri = st_.intrinsic();
  double y1 = 0.0, x1 = 0.0, y2 = 0.0, x2 = 0.0;
  opposite_angle_args(tri.halfedge_length(T::next(h1)), tri.halfedge_length(h1),
                      tri.halfedge_length(T::prev(h1)), &y1, &x1);
  opposite_angle_args(tri.halfedge_length(T::next(h2)), tri.halfedge_length(h2),
                      tri.halfedge_length(T::prev(h2)), &y2, &x2);
  const double p = y1 * x2, q = x1 * y2, cross = p + q;
  const double bound =
      kSure * (std::abs(x1) + y1) * (std::abs(x2) + y2) + kRound * (std::abs(p) + std::abs(q));
  if (cross > bound) return false;
  if (cross < -bound) return true;
  return beta(w, i) >= kPi - kFlatSlack;
}

Index FlipNetwork::new_node(const PathStep& s, Index curve) {
  Node n;
  n.step = s;
  n.curve = curve;
  nodes_.push_back(n);
  ++uses_[s.edge];
  curves_[curve].length += st_.intrinsic().length(s.edge);
  return static_cast<Index>(nodes_.size()) - 1;
}

void FlipNetwork::link(Index a, Index b) {
  if (a != kInvalidIndex) {
    nodes_[a].next = b;
    ++nodes_[a].stamp;
  }
  if (b != kInvalidIndex) nodes_[b].prev = a;
}

Index FlipNetwork::add(const EdgePath& path, Index id, const KnownJoints* known) {
  const T& tri = st_.intrinsic();
  const Index n = static_cast<Index>(path.steps.size());
  const std::string where = "curve " + std::to_string(id) + ": ";
  for (Index i = 0; i < n; ++i) {
    const PathStep& s = path.steps[i];
    if (s.edge < 0 || s.edge >= tri.n_edges()) {
      throw InvalidInput(where + "step " + std::to_string(i) + " has no edge " +
                         std::to_string(s.edge));
    }
    const bool wraps = path.closed && i + 1 == n;
    if ((i + 1 < n || wraps) &&
        step_head(tri, s) != step_tail(tri, path.steps[wraps ? 0 : i + 1])) {
      throw InvalidInput(where + "steps " + std::to_string(i) + " and " +
                         std::to_string(wraps ? 0 : i + 1) + " are not consecutive");
    }
  }
  const Index c = static_cast<Index>(curves_.size());
  curves_.push_back({kInvalidIndex, path.closed, 0.0});
  std::vector<Index> ids;
  for (const PathStep& s : path.steps) {
    ids.push_back(new_node(s, c));
    if (ids.size() > 1) link(ids[ids.size() - 2], ids.back());
  }
  if (!ids.empty()) {
    curves_[c].first = ids.front();
    if (path.closed) link(ids.back(), ids.front());
  }
  for (const Index j : path.pinned) {
    const bool ok = path.closed ? (j >= 0 && j < n) : (j >= 1 && j < n);
    if (!ok) {
      throw InvalidInput(where + "pinned joint " + std::to_string(j) + " out of range");
    }
    nodes_[ids[j == 0 ? n - 1 : j - 1]].pin_head = true;
  }
  if (known != nullptr) {
    constexpr double kStraight = std::numeric_limits<double>::infinity();
    for (Index j = 1; j < std::min(known->straight_below, n); ++j) {
      set_angles(ids[j - 1], {kStraight, kStraight});
    }
    for (const auto& [j, angles] : known->bent) {
      if (j >= 1 && j < n) set_angles(ids[j - 1], angles);
    }
  }
  return c;
}

void FlipNetwork::release_curves() {
  nodes_.clear();
  curves_.clear();
  queue_ = {};
}

void FlipNetwork::drop_curves() {
  for (const Node& n : nodes_) {
    if (n.alive) --uses_[n.step.edge];
  }
  release_curves();
}

bool FlipNetwork::is_joint(Index a) const {
  return a != kInvalidIndex && nodes_[a].alive && nodes_[a].next != kInvalidIndex;
}

std::pair<Index, Index> FlipNetwork::joint_wedge_ends(Index a, int side) const {
  return detail::joint_wedge_ends(st_.intrinsic(), nodes_[a].step, nodes_[nodes_[a].next].step,
                                  side);
}

void FlipNetwork::set_angles(Index a, const Eigen::Vector2d& angles) {
  Node& n = nodes_[a];
  n.angles = angles;
  n.angles_stamp = n.stamp;
  n.angles_known = true;
}

Eigen::Vector2d FlipNetwork::joint_angles(Index a) {
  const Node& n = nodes_[a];
  if (n.angles_known && n.angles_stamp == n.stamp) return n.angles;
  const Eigen::Vector2d angles = walk_joint_angles(a);
  set_angles(a, angles);
  return angles;
}

// The joint's two wedge angles. Inside the surface, the signposts at b give them in O(1) (the
// directions of the two steps differ by the side-0 wedge angle, up to rounding accumulated over
// flips): a joint that is straight by a margin above that rounding needs no walk. A bent joint
// is summed face by face on side 0, as shorten() always did (the same bits), unless side 0
// holds more than kLongWedge faces (a hub of single-source geodesics): then the signposts'
// figure stands.
Eigen::Vector2d FlipNetwork::walk_joint_angles(Index a) {
  constexpr Index kLongWedge = 32;
  constexpr double kMargin = 1e-9;  // radians; signpost rounding is ~1e-13 even at hubs
  const PathStep& in = nodes_[a].step;
  const PathStep& out = nodes_[nodes_[a].next].step;
  if (a != nodes_[a].next && in.edge == out.edge && in.forward != out.forward) return {0.0, 0.0};
  const T& tri = st_.intrinsic();
  const auto [s0, e0] = joint_wedge_ends(a, 0);
  const auto corner = [this](Index h) { return this->corner(h); };
  const Index b = step_head(tri, in);
  if (one_closed_fan(b) && s0 != kInvalidIndex && e0 != kInvalidIndex) {
    const double theta = st_.vertex_angle_sum(b);
    double est = st_.halfedge_direction(tri.twin(e0)) - st_.halfedge_direction(s0);
    if (est < 0.0) est += theta;
    const bool clear = est > kMargin && theta - est > kMargin;  // not a full turn or none
    if (clear && std::min(est, theta - est) >= limit_ + kMargin) return {est, theta - est};
    if (clear) {
      const double side0 = sum_wedge(tri, s0, e0, corner, kLongWedge);
      if (std::isnan(side0)) return {est, theta - est};
      if (std::isfinite(side0)) return {side0, theta - side0};  // as below, the same bits
    }
  }
  const double side0 = sum_wedge(tri, s0, e0, corner);
  if (std::isfinite(side0) && !st_.is_boundary_vertex(b)) {
    return {side0, st_.vertex_angle_sum(b) - side0};  // the two wedges make the whole fan
  }
  const auto [s1, e1] = joint_wedge_ends(a, 1);
  return {side0, sum_wedge(tri, s1, e1, corner)};
}

void FlipNetwork::push_joint(Index a) {
  if (!is_joint(a) || nodes_[a].pin_head) return;
  const double m = joint_angles(a).minCoeff();
  if (m < limit_) queue_.push({m, a, nodes_[a].stamp});
}

bool FlipNetwork::remove_backtrack(Index a) {
  const Index b = nodes_[a].next;
  const PathStep& in = nodes_[a].step;
  const PathStep& out = nodes_[b].step;
  if (a == b || in.edge != out.edge || in.forward == out.forward) return false;
  Curve& c = curves_[nodes_[a].curve];
  const Index p = nodes_[a].prev, n = nodes_[b].next;
  uses_[in.edge] -= 2;
  c.length -= 2.0 * st_.intrinsic().length(in.edge);
  for (const Index x : {a, b}) {
    nodes_[x].alive = false;
    ++nodes_[x].stamp;
  }
  if (c.closed && p == b) {  // a two-step loop back and forth: shrunk to a point
    c.first = kInvalidIndex;
    c.length = 0.0;
    return true;
  }
  if (p != kInvalidIndex) nodes_[p].pin_head = nodes_[p].pin_head || nodes_[b].pin_head;
  link(p, n);
  if (c.first == a || c.first == b) c.first = n;  // open: a was first; loop: any node will do
  push_joint(p);
  return true;
}

// The wedge from start to end, as wedge_faces() gives it, into *w; false when it holds a curve
// edge or a fixed edge, or does not close (the walk stops at the first obstacle: a blocked
// joint at a vertex of high valence is common in single-source geodesics). One walk for both.
bool FlipNetwork::open_wedge(Index start, Index end, std::vector<Index>* w) const {
  w->clear();
  if (start == kInvalidIndex || end == kInvalidIndex) return false;
  const T& tri = st_.intrinsic();
  w->push_back(start);
  for (Index x = start; T::prev(x) != end;) {
    x = tri.twin(T::prev(x));
    if (x == kInvalidIndex || static_cast<Index>(w->size()) > tri.n_halfedges()) return false;
    const Index e = tri.edge(x);
    if (uses_[e] > 0 || (fixed_ != nullptr && (*fixed_)[e] != 0)) return false;
    w->push_back(x);
  }
  return true;
}

// Flips the wedge's interior edges whose angle β at their far end is < π (their diamonds are
// then convex: the wedge angle is < π too) until none is left. Leaves the final wedge in wedge_
// and returns true, or returns false when the wedge holds a curve edge or a fixed edge
// (straightening would cross it), or an edge with β < π that cannot be flipped.
// Each pass scans the wedge from its start for the first edge to flip; a flip at index k
// changes only the faces k − 1 and k, so the next pass resumes at k − 1: the β before it, and
// which of those edges refused to flip, are those of the pass before (same faces, same bits).
// The wedge after a flip is spliced in place when its two faces have one corner at the joint
// (every flip on the benchmark meshes; D-385), else walked again.
bool FlipNetwork::flip_wedge(Index a, int side) {
  const T& tri = st_.intrinsic();
  std::vector<Index>& w = wedge_;
  const auto [start, end] = joint_wedge_ends(a, side);
  if (!open_wedge(start, end, &w)) return false;
  constexpr std::size_t kNone = std::numeric_limits<std::size_t>::max();
  std::size_t from = 1, refused = kNone;  // refused: the first index that refused to flip
  for (std::size_t guard = w.size(); guard > 0 && !w.empty(); --guard) {
    std::size_t flipped = kNone;
    bool spliced = false;  // w already updated for the flip
    for (std::size_t j = from; j < w.size(); ++j) {
      if (beta_at_least_flat(w, j)) continue;
      const Index x = w[j];
      const Index e = tri.edge(x);
      // whether the diamond's other corners (head(x), the third corners of faces j and j − 1)
      // all differ from b = tail(x): then faces j − 1 and j are passed once by the wedge (a
      // face with one corner at b is), and the walk after the flip is known without walking
      const Index b = tri.tail(x);
      const bool once = tri.tail(T::next(x)) != b && tri.tail(T::prev(x)) != b &&
                        tri.tail(T::next(w[j - 1])) != b;
      double measured[2];  // the signposts' two new corners (a third fewer atan2 in corner())
      if (st_.flip_edge(e, measured)) {
        forget_corners(e);
        const Index h = tri.edge_halfedge(e);
        corner_.get()[T::next(tri.twin(h))] = measured[0];
        corner_.get()[T::next(h)] = measured[1];
        flipped = j;
        ++flips_;
        if (on_flip) on_flip(e);
        if (once) {
          // in both flip patterns the new face at b holds w[j − 1]'s side in slot prev(x),
          // followed by w[j + 1]: the walk would give w[0 .. j − 2], prev(x), w[j + 1 ..]
          w[j - 1] = T::prev(x);
          w.erase(w.begin() + static_cast<std::ptrdiff_t>(j));
          spliced = true;
        }
        if (check_splices) check_splice(a, side, j, x, spliced);
        break;
      }
      refused = std::min(refused, j);
    }
    if (flipped == kNone) return refused == kNone && !w.empty();
    from = std::max<std::size_t>(1, flipped - 1);
    if (!spliced) {
      // a Δ-complex wedge may pass a face twice: the prefix is unchanged only if the flip's
      // two faces are not in it
      const Index f0 = T::face(w[flipped - 1]), f1 = T::face(w[flipped]);
      for (std::size_t i = 0; i < from; ++i) {
        if (T::face(w[i]) == f0 || T::face(w[i]) == f1) from = 1;
      }
    }
    if (refused >= from) refused = kNone;  // those are scanned again
    if (spliced) continue;
    const auto [s, t] = joint_wedge_ends(a, side);  // a flip moves halfedges between slots
    wedge_faces(tri, s, t, &w);
  }
  return false;
}

// check_splices: the wedge in wedge_ spliced after the flip of its edge j (halfedge slot x)
// against the walk joint_wedge_ends() gives, and the prefix before j − 1 free of the two
// flipped faces (the pass resumes there).
void FlipNetwork::check_splice(Index a, int side, std::size_t j, Index x, bool spliced) {
  ++(spliced ? spliced_flips : walked_flips);
  if (!spliced) return;
  const T& tri = st_.intrinsic();
  const auto [s, t] = joint_wedge_ends(a, side);
  std::vector<Index> walked;
  wedge_faces(tri, s, t, &walked);
  bool same = walked == wedge_;
  const Index f0 = T::face(x), f1 = T::face(tri.twin(x));  // x holds the new edge
  for (std::size_t i = 0; i + 1 < j; ++i) {
    same = same && T::face(wedge_[i]) != f0 && T::face(wedge_[i]) != f1;
  }
  if (!same) {
    throw std::logic_error("FlipNetwork: the wedge spliced after flip " + std::to_string(flips_) +
                           " differs from the walked one");
  }
}

// Replaces the steps of joint a (a and its next) by the outer boundary of the wedge in wedge_.
void FlipNetwork::reroute(Index a, int side) {
  const T& tri = st_.intrinsic();
  std::vector<PathStep>& chain = chain_;
  chain.clear();
  for (const Index x : wedge_) chain.push_back(step_along(tri, T::next(x)));
  if (side == 0) {  // the chain runs from the outgoing step's head to the incoming step's tail
    std::reverse(chain.begin(), chain.end());
    for (PathStep& c : chain) c = reversed(c);
  }
  const Index b = nodes_[a].next;
  const Index ci = nodes_[a].curve;
  const bool whole = curves_[ci].closed && (a == b || nodes_[a].prev == b);
  const Index p = whole ? kInvalidIndex : nodes_[a].prev;
  const Index n = whole ? kInvalidIndex : nodes_[b].next;
  const bool pin = nodes_[b].pin_head && !whole;
  for (const Index x : {a, b}) {
    if (!nodes_[x].alive) continue;  // a == b: one node
    --uses_[nodes_[x].step.edge];
    curves_[ci].length -= tri.length(nodes_[x].step.edge);
    nodes_[x].alive = false;
    ++nodes_[x].stamp;
  }
  Index last = p, first_new = kInvalidIndex;
  for (const PathStep& s : chain) {
    const Index x = new_node(s, ci);
    if (first_new == kInvalidIndex) first_new = x;
    link(last, x);
    last = x;
  }
  nodes_[last].pin_head = pin;
  link(last, whole ? first_new : n);
  Curve& c = curves_[ci];
  if (whole || c.first == a || c.first == b) c.first = first_new;
  push_joint(p);
  for (Index x = first_new;; x = nodes_[x].next) {
    push_joint(x);
    if (x == last) break;
  }
}

// One FlipOut at joint a (its wedge angles given), on its smaller bent side first; false if both
// are blocked.
bool FlipNetwork::straighten(Index a, const Eigen::Vector2d& angles) {
  if (!is_joint(a) || nodes_[a].pin_head) return false;
  if (remove_backtrack(a)) return true;
  const int first = angles[0] <= angles[1] ? 0 : 1;
  for (const int side : {first, 1 - first}) {
    if (!(angles[side] < limit_)) continue;
    if (!flip_wedge(a, side)) continue;
    reroute(a, side);
    return true;
  }
  return false;
}

Index FlipNetwork::push_all_bends() {
  const std::size_t before = queue_.size();
  for (const Curve& c : curves_) {
    if (c.first == kInvalidIndex) continue;
    Index x = c.first;
    do {
      push_joint(x);
      x = nodes_[x].next;
    } while (x != kInvalidIndex && x != c.first);
  }
  return static_cast<Index>(queue_.size() - before);
}

void FlipNetwork::finish(FlipOutReport& rep) const {
  rep.lengths.clear();
  rep.collapsed_loops.clear();
  rep.final_length = 0.0;
  for (Index ci = 0; ci < n_curves(); ++ci) {
    const EdgePath p = extract(ci);
    const double l = path_length(st_.intrinsic(), p);
    rep.lengths.push_back(l);
    rep.final_length += l;
    if (!p.closed) continue;
    const bool point = p.steps.empty();
    const bool stuck_self_edge =
        p.steps.size() == 1 && wedge_angles(st_.intrinsic(), p, 0).minCoeff() < limit_;
    if (point || stuck_self_edge) rep.collapsed_loops.push_back(ci);
  }
  rep.flips = flips_;
}

void FlipNetwork::run(const FlipOutOptions& options, FlipOutReport& rep) {
  options.validate();
  limit_ = kPi - options.angle_epsilon;
  const Index cap =
      options.max_iterations >= 0 ? options.max_iterations : 10 * st_.intrinsic().n_edges() + 1000;
  rep.initial_length = 0.0;
  for (const Curve& c : curves_) rep.initial_length += c.length;
  auto total = [this] {
    double s = 0.0;
    for (const Curve& c : curves_) s += c.length;
    return s;
  };
  const Index round = std::max<Index>(100, static_cast<Index>(nodes_.size()));
  double mark = rep.initial_length;
  Index since_mark = 0, successes = 0;
  push_all_bends();
  rep.stopped_by = FlipOutStop::kConverged;
  for (bool done = false; !done;) {
    while (!queue_.empty() && !done) {
      const Bend b = queue_.top();
      queue_.pop();
      if (!is_joint(b.node) || nodes_[b.node].stamp != b.stamp || nodes_[b.node].pin_head) continue;
      const Eigen::Vector2d angles = joint_angles(b.node);
      const double m = angles.minCoeff();
      if (!(m < limit_)) continue;
      if (m > b.angle) {  // the key is stale (flips elsewhere opened this joint): requeue
        queue_.push({m, b.node, b.stamp});
        continue;
      }
      if (rep.iterations >= cap) {
        rep.stopped_by = FlipOutStop::kIterationCap;
        done = true;
        break;
      }
      if (!straighten(b.node, angles)) continue;
      ++rep.iterations;
      ++successes;
      if (++since_mark >= round) {
        const double now = total();
        if (mark - now < options.min_relative_decrease * mark) {
          rep.stopped_by = FlipOutStop::kNoProgress;
          done = true;
        }
        mark = now;
        since_mark = 0;
      }
    }
    if (done) break;
    const Index bent = push_all_bends();  // bends opened by flips elsewhere, and blocked ones
    if (bent == 0) break;
    if (successes == 0) {
      rep.stopped_by = FlipOutStop::kBlocked;
      rep.blocked_joints = bent;
      break;
    }
    successes = 0;
  }
  queue_ = {};
  finish(rep);
}

FlipNetwork::KnownJoints FlipNetwork::known_joints(Index ci) {
  KnownJoints k;
  const Index first = curves_[ci].first;
  if (first == kInvalidIndex || curves_[ci].closed) return k;
  Index j = 1;
  for (Index x = first; nodes_[x].next != kInvalidIndex; x = nodes_[x].next, ++j) {
    const Eigen::Vector2d angles = joint_angles(x);
    if (angles.minCoeff() < limit_) k.bent.emplace_back(j, angles);
  }
  k.straight_below = j;
  return k;
}

EdgePath FlipNetwork::extract(Index ci) const {
  EdgePath p;
  p.closed = curves_[ci].closed;
  const Index first = curves_[ci].first;
  if (first == kInvalidIndex) return p;
  Index x = first;
  do {
    p.steps.push_back(nodes_[x].step);
    if (nodes_[x].pin_head && nodes_[x].next != kInvalidIndex) {
      const Index k = static_cast<Index>(p.steps.size());
      p.pinned.push_back(nodes_[x].next == first ? 0 : k);
    }
    x = nodes_[x].next;
  } while (x != kInvalidIndex && x != first);
  std::sort(p.pinned.begin(), p.pinned.end());
  return p;
}

}  // namespace ifem::intrinsic::detail

namespace ifem::intrinsic {

// ---------------------------------------------------------------------------------------------
// The public entry points of flip_geodesic.h that run on the engine

namespace {
constexpr double kNoWedge = std::numeric_limits<double>::infinity();
}  // namespace

Eigen::Vector2d wedge_angles(const IntrinsicTriangulation& tri, const EdgePath& path, Index i) {
  const Index n = static_cast<Index>(path.steps.size());
  const PathStep& in = path.steps[i == 0 ? n - 1 : i - 1];
  const PathStep& out = path.steps[i];
  if (n > 1 && in.edge == out.edge && in.forward != out.forward) return {0.0, 0.0};
  const auto [s0, e0] = detail::joint_wedge_ends(tri, in, out, 0);
  const auto [s1, e1] = detail::joint_wedge_ends(tri, in, out, 1);
  return {detail::wedge_angle(tri, s0, e0), detail::wedge_angle(tri, s1, e1)};
}

double min_wedge_angle(const IntrinsicTriangulation& tri, const EdgePath& path) {
  double m = kNoWedge;
  const Index n = static_cast<Index>(path.steps.size());
  for (Index i = path.closed ? 0 : 1; i < n; ++i) {
    if (std::find(path.pinned.begin(), path.pinned.end(), i) != path.pinned.end()) continue;
    m = std::min(m, wedge_angles(tri, path, i).minCoeff());
  }
  return m;
}

FlipOutReport shorten(SignpostTriangulation& st, std::vector<EdgePath>& paths,
                      const FlipOutOptions& options, const std::vector<char>* fixed_edges) {
  options.validate();
  const Index ne = st.intrinsic().n_edges();
  if (fixed_edges != nullptr && static_cast<Index>(fixed_edges->size()) != ne) {
    throw InvalidInput("shorten: fixed_edges has " + std::to_string(fixed_edges->size()) +
                       " flags for " + std::to_string(ne) + " edges");
  }
  std::vector<int> uses(ne, 0);
  detail::FlipNetwork net(st, uses, fixed_edges);
  for (std::size_t c = 0; c < paths.size(); ++c) net.add(paths[c], static_cast<Index>(c));
  FlipOutReport rep;
  net.run(options, rep);
  for (std::size_t c = 0; c < paths.size(); ++c) paths[c] = net.extract(static_cast<Index>(c));
  return rep;
}

FlipOutReport shorten(SignpostTriangulation& st, EdgePath& path, const FlipOutOptions& options) {
  std::vector<EdgePath> one{std::move(path)};
  const FlipOutReport rep = shorten(st, one, options);
  path = std::move(one.front());
  return rep;
}

}  // namespace ifem::intrinsic
