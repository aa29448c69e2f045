// Normal coordinates and roundabouts (normal_coordinates.h). Notation used throughout: in a
// face with sides 0, 1, 2 (side s runs from corner s to corner s+1) and clamped coordinates
// n[s] = max(n, 0), the input edges inside the face are arcs of two kinds:
//   corner[k]: arcs cutting off corner k (crossing side k and side k+2),
//   fan[k]:    arcs leaving corner k (crossing the opposite side k+1).
// Arcs are disjoint, so at most one corner has a fan, and n[s] = corner[s] + corner[s+1] +
// fan[s+2]. Along side s, counted from corner s, the crossings are: corner[s] arcs of corner s,
// then fan[s+2] arcs of the opposite corner, then corner[s+1] arcs of corner s+1.
#include "intrinsic/integer/normal_coordinates.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

#include "intrinsic/core/errors.h"
#include "intrinsic/core/geometry.h"

namespace ifem::intrinsic {
namespace {

using T = IntrinsicTriangulation;

// The third corner of a triangle laid out on a→b, to the left of a→b, at distance la from a
// and lb from b.
Eigen::Vector2d place_left(const Eigen::Vector2d& a, const Eigen::Vector2d& b, double la,
                           double lb) {
  const Eigen::Vector2d ab = b - a;
  const double d = ab.norm();
  const Eigen::Vector2d u = ab / d, w(-u.y(), u.x());
  const double x = (la * la - lb * lb + d * d) / (2.0 * d);
  const double y = std::sqrt(std::max(0.0, la * la - x * x));
  return a + x * u + y * w;
}

// Where the arc from p (below the x axis) to q (above) crosses the intrinsic edge [0, len] on
// the x axis: the fraction s along the arc (returned) and the abscissa *x. The integers say that
// it does; the intersection of the two lines says where. When that lies off the edge or off the
// arc by more than rounding, the lines are nearly parallel (the arc runs along the edge, whose
// ends both lie within rounding of the input edge: two vertices inserted there) and the
// intersection means nothing: s moves to the nearest fraction whose point lies over the edge
// (x in [0, len]) and on the arc, which is within rounding of both. Intersections within
// rounding of the segments are kept as computed.
double arc_crossing(const Eigen::Vector2d& p, const Eigen::Vector2d& q, double len, double* x) {
  const double dy = q.y() - p.y(), dx = q.x() - p.x();
  double s = dy != 0.0 ? -p.y() / dy : 0.5;
  *x = p.x() + s * dx;
  const double slack = 1e-9;
  if (s >= -slack && s <= 1.0 + slack && *x >= -slack * len && *x <= (1.0 + slack) * len) return s;
  double lo = 0.0, hi = 1.0;
  if (dx != 0.0) {
    const double s0 = -p.x() / dx, s1 = (len - p.x()) / dx;
    lo = std::max(lo, std::min(s0, s1));
    hi = std::min(hi, std::max(s0, s1));
  }
  s = lo <= hi ? std::clamp(s, lo, hi) : std::clamp(s, 0.0, 1.0);
  *x = std::clamp(p.x() + s * dx, 0.0, len);
  return s;
}

// Whether x lies strictly between `from` and `to` going forward cyclically (along the boundary
// of a star, counter-clockwise: the left part of a chord from `to` to `from` has those points).
bool in_cyclic_interval(std::pair<int, int> from, std::pair<int, int> to, std::pair<int, int> x) {
  return from < to ? (from < x && x < to) : (from < x || x < to);
}

[[noreturn]] void inconsistent(const std::string& what) {
  throw InvalidInput("normal coordinates: " + what);
}

}  // namespace

NormalCoordinateTriangulation::NormalCoordinateTriangulation(const std::vector<Triangle>& faces,
                                                             const Positions& positions,
                                                             double mollify_relative_epsilon,
                                                             BuildReport* report)
    : positions_(positions) {
  BuildReport build;
  input_ = IntrinsicTriangulation::from_positions(faces, positions, &build);
  face_origin_ = build.face_origin;
  if (report != nullptr) *report = build;
  if (mollify_relative_epsilon > 0.0) input_.mollify(mollify_relative_epsilon);
  tri_ = input_;
  const Index nv = input_.n_vertices(), nh = input_.n_halfedges();
  n_.assign(input_.n_edges(), -1);
  r_.assign(nh, 0);
  spokes_.assign(nv, {});
  fans_.assign(nv, {});
  std::vector<std::vector<Index>> boundary_out(nv);  // outgoing boundary sides: fan starts
  for (Index h = 0; h < nh; ++h) {
    if (input_.twin(h) == kInvalidIndex) boundary_out[input_.tail(h)].push_back(h);
  }
  // each fan of faces at a vertex gives a run of spokes: a boundary fan starts at its outgoing
  // boundary side (counter-clockwise steps never leave it, so its indices never wrap), a closed
  // fan anywhere (its indices wrap within the fan: spoke_index())
  std::vector<char> seen(nh, 0);
  for (Index v = 0; v < nv; ++v) {
    const Index h0 = input_.vertex_halfedge(v);
    if (h0 == kInvalidIndex) continue;
    if (boundary_out[v].empty()) add_fan(v, h0, seen);
    for (const Index h : boundary_out[v]) add_fan(v, h, seen);
  }
  for (Index h = 0; h < nh; ++h) {
    if (!seen[h]) add_fan(input_.tail(h), h, seen);  // a further closed fan (pinched vertex)
  }
  for (Index v = 0; v < nv; ++v) {
    if (fans_[v].size() > 1) {
      fans_[v].push_back(static_cast<int>(spokes_[v].size()));
    } else {
      fans_[v].clear();
    }
  }
}

// Appends the spokes of v's fan from outgoing side h0 (counter-clockwise, h → twin(prev(h)); a
// boundary fan also ends with its incoming boundary side, seen from v), records the fan's first
// index and sets the roundabouts of its sides.
void NormalCoordinateTriangulation::add_fan(Index v, Index h0, std::vector<char>& seen) {
  auto& list = spokes_[v];
  fans_[v].push_back(static_cast<int>(list.size()));
  const Index nh = input_.n_halfedges();
  Index h = h0;
  for (Index guard = 0; guard <= nh; ++guard) {
    const Index e = input_.edge(h);
    r_[h] = static_cast<int>(list.size());
    seen[h] = 1;
    list.push_back({e, input_.edge_halfedge(e) == h ? 0.0 : 1.0});
    const Index p = T::prev(h);
    const Index tw = input_.twin(p);
    if (tw == kInvalidIndex) {
      const Index ep = input_.edge(p);
      list.push_back({ep, input_.edge_halfedge(ep) == p ? 1.0 : 0.0});
      break;
    }
    h = tw;
    if (h == h0) break;
  }
}

double NormalCoordinateTriangulation::vertex_at(Index v, Index input_edge) const {
  if (v >= n_input_vertices()) return spokes_[v].empty() ? 0.0 : spokes_[v][0].at;
  return input_.tail(input_.edge_halfedge(input_edge)) == v ? 0.0 : 1.0;
}

Index NormalCoordinateTriangulation::input_edge_along(Index h) const {
  if (n_[tri_.edge(h)] >= 0) return kInvalidIndex;
  const Index v = tri_.tail(h);
  if (spokes_[v].empty()) inconsistent("edge along an input edge at a vertex without spokes");
  return spokes_[v][r_[h]].input_edge;
}

int NormalCoordinateTriangulation::spoke_index(Index v, int r, long steps) const {
  long first = 0, d = static_cast<long>(spokes_[v].size());
  if (d == 0) return 0;
  const auto& fans = fans_[v];
  if (!fans.empty()) {  // several fans: stay within r's
    std::size_t k = 0;
    while (k + 2 < fans.size() && fans[k + 1] <= r) ++k;
    first = fans[k];
    d = fans[k + 1] - fans[k];
  }
  return static_cast<int>(first + (((r - first + steps) % d) + d) % d);
}

NormalCoordinateTriangulation::FaceCounts NormalCoordinateTriangulation::counts(Index f) const {
  FaceCounts c;
  for (int s = 0; s < 3; ++s) c.n[s] = std::max(0, n_[tri_.edge(3 * f + s)]);
  for (int k = 0; k < 3; ++k) {
    c.fan[k] = std::max(0, c.n[(k + 1) % 3] - c.n[k] - c.n[(k + 2) % 3]);
  }
  for (int k = 0; k < 3; ++k) {
    const int twice = c.n[k] + c.n[(k + 2) % 3] - c.n[(k + 1) % 3] - c.fan[(k + 1) % 3] -
                      c.fan[(k + 2) % 3] + c.fan[k];
    c.corner[k] = twice / 2;
  }
  return c;
}

void NormalCoordinateTriangulation::grow_records() {
  n_.resize(tri_.n_edges(), 0);
  r_.resize(tri_.n_halfedges(), 0);
  spokes_.resize(tri_.n_vertices());
  fans_.resize(tri_.n_vertices());
}

// ---------------------------------------------------------------------------------------------
// Flips: integers only

bool NormalCoordinateTriangulation::flip_edge(Index e) {
  const Index h = tri_.edge_halfedge(e);
  const Index t = tri_.twin(h);
  if (t == kInvalidIndex || T::face(h) == T::face(t)) return false;
  const Index h1 = T::next(h), h2 = T::prev(h), t1 = T::next(t), t2 = T::prev(t);
  const Index c = tri_.tail(h2), d = tri_.tail(t2);
  // diamond a→b = h in face (a, b, c), b→a = t in face (b, a, d); positions along h from a
  const FaceCounts A = counts(T::face(h)), B = counts(T::face(t));
  const int sh = T::side(h), st = T::side(t);
  const int n = std::max(0, n_[e]);
  const int cA1 = A.corner[sh], cB1 = A.corner[(sh + 1) % 3], cC1 = A.corner[(sh + 2) % 3];
  const int fA1 = A.fan[sh], fB1 = A.fan[(sh + 1) % 3], fC1 = A.fan[(sh + 2) % 3];
  const int cB2 = B.corner[st], cA2 = B.corner[(st + 1) % 3], cD2 = B.corner[(st + 2) % 3];
  const int fB2 = B.fan[st], fA2 = B.fan[(st + 1) % 3], fD2 = B.fan[(st + 2) % 3];
  // arcs from c and arcs from d meeting across h: an input edge c–d, the new edge runs along it
  const int along = std::max(0, std::min(cA1 + fC1, cA2 + fD2) - std::max(cA1, cA2));
  int n_new = -1;
  if (along == 0) {
    // every arc not crossing h separates c or d from h; an arc crossing h crosses c–d when
    // its two halves end on sides of different corners (a and b); the old input edge a–b too
    n_new = cC1 + fA1 + fB1 + cD2 + fA2 + fB2 + std::max(0, cA1 + cB2 - n) +
            std::max(0, cB1 + cA2 - n) + (n_[e] < 0 ? 1 : 0);
  }
  // c→d turns from c→a past the arcs of c's fan that end on a's side; d→c from d→b likewise
  const long rc = (shared(h2) ? 1 : 0) + std::max(0, std::min(cA1 + fC1, cA2) - cA1);
  const long rd = (shared(t2) ? 1 : 0) + std::max(0, cA2 + fD2 - std::max(cA2, n - cB1));
  const int rh1 = r_[h1], rh2 = r_[h2], rt1 = r_[t1], rt2 = r_[t2];
  if (!tri_.flip_edge(e)) return false;
  // slots keep their sides' roundabouts: h1 ← h2, h2 ← t1, t1 ← t2, t2 ← h1
  r_[h1] = rh2;
  r_[h2] = rt1;
  r_[t1] = rt2;
  r_[t2] = rh1;
  r_[t] = spoke_index(c, rh2, rc);  // t = c→d
  r_[h] = spoke_index(d, rt2, rd);  // h = d→c
  n_[e] = n_new;
  return true;
}

FlipReport NormalCoordinateTriangulation::flip_to_delaunay() {
  return tri_.flip_to_delaunay([this](Index e) { return flip_edge(e); });
}

FlipReport NormalCoordinateTriangulation::flip_to_delaunay_from(std::vector<Index> queue,
                                                                std::vector<Index>* touched) {
  return tri_.flip_to_delaunay_from(std::move(queue), touched,
                                    [this](Index e) { return flip_edge(e); });
}

FlipReport NormalCoordinateTriangulation::flip_to_delaunay(const std::vector<char>& fixed_edges) {
  return tri_.flip_to_delaunay(
      [this, &fixed_edges](Index e) { return !is_flagged(&fixed_edges, e) && flip_edge(e); });
}

FlipReport NormalCoordinateTriangulation::flip_to_delaunay_from(
    std::vector<Index> queue, std::vector<Index>* touched, const std::vector<char>& fixed_edges) {
  return tri_.flip_to_delaunay_from(std::move(queue), touched, [this, &fixed_edges](Index e) {
    return !is_flagged(&fixed_edges, e) && flip_edge(e);
  });
}

// ---------------------------------------------------------------------------------------------
// Tracing

NormalCoordinateTriangulation::ArcEnd NormalCoordinateTriangulation::follow(
    Index h, int p, Eigen::Vector2d a, Eigen::Vector2d b) const {
  // the arc enters face(h) through side h at position p from tail(h) (laid out at a, head at b)
  const Index cap = 4 * tri_.n_faces() + 1000;
  for (Index step = 0; step < cap; ++step) {
    const Index f = T::face(h);
    const int s = T::side(h);
    const FaceCounts c = counts(f);
    if (p < 1 || p > c.n[s]) inconsistent("arc position out of range in face " + std::to_string(f));
    const Index hn = T::next(h), hp = T::prev(h);
    const Eigen::Vector2d z = place_left(a, b, tri_.halfedge_length(hp), tri_.halfedge_length(hn));
    if (p <= c.corner[s]) {  // around corner s: leaves through side s+2, as p-th from a
      h = tri_.twin(hp);
      b = z;
    } else if (p <= c.corner[s] + c.fan[(s + 2) % 3]) {  // ends at the opposite corner
      ArcEnd end;
      end.vertex = tri_.tail(hp);
      end.spoke = spoke_index(end.vertex, r_[hp], (shared(hp) ? 1 : 0) + (p - c.corner[s] - 1));
      end.pos = z;
      if (spokes_[end.vertex].empty()) inconsistent("arc ends at a vertex without spokes");
      return end;
    } else {  // around corner s+1: leaves through side s+1, q-th from b
      const int q = c.n[s] - p + 1;
      h = tri_.twin(hn);
      p = c.n[(s + 1) % 3] - q + 1;
      a = z;
    }
    if (h == kInvalidIndex) inconsistent("arc crosses the boundary");
  }
  inconsistent("arc does not end");
}

std::vector<InputCrossing> NormalCoordinateTriangulation::trace_halfedge(Index h) const {
  std::vector<InputCrossing> out;
  const int n = n_[tri_.edge(h)];
  if (n <= 0) return out;
  const Index tw = tri_.twin(h);
  if (tw == kInvalidIndex) inconsistent("boundary edge crossed by input edges");
  const double len = tri_.halfedge_length(h);
  const Eigen::Vector2d a(0.0, 0.0), b(len, 0.0);
  out.reserve(n);
  for (int p = 1; p <= n; ++p) {
    const ArcEnd e1 = follow(h, p, a, b);           // in face(h), above the x axis
    const ArcEnd e2 = follow(tw, n - p + 1, b, a);  // in face(tw), below
    const InputSpoke& s1 = spokes_[e1.vertex][e1.spoke];
    const InputSpoke& s2 = spokes_[e2.vertex][e2.spoke];
    if (s1.input_edge != s2.input_edge) inconsistent("arc ends on two different input edges");
    double x = 0.0;
    const double s = arc_crossing(e2.pos, e1.pos, len, &x);
    out.push_back({s1.input_edge, x / len, s2.at + s * (s1.at - s2.at), s1.at > s2.at});
  }
  return out;
}

std::vector<InputCrossing> NormalCoordinateTriangulation::trace_edge(Index e) const {
  return trace_halfedge(tri_.edge_halfedge(e));
}

SurfacePoint NormalCoordinateTriangulation::crossing_point(const InputCrossing& c) const {
  const Index h = input_.edge_halfedge(c.input_edge);
  SurfacePoint p;
  p.face = T::face(h);
  p.bary[T::side(h)] = 1.0 - c.input_t;
  p.bary[(T::side(h) + 1) % 3] = c.input_t;
  return p;
}

Eigen::Vector3d NormalCoordinateTriangulation::crossing_position(const InputCrossing& c) const {
  const Index h = input_.edge_halfedge(c.input_edge);
  const Eigen::Vector3d x0 = positions_.row(input_.tail(h)), x1 = positions_.row(input_.head(h));
  return (1.0 - c.input_t) * x0 + c.input_t * x1;
}

// ---------------------------------------------------------------------------------------------
// Insertion and splitting: where the new edges fall among the arcs of the cut faces

// Within this fraction of a face's longest side of an input edge crossing it, a new vertex is
// taken to lie on that edge (insert_vertex()).
constexpr double kOnArc = 1e-10;

// The arc of face f nearest to x = Σ bary[k]·corner k in f's layout, if within kOnArc of f's
// longest side: a corner arc i of corner k runs from its crossing of side k (i-th from corner
// k) to its crossing of side k+2 (i-th back from corner k), a fan arc j from corner k to its
// crossing of side k+1 (after the corner arcs of corner k+1). `trace` holds f's sides traced.
NormalCoordinateTriangulation::OnArc NormalCoordinateTriangulation::arc_at(
    Index f, const Eigen::Vector3d& bary, const FaceCounts& c,
    const std::vector<InputCrossing> trace[3]) const {
  Eigen::Vector2d p[3];
  face_layout(tri_, f, p);
  const Eigen::Vector2d x = bary[0] * p[0] + bary[1] * p[1] + bary[2] * p[2];
  double best = 0.0;
  for (int k = 0; k < 3; ++k) best = std::max(best, (p[(k + 1) % 3] - p[k]).norm());
  best *= kOnArc;
  OnArc on;
  auto consider = [&](int k, bool fan, int i, const Eigen::Vector2d& a, const Eigen::Vector2d& b,
                      Index edge, double at_a, double at_b) {
    const Eigen::Vector2d ab = b - a;
    const double len2 = ab.squaredNorm();
    const double s = len2 > 0.0 ? std::clamp((x - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
    const double d = (x - a - s * ab).norm();
    if (d <= best) best = d, on = {k, fan, i, {edge, at_a + s * (at_b - at_a)}};
  };
  for (int k = 0; k < 3; ++k) {
    const int k1 = (k + 1) % 3, k2 = (k + 2) % 3;
    for (int i = 1; i <= c.corner[k]; ++i) {
      const InputCrossing& P = trace[k][i - 1];
      const InputCrossing& Q = trace[k2][c.n[k2] - i];
      if (P.input_edge != Q.input_edge) inconsistent("a corner arc ends on two input edges");
      consider(k, false, i, p[k] + P.t * (p[k1] - p[k]), p[k2] + Q.t * (p[k] - p[k2]), P.input_edge,
               P.input_t, Q.input_t);
    }
    const Index ck = tri_.tail(3 * f + k);
    for (int j = 1; j <= c.fan[k]; ++j) {
      const InputCrossing& R = trace[k1][c.corner[k1] + j - 1];
      const long steps = (shared(3 * f + k) ? 1 : 0) + j - 1;
      const InputSpoke& sp = spokes_[ck][spoke_index(ck, r_[3 * f + k], steps)];
      if (sp.input_edge != R.input_edge) inconsistent("a fan arc ends on two input edges");
      consider(k, true, j, p[k], p[k1] + R.t * (p[k2] - p[k1]), R.input_edge, sp.at, R.input_t);
    }
  }
  return on;
}

// Where the arcs of face f fall relative to a point x = Σ bary[k]·corner k, decided per arc
// from x's barycentric coordinates and the arc's end fractions along the sides (no layout:
// robust where arcs shrink onto a corner, e.g. a vertex inserted on an input edge), turned
// into counts that are consistent by construction (x on an arc counts as on one side):
// crossing[k] = arcs the segment x–corner k crosses, before[k] = arcs of corner k's fan met
// turning counter-clockwise from side k before x. In corner k's frame (u, w) = (bary[k+1],
// bary[k+2]): x lies on corner k's side of a corner arc ending at fractions a (side k, from
// corner k) and b (side k+2, towards corner k+2) iff u/a + w/b < 1, and on corner k+2's side
// of a fan arc ending at fraction c of side k+1 iff w > c (u + w). The arc x lies on within
// rounding (arc_at(), `on`) crosses none of the three segments (a fan arc runs along the one
// to its corner), and the arcs of its family before it are on the corner's side of x.
void NormalCoordinateTriangulation::count_new_spokes(Index f, const Eigen::Vector3d& bary,
                                                     int crossing[3], int before[3],
                                                     OnArc* on) const {
  const FaceCounts c = counts(f);
  std::vector<InputCrossing> trace[3];
  for (int s = 0; s < 3; ++s) {
    if (c.n[s] > 0) trace[s] = trace_halfedge(3 * f + s);
  }
  *on = arc_at(f, bary, c, trace);
  auto frac = [&](int s, int i) { return std::clamp(trace[s][i - 1].t, 0.0, 1.0); };
  for (int k = 0; k < 3; ++k) {
    const int k1 = (k + 1) % 3, k2 = (k + 2) % 3;
    const double u = bary[k1], w = bary[k2];
    int far = 0;  // corner k's arcs with x beyond them
    for (int i = 1; i <= c.corner[k]; ++i) {
      const double a = frac(k, i), b = 1.0 - frac(k2, c.n[k2] - i + 1);
      far += u * b + w * a < a * b ? 0 : 1;
    }
    for (int j = 1; j <= c.fan[k]; ++j) before[k] += w > frac(k1, c.corner[k1] + j) * (u + w);
    int on_corner = 0, on_fan = 0;
    if (on->corner == k && on->fan) before[k] = on->index - 1, on_fan = 1;
    if (on->corner == k && !on->fan) far = on->index - 1, on_corner = 1;
    crossing[k] += far;
    crossing[k1] += c.corner[k] - far - on_corner + before[k];
    crossing[k2] += c.corner[k] - far - on_corner + c.fan[k] - before[k] - on_fan;
  }
}

Index NormalCoordinateTriangulation::insert_vertex(Index f, const Eigen::Vector3d& bary) {
  if (f < 0 || f >= tri_.n_faces()) {
    throw InvalidInput("insert_vertex: face " + std::to_string(f) + " out of range");
  }
  int crossing[3] = {0, 0, 0}, before[3] = {0, 0, 0};
  OnArc on;
  count_new_spokes(f, bary, crossing, before, &on);
  int r_old[3], shared_side[3];
  Index corner[3];
  for (int k = 0; k < 3; ++k) {
    r_old[k] = r_[3 * f + k];
    shared_side[k] = shared(3 * f + k) ? 1 : 0;
    corner[k] = tri_.tail(3 * f + k);
  }
  const int r1 = r_[3 * f + 1], r2 = r_[3 * f + 2];
  const Index e0 = tri_.n_edges();
  const Index v = tri_.insert_vertex_in_face(f, bary);
  grow_records();
  const Index f1 = tri_.n_faces() - 2, f2 = f1 + 1;
  r_[3 * f1] = r1;                                                                // c1→c2 moved
  r_[3 * f2] = r2;                                                                // c2→c0 moved
  r_[3 * f2 + 1] = spoke_index(corner[0], r_old[0], shared_side[0] + before[0]);  // c0→v
  r_[3 * f + 1] = spoke_index(corner[1], r_old[1], shared_side[1] + before[1]);   // c1→v
  r_[3 * f1 + 1] = spoke_index(corner[2], r_old[2], shared_side[2] + before[2]);  // c2→v
  const Index out[3] = {3 * f + 2, 3 * f1 + 2, 3 * f2 + 2};                       // v→c0, c1, c2
  for (int k = 0; k < 3; ++k) r_[out[k]] = 0;
  for (int k = 0; k < 3; ++k) n_[e0 + k] = crossing[k];
  if (on.corner >= 0) {
    // v on an input edge: spokes counter-clockwise, 0 towards side k's crossing (a corner arc
    // of corner k) or along v→c_k (a fan arc), 1 towards the crossing of side k+2 (corner
    // arc) or k+1 (fan arc)
    const int k = on.corner;
    spokes_[v] = {on.spoke, on.spoke};
    r_[out[(k + 1) % 3]] = 1;
    r_[out[(k + 2) % 3]] = on.fan ? 0 : 1;
    if (on.fan) n_[e0 + k] = -1;
  }
  return v;
}

// The arcs of face(side_h) crossing the segment from a new vertex m on side s = side(side_h)
// (q crossings of that side lie between its tail and m) to the opposite corner k = s+2, and
// (fan_before) the arcs of corner k's fan that end on side s before m. Along side s, from its
// tail: corner[s] arcs of corner s, fan[k] arcs of corner k, corner[s+1] arcs of corner s+1.
// The segment crosses corner k's arcs, the fans of corners s and s+1 (they separate side s from
// corner k), the arcs of corner s beyond m and the arcs of corner s+1 before m. With at_m, the
// arc of the (q+1)-th crossing ends at m: it crosses nothing (an arc of corner s no longer
// counts among those beyond m), and a fan arc of corner k runs along the segment (−1).
int NormalCoordinateTriangulation::count_diagonal(Index side_h, int q, bool at_m, int* fan_before,
                                                  int* kind) const {
  const FaceCounts c = counts(T::face(side_h));
  const int s = T::side(side_h), s1 = (s + 1) % 3, k = (s + 2) % 3;
  *fan_before = std::clamp(q - c.corner[s], 0, c.fan[k]);
  *kind = q < c.corner[s] ? 0 : q < c.corner[s] + c.fan[k] ? 1 : 2;
  if (at_m && *kind == 1) return -1;
  return c.corner[k] + c.fan[s] + c.fan[s1] + std::max(0, c.corner[s] - q) -
         (at_m && *kind == 0 ? 1 : 0) + std::max(0, q - c.corner[s] - c.fan[k]);
}

// Long function: one straight sequence (measure both faces, split, write every new record),
// kept together so the slot bookkeeping reads against triangulation.h's split_edge layout.
Index NormalCoordinateTriangulation::split_edge(Index e, double t) {
  if (e < 0 || e >= tri_.n_edges() || !tri_.can_split_edge(e)) return tri_.split_edge(e, t);
  const Index h = tri_.edge_halfedge(e), tw = tri_.twin(h);
  const bool interior = tw != kInvalidIndex;
  const Index h1 = T::next(h), h2 = T::prev(h);
  const Index t1 = interior ? T::next(tw) : kInvalidIndex,
              t2 = interior ? T::prev(tw) : kInvalidIndex;
  const Index a = tri_.tail(h), b = tri_.head(h), c = tri_.tail(h2);
  const Index d = interior ? tri_.tail(t2) : kInvalidIndex;
  const int n_e = n_[e], n = std::max(0, n_e);
  int q = 0;                         // crossings between a and the new vertex
  std::vector<InputSpoke> m_spokes;  // a vertex on an input edge: two spokes
  if (n > 0) {
    const std::vector<InputCrossing> trace = trace_halfedge(h);
    int near = 0;  // the crossing nearest to m: m is on its input edge if within rounding
    for (int i = 0; i < n; ++i) {
      q += trace[i].t < t ? 1 : 0;
      if (std::abs(trace[i].t - t) < std::abs(trace[near].t - t)) near = i;
    }
    if (std::abs(trace[near].t - t) <= kOnArc) {
      q = near;
      m_spokes.assign(2, InputSpoke{trace[near].input_edge, trace[near].input_t});
    }
  }
  const bool at_m = !m_spokes.empty();
  // new diagonals m–c and m–d: the arcs of each face crossing them, read from the integers and
  // the q crossings of e before m (so always consistent)
  int c_before = 0, d_before = 0, c_kind = 0, d_kind = 0;
  const int n_mc = count_diagonal(h, q, at_m, &c_before, &c_kind);
  const int n_md = interior ? count_diagonal(tw, n - q - at_m, at_m, &d_before, &d_kind) : 0;
  const int rh2 = r_[h2], rt2 = interior ? r_[t2] : 0;
  const long rc = (shared(h2) ? 1 : 0) + c_before;
  const long rd = interior ? (shared(t2) ? 1 : 0) + d_before : 0;
  const int rh1 = r_[h1], rt1 = interior ? r_[t1] : 0;
  // on the input edge e runs along: two spokes, 0 toward b and 1 toward a
  if (n_e < 0) {
    const InputSpoke& sa = spokes_[a][r_[h]];
    const double at_b = interior ? spokes_[b][r_[tw]].at : vertex_at(b, sa.input_edge);
    const InputSpoke s{sa.input_edge, sa.at + t * (at_b - sa.at)};
    m_spokes = {s, s};
  }
  const Index e_mb = tri_.n_edges();
  const Index m = tri_.split_edge(e, t);
  grow_records();
  const Index g1 = interior ? tri_.n_faces() - 2 : tri_.n_faces() - 1, g2 = g1 + 1;
  const bool along = n_e < 0;
  spokes_[m] = std::move(m_spokes);
  n_[e] = along ? -1 : q;
  n_[e_mb] = along ? -1 : n - q - at_m;
  n_[e_mb + 1] = n_mc;
  // m's spokes counter-clockwise (around m: b, c, a, d): along e, 0 toward b and 1 toward a;
  // at a crossing, 0 into face(h) (before c for an arc of b's corner) and 1 into face(tw)
  // (after d for an arc of a's corner)
  r_[3 * g1 + 1] = rh1;                             // b→c moved
  r_[3 * g1 + 2] = spoke_index(c, rh2, rc);         // c→m
  r_[3 * g1] = 0;                                   // m→b
  r_[h1] = along || (at_m && c_kind == 2) ? 1 : 0;  // m→c
  if (interior) {
    n_[e_mb + 2] = n_md;
    r_[3 * g2 + 1] = rt1;                      // a→d moved
    r_[3 * g2 + 2] = spoke_index(d, rt2, rd);  // d→m
    r_[3 * g2] = along || at_m ? 1 : 0;        // m→a
    r_[t1] = at_m && d_kind != 2 ? 1 : 0;      // m→d
  }
  return m;
}

// ---------------------------------------------------------------------------------------------
// Moving an inserted vertex inside its flat star. Notation: spokes h_i = v→ring i, star face
// F_i = face(h_i) = (v, ring i, ring i+1) with outer side o_i = next(h_i) and g_i = prev(h_i)
// (ring i+1 → v, the twin of h_i+1). Input edges cross the flat star as straight chords.

bool NormalCoordinateTriangulation::is_boundary_vertex(Index v) const {
  const Index h0 = tri_.vertex_halfedge(v);
  if (h0 == kInvalidIndex) return false;
  Index h = h0;
  for (Index guard = 0; guard <= tri_.n_halfedges(); ++guard) {
    if (tri_.twin(h) == kInvalidIndex) return true;
    h = tri_.twin(T::prev(h));
    if (h == kInvalidIndex) return true;
    if (h == h0) return false;
  }
  return false;
}

// The piece of an input edge entering star face face(h) through side h, p-th from tail(h),
// followed through the star (the rules of follow()) to the outer side it leaves through, or
// the ring vertex or centre it ends at. Sets *crossed to the first spoke it crosses (the ring
// index of its far end) if *crossed < 0.
NormalCoordinateTriangulation::StarEnd NormalCoordinateTriangulation::walk_star(
    const std::vector<Index>& spokes, Index h, int p, int* crossed) const {
  const int k = static_cast<int>(spokes.size());
  // 0: h_i, 1: o_i, 2: g_i
  auto role = [&](Index x, int* i) {
    for (int j = 0; j < k; ++j) {
      *i = j;
      if (x == spokes[j]) return 0;
      if (x == T::next(spokes[j])) return 1;
      if (x == T::prev(spokes[j])) return 2;
    }
    inconsistent("an input edge leaves the star of a vertex through a spoke");
  };
  for (int step = 0; step <= 2 * k + 2; ++step) {
    const int s = T::side(h);
    const FaceCounts c = counts(T::face(h));
    if (p < 1 || p > c.n[s]) inconsistent("arc position out of range in a vertex star");
    Index exit = kInvalidIndex;
    int q = 0;  // exit's q-th crossing from its tail
    if (p <= c.corner[s]) {
      exit = T::prev(h);
      q = c.n[(s + 2) % 3] - p + 1;
    } else if (p <= c.corner[s] + c.fan[(s + 2) % 3]) {  // ends at tail(prev(h))
      int i = 0;
      const int r = role(T::prev(h), &i);
      const Index hp = T::prev(h);
      const int spoke =
          spoke_index(tri_.tail(hp), r_[hp], (shared(hp) ? 1 : 0) + p - c.corner[s] - 1);
      if (r == 0) return {StarEnd::kCentre, 0, 0, spoke};
      return {StarEnd::kCorner, r == 1 ? i : (i + 1) % k, 0, spoke};
    } else {
      exit = T::next(h);
      q = c.n[s] - p + 1;
    }
    int i = 0;
    const int exit_role = role(exit, &i);
    if (exit_role == 1) return {StarEnd::kOuter, i, q};
    if (*crossed < 0) *crossed = exit_role == 0 ? i : (i + 1) % k;
    h = tri_.twin(exit);
    p = std::max(0, n_[tri_.edge(exit)]) - q + 1;
  }
  inconsistent("an input edge does not leave the star of a vertex");
}

// Every input edge piece inside v's star as a chord between two ends on the star's boundary,
// each once (ends ordered along the boundary: (ring, pos), a ring vertex with pos 0); at a
// vertex on an input edge, its two pieces are joined into one chord, the last, from the end
// along v's spoke 0 to the end along spoke 1. False if the pieces ending at v are not one per
// spoke of v, or v has other than 0 or 2 spokes.
bool NormalCoordinateTriangulation::star_chords(Index v, const std::vector<Index>& spokes,
                                                std::vector<StarChord>* chords) const {
  const int k = static_cast<int>(spokes.size());
  std::vector<std::pair<int, StarEnd>> at_centre;  // (spoke of v, other end)
  auto key = [](const StarEnd& e) { return std::pair(e.ring, e.pos); };
  int crossed = -1;
  auto add = [&](const StarEnd& from, const StarEnd& to) {
    if (to.kind == StarEnd::kCentre) {
      at_centre.emplace_back(to.spoke, from);
    } else if (key(from) < key(to)) {
      chords->push_back({{from, to}, crossed});
    }
  };
  for (int i = 0; i < k; ++i) {
    const Index o = T::next(spokes[i]);
    for (int j = 1; j <= n_[tri_.edge(o)]; ++j) {
      crossed = -1;
      add({StarEnd::kOuter, i, j}, walk_star(spokes, o, j, &crossed));
    }
  }
  for (int i = 0; i < k; ++i) {
    const Index h = spokes[i], g = T::prev(h);
    const FaceCounts c = counts(T::face(h));
    const int sh = T::side(h), so = (sh + 1) % 3, sg = (sh + 2) % 3;
    // ring i's fan crosses g_i after corner[sg] arcs from ring i+1; ring i+1's fan crosses h_i
    // after corner[sh] arcs from v
    for (int m = 1; m <= c.fan[so]; ++m) {
      crossed = (i + 1) % k;
      add({StarEnd::kCorner, i, 0},
          walk_star(spokes, tri_.twin(g), c.n[sg] - c.corner[sg] - m + 1, &crossed));
    }
    for (int m = 1; m <= c.fan[sg]; ++m) {
      crossed = i;
      add({StarEnd::kCorner, (i + 1) % k, 0},
          walk_star(spokes, tri_.twin(h), c.n[sh] - c.corner[sh] - m + 1, &crossed));
    }
    if (n_[tri_.edge(h)] < 0) {  // along h_i
      at_centre.emplace_back(r_[h], StarEnd{StarEnd::kCorner, i, 0, r_[tri_.twin(h)]});
    }
  }
  if (at_centre.size() != spokes_[v].size()) return false;
  if (at_centre.empty()) return true;
  if (at_centre.size() != 2 || key(at_centre[0].second) == key(at_centre[1].second)) return false;
  if (at_centre[0].first == at_centre[1].first) return false;
  if (at_centre[0].first != 0) std::swap(at_centre[0], at_centre[1]);
  chords->push_back({{at_centre[0].second, at_centre[1].second}, -1});
  return true;
}

// Long function: one straight sequence (chords, the side of each, the counts, the update).
bool NormalCoordinateTriangulation::move_inserted_vertex(Index v, const Eigen::Vector2d& d,
                                                         double min_relative_height) {
  std::vector<Index> hs;
  std::vector<Eigen::Vector2d> ring;
  const StarMove check =
      check_star_move(tri_, v, n_input_vertices(), d, min_relative_height, &hs, &ring);
  if (check != StarMove::kMoves) return check == StarMove::kStays;
  std::vector<StarChord> chords;
  if (!star_chords(v, hs, &chords)) return false;
  const int k = static_cast<int>(hs.size());
  std::vector<std::vector<InputCrossing>> outer(k);
  double radius = 0.0;
  for (int i = 0; i < k; ++i) {
    radius = std::max(radius, ring[i].norm());
    if (n_[tri_.edge(T::next(hs[i]))] > 0) outer[i] = trace_halfedge(T::next(hs[i]));
  }
  auto position = [&](const StarEnd& e) -> Eigen::Vector2d {
    if (e.kind == StarEnd::kCorner) return ring[e.ring];
    const double t = outer[e.ring][e.pos - 1].t;
    return (1.0 - t) * ring[e.ring] + t * ring[(e.ring + 1) % k];
  };
  auto key = [](const StarEnd& e) { return std::pair(e.ring, e.pos); };
  // the side of each chord (end 0 → end 1) the new position lies on: a chord splits the star
  // in two, and the new position (in the kernel) lies in the part on that side of its line.
  // Within rounding of the line but not of the chord: in the part v lies in (from the
  // integers: the part without the ring vertex whose spoke the chord crosses), as the segment
  // from v to it does not cross the chord. Within rounding of the chord itself (of one chord;
  // of several, the move is refused): v lands on that input edge and gets its two spokes (a
  // vertex on an input edge moved along it stays on it).
  const double tol = 1e-10 * radius;
  std::vector<char> left(chords.size(), 0);
  std::size_t on = chords.size();  // the chord v lands on, if any
  for (std::size_t c = 0; c < chords.size(); ++c) {
    const Eigen::Vector2d a = position(chords[c].end[0]), ab = position(chords[c].end[1]) - a;
    const double cr = cross2(ab, d - a), len = ab.norm();
    if (len > 100.0 * tol && std::abs(cr) > tol * len) {
      left[c] = cr > 0.0 ? 1 : 0;
      continue;
    }
    const double t = len > 0.0 ? std::clamp((d - a).dot(ab) / (len * len), 0.0, 1.0) : 0.0;
    if (len > 100.0 * tol && (d - a - t * ab).norm() <= tol) {
      if (on < chords.size()) return false;
      on = c;
      continue;
    }
    if (chords[c].crossed < 0) return false;  // v's own input edge, too short to tell
    const std::pair<int, int> kx(chords[c].crossed, 0);
    left[c] = in_cyclic_interval(key(chords[c].end[1]), key(chords[c].end[0]), kx) ? 0 : 1;
  }
  // per ring vertex x: chords crossing the new spoke to it (x in the other part than the new
  // position, by the order of the ends along the boundary), and chords ending at x that come
  // before the new spoke turning counter-clockwise from o_x (the new position on their far side)
  std::vector<int> n_new(k, 0), before(k, 0);
  for (std::size_t c = 0; c < chords.size(); ++c) {
    if (c == on) continue;
    const StarEnd& a = chords[c].end[0];
    const StarEnd& b = chords[c].end[1];
    for (int x = 0; x < k; ++x) {
      const std::pair<int, int> kx(x, 0);
      if (kx == key(a) || kx == key(b)) continue;
      if (in_cyclic_interval(key(b), key(a), kx) != (left[c] != 0)) ++n_new[x];
    }
    if (a.kind == StarEnd::kCorner) before[a.ring] += left[c];
    if (b.kind == StarEnd::kCorner) before[b.ring] += 1 - left[c];
  }
  // on an input edge: spoke 0 towards the chord's end 0, spoke 1 towards end 1; a new edge to
  // a ring vertex on the chord runs along it, another one turns counter-clockwise to spoke 1
  // first when its ring vertex lies left of the chord from end 1 to end 0
  std::vector<int> r_out(k, 0);
  std::vector<InputSpoke> new_spokes;
  if (on < chords.size()) {
    const StarEnd& e0 = chords[on].end[0];
    const StarEnd& e1 = chords[on].end[1];
    for (int x = 0; x < k; ++x) {
      const std::pair<int, int> kx(x, 0);
      if (kx == key(e0) || kx == key(e1)) {
        n_new[x] = -1;
        r_out[x] = kx == key(e0) ? 0 : 1;
      } else {
        r_out[x] = in_cyclic_interval(key(e0), key(e1), kx) ? 1 : 0;
      }
    }
    auto input_edge = [&](const StarEnd& e) {
      if (e.kind == StarEnd::kOuter) return outer[e.ring][e.pos - 1].input_edge;
      return e.spoke < 0 ? kInvalidIndex : spokes_[tri_.head(hs[e.ring])][e.spoke].input_edge;
    };
    Index ie =
        !spokes_[v].empty() && chords[on].crossed < 0 ? spokes_[v][0].input_edge : input_edge(e0);
    if (ie == kInvalidIndex) ie = input_edge(e1);
    if (ie == kInvalidIndex) return false;
    auto at = [&](const StarEnd& e) {
      return e.kind == StarEnd::kCorner ? vertex_at(tri_.head(hs[e.ring]), ie)
                                        : outer[e.ring][e.pos - 1].input_t;
    };
    const Eigen::Vector2d p0 = position(e0), p01 = position(e1) - p0;
    const double lambda = std::clamp((d - p0).dot(p01) / p01.squaredNorm(), 0.0, 1.0);
    const InputSpoke sp{ie, at(e0) + lambda * (at(e1) - at(e0))};
    new_spokes = {sp, sp};
  }
  spokes_[v] = std::move(new_spokes);
  for (int x = 0; x < k; ++x) {
    const Index o = T::next(hs[x]);
    tri_.set_length(tri_.edge(hs[x]), (ring[x] - d).norm());
    r_[tri_.twin(hs[x])] = spoke_index(tri_.tail(o), r_[o], (shared(o) ? 1 : 0) + before[x]);
    n_[tri_.edge(hs[x])] = n_new[x];
    r_[hs[x]] = r_out[x];
  }
  return true;
}

void NormalCoordinateTriangulation::validate() const {
  for (Index f = 0; f < tri_.n_faces(); ++f) {
    const FaceCounts c = counts(f);
    int fans = 0;
    for (int k = 0; k < 3; ++k) {
      const int twice = c.n[k] + c.n[(k + 2) % 3] - c.n[(k + 1) % 3] - c.fan[(k + 1) % 3] -
                        c.fan[(k + 2) % 3] + c.fan[k];
      if (twice < 0 || twice % 2 != 0) inconsistent("face " + std::to_string(f) + " has no arcs");
      fans += c.fan[k] > 0 ? 1 : 0;
    }
    if (fans > 1) inconsistent("face " + std::to_string(f) + " has arcs leaving two corners");
  }
  for (Index h = 0; h < tri_.n_halfedges(); ++h) {
    const auto d = static_cast<int>(spokes_[tri_.tail(h)].size());
    if (r_[h] < 0 || (d > 0 && r_[h] >= d) || (d == 0 && r_[h] != 0)) {
      inconsistent("roundabout of halfedge " + std::to_string(h) + " out of range");
    }
  }
}

// ---------------------------------------------------------------------------------------------
// Directions at input vertices (the 3D tangent bases of refined surfaces, D-280)

namespace {

// The input face left of the outgoing input halfedge `ih` (a wedge at its tail), laid out: corner
// j is the tail, corner j+1 the head.
struct WedgeLayout {
  Index ih = kInvalidIndex;
  int j = 0;
  Eigen::Vector2d p[3];
};

WedgeLayout wedge_layout(const IntrinsicTriangulation& input, Index ih) {
  WedgeLayout w;
  w.ih = ih;
  w.j = T::side(ih);
  face_layout(input, T::face(ih), w.p);
  return w;
}

// The angle from a to b, counter-clockwise, in (−π, π].
double angle_between(const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return std::atan2(a.x() * b.y() - a.y() * b.x(), a.dot(b));
}

// The angle at the wedge's corner from its first side (the input halfedge w.ih) to `first`, an
// intrinsic edge's first crossing, which lies on the wedge's side opposite the corner.
double first_crossing_angle(const IntrinsicTriangulation& input, const WedgeLayout& w,
                            const InputCrossing& first) {
  const Index ob = T::next(w.ih);
  if (input.edge(ob) != first.input_edge) inconsistent("a first crossing off its wedge");
  const double s =
      input.edge_halfedge(first.input_edge) == ob ? first.input_t : 1.0 - first.input_t;
  const Eigen::Vector2d x = w.p[(w.j + 1) % 3], y = w.p[(w.j + 2) % 3];
  return angle_between(x - w.p[w.j], x + s * (y - x) - w.p[w.j]);
}

}  // namespace

// The outgoing input halfedge of spoke k of input vertex v (a spoke that starts a wedge).
Index NormalCoordinateTriangulation::spoke_out(Index v, int k) const {
  const InputSpoke& s = spokes_[v][static_cast<std::size_t>(k)];
  const Index eh = input_.edge_halfedge(s.input_edge);
  const Index out = s.at == 0.0 ? eh : input_.twin(eh);
  if (out == kInvalidIndex) inconsistent("a wedge starting at an incoming boundary spoke");
  return out;
}

// The angle of h (tail an input vertex, n(h) = 0) from the first spoke of its wedge, walking
// clockwise: each intrinsic corner passed adds its angle, until a halfedge along an input edge
// (that spoke), one with crossings (its first crossing in the wedge), or a corner with spokes
// inside (the last of them crosses the opposite side at a traced point).
double NormalCoordinateTriangulation::wedge_angle(Index h) const {
  const Index v = tri_.tail(h);
  double acc = 0.0;
  Index cur = h;
  for (Index guard = 0; guard <= tri_.n_halfedges(); ++guard) {
    const Index tw = tri_.twin(cur);
    if (tw == kInvalidIndex) inconsistent("no spoke clockwise of a halfedge at a boundary vertex");
    const Index g = T::next(tw);  // clockwise of cur; face(g) has the corner (g, cur) at v
    const Index f = T::face(g);
    const int k = T::side(g);
    const FaceCounts c = counts(f);
    if (c.fan[k] > 0) {
      const std::vector<InputCrossing> across = trace_halfedge(T::next(g));
      const std::size_t i = static_cast<std::size_t>(c.corner[(k + 1) % 3] + c.fan[k] - 1);
      if (i >= across.size()) inconsistent("a fan arc missing from its opposite side");
      Eigen::Vector2d q[3];
      face_layout(tri_, f, q);
      const Eigen::Vector2d a = q[(k + 1) % 3], b = q[(k + 2) % 3];
      const Eigen::Vector2d at = a + across[i].t * (b - a);
      return acc + angle_between(at - q[k], b - q[k]);
    }
    acc += corner_angle(tri_, g);
    const int ng = n_[tri_.edge(g)];
    if (ng < 0) return acc;
    if (ng > 0) {
      const WedgeLayout w = wedge_layout(input_, spoke_out(v, spoke_index(v, r_[g], -1)));
      return acc + first_crossing_angle(input_, w, trace_halfedge(g).front());
    }
    cur = g;
  }
  inconsistent("the walk around an input vertex did not end");
}

Eigen::Vector3d NormalCoordinateTriangulation::halfedge_direction_3d(Index h) const {
  if (h < 0 || h >= tri_.n_halfedges()) {
    throw InvalidInput("halfedge_direction_3d: halfedge " + std::to_string(h) +
                       " out of range [0, " + std::to_string(tri_.n_halfedges()) + ")");
  }
  const Index v = tri_.tail(h);
  if (v >= n_input_vertices()) {
    throw InvalidInput("halfedge_direction_3d: halfedge " + std::to_string(h) +
                       " starts at inserted vertex " + std::to_string(v));
  }
  const Eigen::Vector3d xv = positions_.row(v).transpose();
  const int n = n_[tri_.edge(h)];
  if (n < 0) {  // along the input edge of spoke r(h), towards its other end
    const InputSpoke& s = spokes_[v][r_[h]];
    const Index eh = input_.edge_halfedge(s.input_edge);
    const Index w = s.at == 0.0 ? input_.head(eh) : input_.tail(eh);
    return (positions_.row(w).transpose() - xv).normalized();
  }
  if (n > 0) return (crossing_position(trace_halfedge(h).front()) - xv).normalized();
  const WedgeLayout w = wedge_layout(input_, spoke_out(v, spoke_index(v, r_[h], -1)));
  const double alpha = wedge_angle(h);
  const Eigen::Vector2d o = w.p[w.j], e1 = w.p[(w.j + 1) % 3] - o, e2 = w.p[(w.j + 2) % 3] - o;
  const Eigen::Vector2d u = e1.normalized();
  const Eigen::Vector2d d = std::cos(alpha) * u + std::sin(alpha) * Eigen::Vector2d(-u.y(), u.x());
  // d = a·e1 + b·e2 (Cramer's rule), mapped onto the 3D triangle
  const double det = e1.x() * e2.y() - e1.y() * e2.x();
  const Eigen::Vector2d ab((d.x() * e2.y() - d.y() * e2.x()) / det,
                           (e1.x() * d.y() - e1.y() * d.x()) / det);
  const Index x = input_.head(w.ih), y = input_.tail(T::prev(w.ih));
  const Eigen::Vector3d d3 =
      ab[0] * (positions_.row(x).transpose() - xv) + ab[1] * (positions_.row(y).transpose() - xv);
  return d3.normalized();
}

double NormalCoordinateTriangulation::angle_from_input_halfedge(Index h, Index from) const {
  if (h < 0 || h >= tri_.n_halfedges()) {
    throw InvalidInput("angle_from_input_halfedge: halfedge " + std::to_string(h) +
                       " out of range [0, " + std::to_string(tri_.n_halfedges()) + ")");
  }
  const Index v = tri_.tail(h);
  if (v >= n_input_vertices()) {
    throw InvalidInput("angle_from_input_halfedge: halfedge " + std::to_string(h) +
                       " starts at inserted vertex " + std::to_string(v));
  }
  if (from < 0 || from >= input_.n_halfedges() || input_.tail(from) != v) {
    throw InvalidInput("angle_from_input_halfedge: input halfedge " + std::to_string(from) +
                       " does not start at vertex " + std::to_string(v));
  }
  // h's direction as (an outgoing input halfedge b, the angle from b counter-clockwise)
  Index b = kInvalidIndex;
  double alpha = 0.0;
  const int n = n_[tri_.edge(h)];
  if (n < 0) {  // along the input edge of spoke r(h)
    const InputSpoke& s = spokes_[v][r_[h]];
    const Index eh = input_.edge_halfedge(s.input_edge);
    const Index in = s.at == 0.0 ? input_.twin(eh) : eh;  // into v (none: v is its tail)
    b = s.at == 0.0 ? eh : input_.twin(eh);
    if (b == kInvalidIndex) {  // an incoming boundary side: the far side of its face's corner
      b = T::next(in);
      alpha = corner_angle(input_, b);
    }
  } else {
    const WedgeLayout w = wedge_layout(input_, spoke_out(v, spoke_index(v, r_[h], -1)));
    b = w.ih;
    if (n == 0) {
      alpha = wedge_angle(h);
    } else {  // the first crossing, on the wedge's side opposite v
      alpha = first_crossing_angle(input_, w, trace_halfedge(h).front());
    }
  }
  // from `from` to b over the input's corners: counter-clockwise, or clockwise when the fan
  // ends at the boundary first
  double acc = 0.0;
  for (Index cur = from, guard = 0; guard <= input_.n_halfedges(); ++guard) {
    if (cur == b) return acc + alpha;
    const Index p = input_.twin(T::prev(cur));
    if (p == kInvalidIndex) break;
    acc += corner_angle(input_, cur);
    cur = p;
  }
  acc = 0.0;
  for (Index cur = from, guard = 0; guard <= input_.n_halfedges(); ++guard) {
    if (cur == b) return acc + alpha;
    const Index tw = input_.twin(cur);
    if (tw == kInvalidIndex) break;
    cur = T::next(tw);
    acc -= corner_angle(input_, cur);
  }
  throw InvalidInput("angle_from_input_halfedge: halfedge " + std::to_string(h) +
                     " is not in the fan of faces of input halfedge " + std::to_string(from) +
                     " at vertex " + std::to_string(v));
}

}  // namespace ifem::intrinsic
