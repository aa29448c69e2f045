// Straight segments across one vertex's wedge made an edge by flips (straight_insert.h).
#include "intrinsic/geodesic/straight_insert.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "intrinsic/core/geometry.h"

namespace ifem::intrinsic::detail {
long g_plan_dbg[24];

namespace {

using T = IntrinsicTriangulation;
constexpr double kBeyond = 1e-6;  // relative margin of "strictly beyond the line" (≈ radians)

double cross(double ax, double ay, double bx, double by) { return ax * by - ay * bx; }

}  // namespace

int plan_fan_segment(const SignpostTriangulation& st, Index h_up, Index h_uw,
                     const std::vector<int>& uses, FanSegment* out) {
  const T& tri = st.intrinsic();
  const Index u = tri.tail(h_up);
  if (st.is_boundary_vertex(u) || tri.tail(h_uw) != u) { ++g_plan_dbg[1]; return false; }
  FanSegment& s = *out;
  s.u = u, s.p = tri.head(h_up), s.w = tri.head(h_uw);
  if (s.p == s.w || s.p == u || s.w == u) { ++g_plan_dbg[2]; return false; }
  s.spokes.clear(), s.x.clear(), s.y.clear();
  // walk counter-clockwise from u→p to u→w (x → twin(prev(x))), laying the far ends out
  double phi = 0.0;
  bool spoke_used = false;
  Index x = h_up;
  const double r = tri.halfedge_length(h_up);
  s.x.push_back(r), s.y.push_back(0.0);
  const Index guard = tri.n_halfedges();
  for (Index k = 0; k <= guard; ++k) {
    phi += corner_angle(tri, x);
    if (!(phi < kPi)) { ++g_plan_dbg[3]; return false; }
    x = tri.twin(T::prev(x));
    if (x == kInvalidIndex) { ++g_plan_dbg[4]; return false; }
    const double l = tri.halfedge_length(x);
    s.x.push_back(l * std::cos(phi)), s.y.push_back(l * std::sin(phi));
    if (x == h_uw) break;
    const Index v = tri.head(x), e = tri.edge(x);
    if (v == u || v == s.p || v == s.w) { ++g_plan_dbg[5]; return false; }
    if (uses[static_cast<std::size_t>(e)] > 0) spoke_used = true;
    s.spokes.push_back(e);
    if (k == guard) { ++g_plan_dbg[6]; return false; }
  }
  if (x != h_uw) { ++g_plan_dbg[7]; return false; }
  const double px = s.x.front(), py = s.y.front(), wx = s.x.back(), wy = s.y.back();
  const double dx = wx - px, dy = wy - py;
  s.length = std::hypot(dx, dy);
  if (!(s.length > 0.0)) { ++g_plan_dbg[8]; return false; }
  // the direction at p: p→u turned by the angle at p from (u − p) to (w − p), counter-clockwise
  const double turn = std::atan2(cross(-px, -py, dx, dy), (-px) * dx + (-py) * dy);
  s.direction_at_p = st.wrap_direction(s.p, st.halfedge_direction(tri.twin(h_up)) + turn);
  // at w: w→u turned by the angle at w from (u − w) to (p − w), counter-clockwise
  const double turn_w = std::atan2(cross(-wx, -wy, -dx, -dy), (-wx) * (-dx) + (-wy) * (-dy));
  if (tri.twin(h_uw) == kInvalidIndex || tri.twin(h_up) == kInvalidIndex) { ++g_plan_dbg[11]; return false; }
  s.direction_at_w = st.wrap_direction(s.w, st.halfedge_direction(tri.twin(h_uw)) + turn_w);
  if (spoke_used) return 1;
  // every spoke's far end strictly beyond the line p–w, on the side away from u
  const double side_u = cross(dx, dy, -px, -py);  // u at the origin
  const double scale = s.length * std::max({r, tri.halfedge_length(h_uw), s.length});
  if (!(std::abs(side_u) > kBeyond * scale)) { ++g_plan_dbg[9]; return 1; }
  for (std::size_t k = 1; k + 1 < s.x.size(); ++k) {
    const double c = cross(dx, dy, s.x[k] - px, s.y[k] - py);
    if (!(c * (side_u > 0.0 ? -1.0 : 1.0) > kBeyond * scale)) { ++g_plan_dbg[10];
      if (std::getenv("IFEM_SS_DEBUG2")) { std::fprintf(stderr, "fail k=%zu of %zu side_u %g c %g:", k, s.x.size(), side_u, c); for (std::size_t j = 0; j < s.x.size(); ++j) std::fprintf(stderr, " (%.3f,%.3f)", s.x[j], s.y[j]); std::fprintf(stderr, "\n"); }
      return 1; }
  }
  if (s.spokes.empty()) s.closing = tri.edge(T::next(h_up));
  return 2;
}

bool fan_ear_convex(const FanSegment& plan, std::size_t a, std::size_t b, std::size_t c) {
  // b and u (the origin) strictly on opposite sides of the line a–c
  const double ax = plan.x[a], ay = plan.y[a];
  const double cx = plan.x[c] - ax, cy = plan.y[c] - ay;
  const double sb = cross(cx, cy, plan.x[b] - ax, plan.y[b] - ay);
  const double su = cross(cx, cy, -ax, -ay);
  const double scale = std::hypot(cx, cy) * std::max(std::hypot(ax, ay), std::hypot(cx, cy));
  return sb * su < 0.0 && std::abs(sb) > kBeyond * scale && std::abs(su) > kBeyond * scale;
}

namespace {

// The layout position of vertex v in the strip, or nullptr.
const Eigen::Vector2d* strip_at(const StripSegment& s, Index v) {
  for (const auto& [id, pos] : s.at) {
    if (id == v) return &pos;
  }
  return nullptr;
}

// Records v at pos; false when v is already at another place (a strip through a vertex twice).
bool strip_put(StripSegment* s, Index v, const Eigen::Vector2d& pos) {
  if (const Eigen::Vector2d* q = strip_at(*s, v)) return (*q - pos).norm() <= 1e-9 * pos.norm();
  s->at.push_back({v, pos});
  return true;
}

// Whether a and b lie strictly on opposite sides of the line from the origin along d.
bool straddles(const Eigen::Vector2d& d, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  const double sa = cross(d.x(), d.y(), a.x(), a.y()), sb = cross(d.x(), d.y(), b.x(), b.y());
  const double m = kBeyond * d.norm() * std::max(a.norm(), b.norm());
  return (sa > m && sb < -m) || (sa < -m && sb > m);
}

// Whether the segment from the origin to W crosses every walked edge strictly inside.
bool strip_holds(const StripSegment& s, const IntrinsicTriangulation& tri,
                 const Eigen::Vector2d& W) {
  for (const Index e : s.crossed) {
    const Index h = tri.edge_halfedge(e);
    const Eigen::Vector2d *a = strip_at(s, tri.tail(h)), *b = strip_at(s, tri.head(h));
    if (a == nullptr || b == nullptr || !straddles(W, *a, *b)) return false;
  }
  return true;
}

// Whether the diamond of edge e (all four corners in the strip) is convex by the margin: its
// two diagonals cross strictly inside, so the flip makes no sliver that rounding would spoil.
bool diamond_convex(const IntrinsicTriangulation& tri, const StripSegment& s, Index e) {
  const Index h = tri.edge_halfedge(e), t = tri.twin(h);
  if (t == kInvalidIndex) return false;
  const Eigen::Vector2d *a = strip_at(s, tri.tail(h)), *b = strip_at(s, tri.head(h)),
                        *c = strip_at(s, tri.tail(T::prev(h))), *d = strip_at(s, tri.tail(T::prev(t)));
  if (!a || !b || !c || !d) return false;
  return straddles(*b - *a, *c - *a, *d - *a) && straddles(*d - *c, *a - *c, *b - *c);
}

}  // namespace

// Long function: the face search at p, the walk and the check are one pass over the strip.
bool plan_strip_segment(const SignpostTriangulation& st, Index h_pu, double theta, Index w,
                        const std::vector<int>& uses, int max_cross, StripSegment* out,
                        int retries_left) {
  const T& tri = st.intrinsic();
  StripSegment& s = *out;
  const Index p = tri.tail(h_pu);
  s.p = p, s.w = w, s.crossed.clear(), s.at.clear(), s.existing = kInvalidIndex;
  // the face at p holding direction theta: rotate from h_pu
  const double big = st.vertex_angle_sum(p);
  double delta = theta - st.halfedge_direction(h_pu);
  if (!st.is_boundary_vertex(p)) {
    if (delta > 0.5 * big) delta -= big;
    if (delta < -0.5 * big) delta += big;
  }
  Index x = h_pu;
  for (int k = 0; k < 4096; ++k) {
    if (delta >= 0.0) {
      const double c = corner_angle(tri, x);
      if (delta < c) break;
      delta -= c;
      x = tri.twin(T::prev(x));
    } else {
      if (tri.twin(x) == kInvalidIndex) { ++g_plan_dbg[12]; return false; }
      x = T::next(tri.twin(x));
      delta += corner_angle(tri, x);
    }
    if (x == kInvalidIndex || k == 4095) { ++g_plan_dbg[13]; return false; }
  }
  const Eigen::Vector2d d(std::cos(delta), std::sin(delta));
  const double c0 = corner_angle(tri, x);
  const Eigen::Vector2d A(tri.halfedge_length(x), 0.0);
  const double lb = tri.halfedge_length(T::prev(x));
  const Eigen::Vector2d B(lb * std::cos(c0), lb * std::sin(c0));
  if (!strip_put(&s, p, Eigen::Vector2d::Zero()) || !strip_put(&s, tri.head(x), A) ||
      !strip_put(&s, tri.tail(T::prev(x)), B)) {
    { ++g_plan_dbg[14]; return false; }
  }
  if (tri.head(x) == w || tri.tail(T::prev(x)) == w) {  // p–w is a side of the first face
    s.existing = tri.head(x) == w ? tri.edge(x) : tri.edge(T::prev(x));
    s.length = tri.length(s.existing);
    s.direction_at_p =
        tri.head(x) == w ? st.halfedge_direction(x)
                          : st.wrap_direction(p, st.halfedge_direction(x) + c0);
    return true;
  }
  Index hc = T::next(x);  // exit side: tail A, head B
  // w reached as a corner of the face just entered (vc) or as an end of the side to cross next
  const auto arrive = [&](const Eigen::Vector2d& W) {
    if (strip_holds(s, tri, W)) {
      s.length = W.norm();
      s.direction_at_p =
          st.wrap_direction(p, st.halfedge_direction(x) + std::atan2(W.y(), W.x()));
      return true;
    }
    ++g_plan_dbg[17];
    // aim at w as laid out in this strip and walk again
    const double aim = st.wrap_direction(p, st.halfedge_direction(x) + std::atan2(W.y(), W.x()));
    return retries_left > 0 &&
           plan_strip_segment(st, h_pu, aim, w, uses, max_cross, out, retries_left - 1);
  };
  for (int k = 0; k < max_cross; ++k) {
    if (tri.tail(hc) == w || tri.head(hc) == w) return arrive(*strip_at(s, w));
    const Index e = tri.edge(hc), t = tri.twin(hc);
    if (t == kInvalidIndex || uses[static_cast<std::size_t>(e)] > 0) { ++g_plan_dbg[15]; return false; }
    s.crossed.push_back(e);
    const Eigen::Vector2d Pa = *strip_at(s, tri.tail(hc)), Pb = *strip_at(s, tri.head(hc));
    // face(t) = (head(hc), tail(hc), C), counter-clockwise
    const double L = (Pa - Pb).norm(), lbc = tri.halfedge_length(T::prev(t)),
                 lac = tri.halfedge_length(T::next(t));
    const Eigen::Vector2d ux = (Pa - Pb) / L, uy(-ux.y(), ux.x());
    const double cx = (L * L + lbc * lbc - lac * lac) / (2.0 * L);
    const Eigen::Vector2d C = Pb + cx * ux + std::sqrt(std::max(0.0, lbc * lbc - cx * cx)) * uy;
    const Index vc = tri.tail(T::prev(t));
    if (!strip_put(&s, vc, C)) { ++g_plan_dbg[16]; return false; }
    if (vc == w) return arrive(C);
    const double sc = cross(d.x(), d.y(), C.x(), C.y());
    const double sa = cross(d.x(), d.y(), Pa.x(), Pa.y());
    if (std::abs(sc) <= kBeyond * C.norm()) { ++g_plan_dbg[18]; return false; }  // through a vertex
    hc = (sc > 0.0) == (sa > 0.0) ? T::prev(t) : T::next(t);
  }
  ++g_plan_dbg[19];
  return false;
}

Index insert_strip_segment(SignpostTriangulation& st, const StripSegment& plan,
                           const std::function<void(Index)>& on_flip) {
  if (plan.existing != kInvalidIndex) return plan.existing;
  const T& tri = st.intrinsic();
  const Eigen::Vector2d W = *strip_at(plan, plan.w);
  std::vector<Index> queue(plan.crossed.rbegin(), plan.crossed.rend());
  std::size_t stalled = 0;
  const std::size_t k = queue.size();
  std::size_t budget = 4 * k * k + 16;  // Sloan flips each crossing edge O(k) times at most
  while (!queue.empty()) {
    if (budget-- == 0) return kInvalidIndex;
    const Index e = queue.back();
    queue.pop_back();
    if (!diamond_convex(tri, plan, e) || !st.flip_edge(e)) {
      queue.insert(queue.begin(), e);
      if (++stalled > queue.size()) return kInvalidIndex;
      continue;
    }
    stalled = 0;
    on_flip(e);
    const Index h = tri.edge_halfedge(e);
    const Index a = tri.tail(h), b = tri.head(h);
    if ((a == plan.p && b == plan.w) || (a == plan.w && b == plan.p)) return e;
    const Eigen::Vector2d *pa = strip_at(plan, a), *pb = strip_at(plan, b);
    if (pa == nullptr || pb == nullptr) return kInvalidIndex;
    if (straddles(W, *pa, *pb)) queue.insert(queue.begin(), e);
  }
  return kInvalidIndex;
}

std::pair<double, double> joint_angles_at(const SignpostTriangulation& st, Index back,
                                          double out) {
  const Index v = st.intrinsic().tail(back);
  const double theta = st.vertex_angle_sum(v);
  double a = out - st.halfedge_direction(back);
  if (a < 0.0) a += theta;
  if (a >= theta) a -= theta;
  return {a, theta - a};
}

}  // namespace ifem::intrinsic::detail
