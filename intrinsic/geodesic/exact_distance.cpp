// Window propagation (Chen & Han; Xin & Wang 2009) on an intrinsic triangulation. A window lives
// on a halfedge h and is about to enter face(h): an interval [b0, b1] of h seen from a source
// image I below h (in h's frame: tail(h) at the origin, head(h) at (L, 0), face(h) above), at
// distance σ from the source. Propagating it through face(h) gives at most two children on the
// two other sides (stored on their twins, in the next face's frame). Pruning, all of it exact:
//   - vertex filter: a window whose every point is reached more cheaply through one end of its
//     edge (a known vertex distance plus the straight run along the edge) is dropped;
//   - one angle, one split: of the windows through the corner C opposite h, the one reaching C
//     first keeps both children; for any other, the rays that cross that window's segment to C
//     are beaten by it (triangle inequality at the crossing) and are cut off.
//   - one window per halfedge remembered: a new window there is cut where that one beats it
//     (prune_window_by(): only where this is proven by convexity).
// Vertex distances are updated from every window through straight paths (bending at a window end
// if C lies outside it by rounding), so every bound is a path's length.
#include "intrinsic/geodesic/exact_distance.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <sstream>

#include "intrinsic/core/geometry.h"
#include "intrinsic/refine/delaunay_refine.h"

namespace ifem::intrinsic {
namespace {

using T = IntrinsicTriangulation;
using Vec2 = Eigen::Vector2d;
using Window = ExactDistance::Window;
constexpr double kInf = std::numeric_limits<double>::infinity();

// A queue entry carries its window (read in key order, a window stored apart would be a cache
// miss at every pop; one pruned when it comes up is never stored), or a vertex: w.h = −1 − v.
struct Entry {
  double key;
  Window w;
};
Entry vertex_entry(double d, Index v) { return {d, {0.0, 0.0, 0.0, 0.0, 0.0, -1 - v, 0}}; }

// Monotone priority queue on non-negative keys (a radix heap: Ahuja, Mehlhorn, Orlin & Tarjan
// 1990, on the bits of the doubles, whose order as unsigned integers is that of the values).
// Every key pushed is at least the last one popped (a child window or a vertex is never nearer
// than the window that made it); one below it by rounding is filed as the last popped one, and
// pop() still returns its own key. Each entry moves down at most 64 buckets, most of them once
// or twice: several times cheaper than a binary heap of millions of entries.
class RadixQueue {
 public:
  bool empty() const { return size_ == 0; }
  std::size_t size() const { return size_; }
  void push(const Entry& e) {
    buckets_[bucket_of(bits_of(e.key))].push_back(e);
    ++size_;
  }
  Entry pop() {
    if (buckets_[0].empty()) refill();
    const Entry e = buckets_[0].back();
    buckets_[0].pop_back();
    --size_;
    return e;
  }

 private:
  std::uint64_t bits_of(double key) const {
    std::uint64_t b = 0;
    const double k = key > 0.0 ? key : 0.0;
    std::memcpy(&b, &k, sizeof b);
    return std::max(b, last_);
  }
  int bucket_of(std::uint64_t b) const { return b == last_ ? 0 : 64 - __builtin_clzll(b ^ last_); }
  // Moves the least non-empty bucket's entries down, with last_ its least key.
  void refill() {
    int i = 1;
    while (buckets_[i].empty()) ++i;
    std::vector<Entry>& from = buckets_[i];
    std::uint64_t least = ~std::uint64_t{0};
    for (const Entry& e : from) least = std::min(least, bits_of(e.key));
    last_ = least;
    for (const Entry& e : from) buckets_[bucket_of(bits_of(e.key))].push_back(e);
    from.clear();
  }
  std::vector<Entry> buckets_[65];
  std::uint64_t last_ = 0;
  std::size_t size_ = 0;
};

// |(x, y)|: the plain formula (std::hypot's care costs several times more on the hot path; lengths
// here are far from over- or underflow in squaring for any mesh below 1e150 units).
inline double norm2(double x, double y) { return std::sqrt(x * x + y * y); }

// Corner of face(h) opposite h in h's frame.
Vec2 apex_of(const T& tri, Index h) {
  return triangle_apex(tri.halfedge_length(h), tri.halfedge_length(T::next(h)),
                       tri.halfedge_length(T::prev(h)));
}

// Where the ray from `img` through (x, 0) meets the segment p0 → p1, as a fraction of it in
// [0, 1].
double ray_fraction(const Vec2& p0, const Vec2& p1, const Vec2& img, double x) {
  const Vec2 d(x - img.x(), -img.y());
  const double den = cross2(p1 - p0, d);
  const double t = cross2(img - p0, d) / den;
  return std::isfinite(t) ? std::clamp(t, 0.0, 1.0) : 0.0;
}

std::string mb(double bytes) {
  std::ostringstream s;
  s.precision(3);
  s << bytes / 1e6 << " MB";
  return s.str();
}

// What a window reads of its halfedge h, in one record (a window pops far from the previous one
// in memory: one cache line instead of a load from each of the triangulation's arrays).
struct HalfedgeRecord {
  double L;                     // length
  double ax, ay;                // apex_of(h): the corner of face(h) opposite h, in h's frame
  Index twin, tail, head, opp;  // opp: tail(prev(h)), the corner opposite h
};

class Propagator {
 public:
  Propagator(const T& tri, ExactDistance& out, double budget_bytes)
      : tri_(tri), out_(out), nv_(tri.n_vertices()), keep_(out.has_paths) {
    max_windows_ = static_cast<std::size_t>(std::max(1.0, budget_bytes / kExactWindowBytes));
    budget_ = budget_bytes;
    out_.distance = Eigen::VectorXd::Constant(nv_, kInf);
    out_.vertex_parent.assign(static_cast<std::size_t>(nv_), ExactDistance::kNone);
    out_.vertex_x.assign(static_cast<std::size_t>(nv_), 0.0);
    split_d_.assign(static_cast<std::size_t>(tri.n_halfedges()), kInf);
    split_x_.assign(static_cast<std::size_t>(tri.n_halfedges()), 0.0);
    emitted_.assign(static_cast<std::size_t>(nv_), 0);
    arrive_he_.assign(static_cast<std::size_t>(nv_), kInvalidIndex);
    arrive_phi_.assign(static_cast<std::size_t>(nv_), 0.0);
    // Outgoing halfedges per vertex (CSR).
    start_.assign(static_cast<std::size_t>(nv_) + 1, 0);
    for (Index h = 0; h < tri.n_halfedges(); ++h) ++start_[tri.tail(h) + 1];
    for (Index v = 0; v < nv_; ++v) start_[v + 1] += start_[v];
    out_he_.resize(static_cast<std::size_t>(tri.n_halfedges()));
    std::vector<Index> fill(start_.begin(), start_.end() - 1);
    for (Index h = 0; h < tri.n_halfedges(); ++h) out_he_[fill[tri.tail(h)]++] = h;
    find_pseudo_sources();
    // Address space only (pages are touched as windows come): no copy while the store grows
    // on typical meshes.
    if (keep_) {
      out_.window_store.reserve(std::min(max_windows_, 32 * std::size_t(tri.n_halfedges())));
    }
    he_.resize(static_cast<std::size_t>(tri.n_halfedges()));
    recent_.assign(std::size_t(tri.n_halfedges()) * kRecent, {0.0, -1.0, 0.0, 0.0, 0.0, 0, 0});
    recent_next_.assign(std::size_t(tri.n_halfedges()), 0);
    for (Index h = 0; h < tri.n_halfedges(); ++h) {
      const Vec2 a = apex_of(tri, h);
      he_[h] = {tri.halfedge_length(h), a.x(), a.y(), tri.twin(h), tri.tail(h), tri.head(h),
                tri.tail(T::prev(h))};
    }
  }

  void add_vertex_source(Index v) {
    out_.distance[v] = 0.0;
    out_.vertex_parent[v] = ExactDistance::kNone;
    queue_.push(vertex_entry(0.0, v));
  }

  // Source k at barycentric `bary` of face f, not at a corner.
  void add_point_source(Index f, const Eigen::Vector3d& bary, Index k) {
    emit_from_point(f, bary, k);
    for (int s = 0; s < 3; ++s) {
      if (bary[(s + 2) % 3] != 0.0) continue;  // the point is on side s: the face beyond too
      const Index g = tri_.twin(3 * f + s);
      if (g == kInvalidIndex) continue;
      const double t = bary[(s + 1) % 3];  // fraction along side s from its tail
      Eigen::Vector3d b2 = Eigen::Vector3d::Zero();
      b2[T::side(g)] = t;
      b2[(T::side(g) + 1) % 3] = 1.0 - t;
      emit_from_point(T::face(g), b2, k);
    }
  }

  void run() {
    while (!queue_.empty()) {
      const Entry e = queue_.pop();
      if (e.w.h >= 0) {
        propagate(e.w);
      } else {
        const Index v = -1 - e.w.h;
        if (emitted_[v] || e.key > out_.distance[v]) continue;
        emitted_[v] = 1;
        emit_from_vertex(v);
      }
    }
    out_.windows = created_;
  }

 private:
  // Saddles (angle sum > 2π) are pseudo-sources (1); so are boundary vertices and vertices whose
  // corners form more than one cycle (a pinched vertex of a tufted cover), where geodesics bend
  // too: these emit into every corner (2).
  void find_pseudo_sources() {
    pseudo_.assign(static_cast<std::size_t>(nv_), 0);
    const Eigen::VectorXd angle = vertex_angle_sums(tri_);
    for (Index v = 0; v < nv_; ++v) {
      pseudo_[v] = angle[v] > 2.0 * kPi * (1.0 + 1e-12) ? 1 : 0;
      const Index h0 = tri_.vertex_halfedge(v);
      if (h0 == kInvalidIndex) continue;
      Index n = 0, h = h0;
      do {
        ++n;
        h = tri_.twin(T::prev(h));
      } while (h != kInvalidIndex && h != h0 && n <= start_[v + 1] - start_[v]);
      if (h != h0 || n != start_[v + 1] - start_[v]) pseudo_[v] = 2;
    }
  }

  // Lowers v's distance to d (a path's length: through `parent`, crossing its halfedge at x).
  // True when v is a pseudo-source still to emit whose arrival the caller may record
  // (arrive()): d is its distance now, or ties it to rounding (kTie) while no arrival is known.
  // A tie keeps a known arrival: that path is as short, and its windows pass v.
  bool relax(Index v, double d, Index parent, double x) {
    const double cur = out_.distance[v];
    if (!(d < cur)) {
      return d <= cur * (1.0 + kTie) && pseudo_[v] && !emitted_[v] &&
             arrive_he_[v] == kInvalidIndex;
    }
    out_.distance[v] = d;
    out_.vertex_parent[v] = parent;
    out_.vertex_x[v] = x;
    if (!pseudo_[v] || emitted_[v]) return false;
    if (d < cur * (1.0 - kTie)) arrive_he_[v] = kInvalidIndex;  // not a tie: forget the arrival
    queue_.push(vertex_entry(d, v));
    return arrive_he_[v] == kInvalidIndex;
  }
  // The path reaching v arrives straight from the direction at angle phi counter-clockwise from
  // the outgoing halfedge o (tail(o) = v), through a window that also has rays on both sides
  // of v: only then do the windows passing v cover the directions outside its shadow.
  void arrive(Index v, Index o, double phi) {
    arrive_he_[v] = o;
    arrive_phi_[v] = phi;
  }

  // Cuts off the parts of w whose points are reached more cheaply through an end of its edge
  // (a vertex distance plus the run along the edge): σ + |I x| − x falls along the edge and
  // σ + |I x| + x rises, so each end dominates an interval next to it, whose end solves a
  // linear equation. False when nothing is left.
  bool trim(Window& w) const {
    const HalfedgeRecord& e = he_[w.h];
    const double L = e.L;
    const double da = out_.distance[e.tail] - w.sigma;
    const double db = out_.distance[e.head] - w.sigma;
    const double r2 = w.ix * w.ix + w.iy * w.iy;
    if (da < kInf) {
      const double den = 2.0 * (w.ix + da);
      if (den > 0.0) {
        w.b0 = std::max(w.b0, (r2 - da * da) / den - kTrimSlack * L);
      } else if (da + w.b1 < norm2(w.b1 - w.ix, w.iy)) {
        return false;
      }
    }
    if (db < kInf) {
      const double jx = L - w.ix;
      const double den = 2.0 * (jx + db);
      if (den > 0.0) {
        w.b1 = std::min(w.b1, L - (jx * jx + w.iy * w.iy - db * db) / den + kTrimSlack * L);
      } else if (db + (L - w.b0) < norm2(w.b0 - w.ix, w.iy)) {
        return false;
      }
    }
    if (!(w.b1 > w.b0)) return false;
    // The far corner of face(h) and the near one of the face behind: a vertex that beats both
    // ends of w beats all of it (the points p with dv + |v p| < σ + |I p| form a convex set).
    if (beats(e.opp, Vec2(e.ax, e.ay), w)) return false;
    if (e.twin != kInvalidIndex) {
      const HalfedgeRecord& d = he_[e.twin];
      if (beats(d.opp, Vec2(L - d.ax, -d.ay), w)) return false;
    }
    return true;
  }

  // True when vertex v at `pos` (in w's frame) reaches every point of w more cheaply than w.
  bool beats(Index v, const Vec2& pos, const Window& w) const {
    return point_beats_window(pos.x(), pos.y(), out_.distance[v], w, kTie);
  }

  // Cuts w by the last kRecent windows pushed on its halfedge (prune_window_by()). True
  // when nothing of w is left; else w is recorded in the ring.
  bool dominated(Window& w) {
    Window* ring = &recent_[std::size_t(w.h) * kRecent];
    for (int k = 0; k < kRecent; ++k) {
      const auto [b0, b1] = prune_window_by(ring[k], w);
      w.b0 = b0;
      w.b1 = b1;
      if (!(w.b1 > w.b0)) return true;
    }
    unsigned char& next = recent_next_[w.h];
    ring[next] = w;
    next = static_cast<unsigned char>((next + 1) % kRecent);
    return false;
  }

  void push_window(Window w) {
    if (!(w.b1 > w.b0)) return;
    if (!trim(w)) return;
    if (dominated(w)) return;
    if ((keep_ ? created_ : queue_.size()) >= max_windows_) {
      std::ostringstream m;
      m << "exact distance: more than " << max_windows_ << " windows"
        << (keep_ ? "" : " waiting at once") << " (" << mb(double(max_windows_) * kExactWindowBytes)
        << " at " << kExactWindowBytes << " bytes each) exceed the memory budget of " << mb(budget_)
        << "; raise it (ExactDistanceOptions::max_memory_bytes, `--memory-budget GB` in the "
           "CLI, memory_budget= in Python) or use the heat method";
      throw InvalidInput(m.str());
    }
    const double nearest_x = std::clamp(w.ix, w.b0, w.b1);
    const double key = w.sigma + norm2(nearest_x - w.ix, w.iy);
    ++created_;
    queue_.push({key, w});
  }

  // Windows from u at its distance on the far sides of the faces around it: of every face for a
  // source or a vertex of kind 2, else only the rays into u's shadow, the directions at least π
  // from the arriving path on both sides (the others are reached by the windows that passed u).
  void emit_from_vertex(Index u) {
    const double sigma = out_.distance[u];
    ++out_.pseudo_sources;
    for (Index k = start_[u]; k < start_[u + 1]; ++k) {
      const Index h = out_he_[k];
      relax(tri_.head(h), sigma + tri_.halfedge_length(h), -1 - u, 0.0);
      relax(tri_.tail(T::prev(h)), sigma + tri_.halfedge_length(T::prev(h)), -1 - u, 0.0);
    }
    const Index oa = arrive_he_[u];
    if (pseudo_[u] == 2 || oa == kInvalidIndex || out_.vertex_parent[u] == ExactDistance::kNone) {
      for (Index k = start_[u]; k < start_[u + 1]; ++k) emit_corner(u, out_he_[k], 0.0, kInf);
      return;
    }
    // Cumulative angles around u's one cycle of corners, from the arriving corner.
    double total = 0.0;
    ring_.clear();
    for (Index h = oa;;) {
      const double alpha = corner_angle(tri_, h);
      ring_.push_back({h, total, alpha});
      total += alpha;
      h = tri_.twin(T::prev(h));
      if (h == oa) break;
    }
    constexpr double kWiden = 1e-9;  // emit a little more than the shadow (rounding)
    const double lo = kPi - kWiden, hi = total - kPi + kWiden;
    if (!(hi > lo)) return;
    const double a = arrive_phi_[u];
    for (const Corner& c : ring_) {
      for (double shift : {-total, 0.0, total}) {  // δ = angle from the arrival, in [0, total)
        const double d0 = c.start - a + shift;
        const double from = std::max(lo, d0), to = std::min(hi, d0 + c.angle);
        if (from < to) emit_corner(u, c.h, from - d0, to - d0);
      }
    }
  }

  // The window from u (= tail(o)) on the side of face(o) opposite u, for the rays at angles
  // [psi0, psi1] from o (counter-clockwise; the whole corner when psi1 ≥ its angle).
  void emit_corner(Index u, Index o, double psi0, double psi1) {
    const Index s = T::next(o), g = tri_.twin(s);
    if (g == kInvalidIndex) return;
    const double L = tri_.halfedge_length(s);
    const Vec2 a = apex_of(tri_, s);
    double b0 = 0.0, b1 = L;
    if (psi0 > 0.0 || psi1 < corner_angle(tri_, o)) {
      const double beta = corner_angle(tri_, s), lub = tri_.halfedge_length(o);
      // distance from head(o) along s of the ray at angle psi (law of sines)
      auto along = [&](double psi) { return lub * std::sin(psi) / std::sin(psi + beta); };
      if (psi1 < corner_angle(tri_, o)) b0 = std::clamp(L - along(psi1), 0.0, L);
      if (psi0 > 0.0) b1 = std::clamp(L - along(psi0), 0.0, L);
    }
    push_window({b0, b1, L - a.x(), -a.y(), out_.distance[u], g, -1 - u});
  }

  void emit_from_point(Index f, const Eigen::Vector3d& bary, Index k) {
    const Index origin = -1 - (nv_ + k);
    for (int s = 0; s < 3; ++s) {
      const Index h = 3 * f + s;
      const double L = tri_.halfedge_length(h);
      const Vec2 c = apex_of(tri_, h);
      const Vec2 p = bary[(s + 1) % 3] * Vec2(L, 0.0) + bary[(s + 2) % 3] * c;
      relax(tri_.tail(h), p.norm(), origin, 0.0);
      if (bary[(s + 2) % 3] == 0.0) continue;  // on side s
      const Index g = tri_.twin(h);
      if (g == kInvalidIndex) continue;
      push_window({0.0, L, L - p.x(), -p.y(), 0.0, g, origin});
    }
  }

  void propagate(Window w);

  static constexpr double kTrimSlack = 1e-13;  // trimming stops short by this × the edge
  static constexpr double kTie = 1e-12;        // distances this close (relative) tie
  const T& tri_;
  ExactDistance& out_;
  const Index nv_;
  const bool keep_;  // ExactDistanceOptions::keep_paths
  std::size_t max_windows_ = 0;
  std::size_t created_ = 0;  // windows pushed (each costs kExactWindowBytes at most)
  // Windows remembered per halfedge: 1, 2 and 4 leave 26%, 27% and 28% fewer windows on a
  // range scan at about the same time; one costs the least memory (docs/decisions.md D-296).
  static constexpr int kRecent = 1;
  std::vector<Window> recent_;              // per halfedge, kRecent windows pushed on it
  std::vector<unsigned char> recent_next_;  // per halfedge: the ring's slot to fill next
  double budget_ = 0.0;
  std::vector<double> split_d_, split_x_;
  std::vector<char> pseudo_, emitted_;
  std::vector<HalfedgeRecord> he_;  // per halfedge
  std::vector<Index> arrive_he_;
  std::vector<double> arrive_phi_;
  struct Corner {
    Index h;
    double start, angle;
  };
  std::vector<Corner> ring_;
  std::vector<Index> start_, out_he_;
  RadixQueue queue_;
};

// w as pushed: trimmed then (push_window()), not again here (the vertex distances improve
// between push and pop, but a second trim dropped 1 window in 10,000 and cost ~8% of the time;
// docs/decisions.md D-321).
void Propagator::propagate(Window w) {
  // Without the store, ids only have to differ from the origins' (−1 − origin): 0 for all.
  const Index id = keep_ ? static_cast<Index>(out_.window_store.size()) : 0;
  if (keep_) out_.window_store.push_back(w);
  const Index h = w.h;
  const HalfedgeRecord& e = he_[h];
  const double L = e.L;
  const Vec2 img(w.ix, w.iy), c(e.ax, e.ay);
  const Vec2 p0(w.b0, 0.0), p1(w.b1, 0.0);
  relax(e.tail, w.sigma + (p0 - img).norm() + w.b0, id, w.b0);
  relax(e.head, w.sigma + (p1 - img).norm() + (L - w.b1), id, w.b1);
  if (!(c.y() > 0.0)) return;  // a degenerate face: nothing beyond
  const double xc = w.ix + (c.x() - w.ix) * (-w.iy) / (c.y() - w.iy);
  const double xs = std::clamp(xc, w.b0, w.b1);
  const Vec2 xp(xs, 0.0);
  if (relax(e.opp, w.sigma + (xp - img).norm() + (c - xp).norm(), id, xs) && xs == xc &&
      w.b0 < xc && xc < w.b1) {  // a straight arrival with rays on both sides
    const Vec2 ca = -c, cx = xp - c;
    arrive(e.opp, T::prev(h), std::atan2(cross2(ca, cx), ca.dot(cx)));
  }
  // One angle, one split.
  double left_end = std::min(w.b1, xc), right_start = std::max(w.b0, xc);
  const double dc = w.sigma + (c - img).norm();
  if (split_d_[h] < dc) {
    const double xo = split_x_[h];
    if (xo < xc) left_end = std::min(left_end, xo);
    if (xo > xc) right_start = std::max(right_start, xo);
  } else if (w.b0 < xc && xc < w.b1) {
    split_d_[h] = dc;
    split_x_[h] = xc;
  }
  if (w.b0 < left_end) {  // onto side C → A, stored on its twin (A → C)
    const HalfedgeRecord& side = he_[T::prev(h)];
    const Index g = side.twin;
    if (g != kInvalidIndex) {
      const double lac = side.L;
      const Vec2 a(0.0, 0.0), u = c / lac;
      const double t0 = ray_fraction(a, c, img, w.b0);
      const double t1 = left_end == xc ? 1.0 : ray_fraction(a, c, img, left_end);
      push_window({t0 * lac, t1 * lac, u.dot(img), std::min(0.0, cross2(u, img)), w.sigma, g, id});
    }
  }
  if (right_start < w.b1) {  // onto side B → C, stored on its twin (C → B)
    const HalfedgeRecord& side = he_[T::next(h)];
    const Index g = side.twin;
    if (g != kInvalidIndex) {
      const double lcb = side.L;
      const Vec2 b(L, 0.0), u = (b - c) / lcb, r = img - c;
      const double t0 = right_start == xc ? 0.0 : ray_fraction(c, b, img, right_start);
      const double t1 = ray_fraction(c, b, img, w.b1);
      push_window({t0 * lcb, t1 * lcb, u.dot(r), std::min(0.0, cross2(u, r)), w.sigma, g, id});
    }
  }
}

}  // namespace

namespace {

// Real roots of σ' + |I' x| = σ + |I x| on the line (squared twice: a quadratic; it may add
// roots that are not crossings, which prune_window_by() checks out).
int crossings(const Window& r, const Window& w, double roots[2]) {
  const double u = w.ix - r.ix, delta = w.sigma - r.sigma;
  const double k = r.ix * r.ix - w.ix * w.ix + r.iy * r.iy - w.iy * w.iy - delta * delta;
  const double d2 = delta * delta;
  const double qa = u * u - d2, qb = u * k + 2.0 * d2 * w.ix;
  const double qc = 0.25 * k * k - d2 * (w.ix * w.ix + w.iy * w.iy);
  if (std::abs(qa) < 1e-300) {
    if (qb == 0.0) return 0;
    roots[0] = -qc / qb;
    return 1;
  }
  const double disc = qb * qb - 4.0 * qa * qc;
  if (disc < 0.0) return 0;
  const double sq = std::sqrt(disc);
  roots[0] = (-qb - sq) / (2.0 * qa);
  roots[1] = (-qb + sq) / (2.0 * qa);
  return 2;
}

}  // namespace

std::pair<double, double> prune_window_by(const ExactDistance::Window& other,
                                          const ExactDistance::Window& w) {
  const Window& r = other;
  if (!(r.sigma >= w.sigma) || r.b1 <= w.b0 || w.b1 <= r.b0) return {w.b0, w.b1};
  const auto beaten = [&](double x) {
    return x >= r.b0 && x <= r.b1 &&
           norm2(x - r.ix, r.iy) + r.sigma <= norm2(x - w.ix, w.iy) + w.sigma;
  };
  const bool at0 = beaten(w.b0), at1 = beaten(w.b1);
  if (at0 && at1) return {w.b0, w.b0};
  if (!at0 && !at1) return {w.b0, w.b1};
  double roots[2];
  const int n = crossings(r, w, roots);
  const double nudge = 1e-13 * (std::abs(w.b0) + std::abs(w.b1));  // a root rounded outside
  if (at0) {  // the least crossing beyond b0 ends the beaten piece
    double t = std::min(w.b1, r.b1);
    for (int i = 0; i < n; ++i) {
      if (roots[i] > w.b0 && roots[i] < t) t = roots[i];
    }
    if (!beaten(t)) t -= nudge;
    return {t > w.b0 && beaten(t) ? t : w.b0, w.b1};
  }
  double t = std::max(w.b0, r.b0);
  for (int i = 0; i < n; ++i) {
    if (roots[i] < w.b1 && roots[i] > t) t = roots[i];
  }
  if (!beaten(t)) t += nudge;
  return {w.b0, t < w.b1 && beaten(t) ? t : w.b1};
}

bool point_beats_window(double px, double py, double d, const ExactDistance::Window& w,
                        double tie) {
  if (!(d < kInf) || !(w.b1 >= w.b0)) return false;
  const double e0 = norm2(w.b0 - w.ix, w.iy) + w.sigma;
  if (!(d + norm2(w.b0 - px, py) < e0 * (1.0 - tie))) return false;
  const double e1 = norm2(w.b1 - w.ix, w.iy) + w.sigma;
  if (!(d + norm2(w.b1 - px, py) < e1 * (1.0 - tie))) return false;
  if (d >= w.sigma) return true;  // the set the point beats is convex: both ends, all of it
  // d < σ: w's own set is the convex one, so w may still win inside (b0, b1), between two
  // crossings; no crossing there means the sign holds all along.
  const Window r{w.b0, w.b1, px, py, d, w.h, w.parent};
  double roots[2];
  const int n = crossings(r, w, roots);
  for (int i = 0; i < n; ++i) {
    if (!(roots[i] <= w.b0 || roots[i] >= w.b1)) return false;  // NaN counts as inside
  }
  return true;
}

SurfacePoint corner_point(Index h) {
  SurfacePoint p;
  p.face = T::face(h);
  p.bary[T::side(h)] = 1.0;
  return p;
}

namespace {

// The point at distance x from tail(h) along h.
SurfacePoint on_halfedge(const T& tri, Index h, double x) {
  SurfacePoint p;
  p.face = T::face(h);
  const double t = std::clamp(x / tri.halfedge_length(h), 0.0, 1.0);
  p.bary[T::side(h)] = 1.0 - t;
  p.bary[(T::side(h) + 1) % 3] = t;
  return p;
}

void check_point(const T& tri, const SurfacePoint& p, std::size_t k) {
  const auto fail = [&](const std::string& why) {
    throw InvalidInput("exact_distance: source " + std::to_string(k) + " " + why);
  };
  if (p.face < 0 || p.face >= tri.n_faces()) {
    fail("has face " + std::to_string(p.face) + ", outside [0, " + std::to_string(tri.n_faces()) +
         ")");
  }
  if (!p.bary.allFinite() || p.bary.minCoeff() < 0.0 || std::abs(p.bary.sum() - 1.0) > 1e-9) {
    std::ostringstream m;
    m << "has barycentric coordinates (" << p.bary[0] << ", " << p.bary[1] << ", " << p.bary[2]
      << "): they must be finite, non-negative and sum to 1";
    fail(m.str());
  }
}

}  // namespace

ExactDistance exact_distance(const IntrinsicTriangulation& tri,
                             const std::vector<SurfacePoint>& sources,
                             const ExactDistanceOptions& options) {
  if (sources.empty()) throw InvalidInput("exact_distance: no source given");
  if (!(options.max_memory_bytes >= 0.0)) {
    throw InvalidInput("exact_distance: max_memory_bytes must be >= 0");
  }
  for (std::size_t k = 0; k < sources.size(); ++k) check_point(tri, sources[k], k);
  ExactDistance out;
  out.tri = &tri;
  out.has_paths = options.keep_paths;
  out.sources = sources;
  const double budget =
      options.max_memory_bytes > 0.0 ? options.max_memory_bytes : default_memory_budget();
  Propagator prop(tri, out, budget);
  for (std::size_t k = 0; k < sources.size(); ++k) {
    Eigen::Vector3d b = sources[k].bary / sources[k].bary.sum();
    Index corner = -1;
    b.maxCoeff(&corner);
    if (b[corner] >= 1.0 - 1e-12) {
      const Index v = tri.tail(3 * sources[k].face + corner);
      out.source_vertex.push_back(v);
      prop.add_vertex_source(v);
    } else {
      for (int c = 0; c < 3; ++c) {
        if (b[c] < 1e-15) b[c] = 0.0;
      }
      b /= b.sum();
      out.source_vertex.push_back(kInvalidIndex);
      out.sources[k].bary = b;
      prop.add_point_source(sources[k].face, b, Index(k));
    }
  }
  prop.run();
  return out;
}

ExactDistance exact_distance(const IntrinsicTriangulation& tri, const std::vector<Index>& sources,
                             const ExactDistanceOptions& options) {
  std::vector<SurfacePoint> points;
  for (std::size_t k = 0; k < sources.size(); ++k) {
    const Index v = sources[k];
    if (v < 0 || v >= tri.n_vertices()) {
      throw InvalidInput("exact_distance: source vertex " + std::to_string(v) + " outside [0, " +
                         std::to_string(tri.n_vertices()) + ")");
    }
    if (tri.vertex_halfedge(v) == kInvalidIndex) {
      throw InvalidInput("exact_distance: source vertex " + std::to_string(v) +
                         " is in no face (unreferenced)");
    }
    points.push_back(corner_point(tri.vertex_halfedge(v)));
  }
  return exact_distance(tri, points, options);
}

std::vector<SurfacePoint> ExactDistance::path_to_source(Index v) const {
  if (v < 0 || v >= distance.size()) {
    throw InvalidInput("path_to_source: vertex " + std::to_string(v) + " outside [0, " +
                       std::to_string(distance.size()) + ")");
  }
  if (!has_paths) {
    throw InvalidInput("path_to_source: the exact distance was run without keep_paths");
  }
  std::vector<SurfacePoint> path;
  if (!std::isfinite(distance[v])) return path;
  const T& t = *tri;
  const Index nv = t.n_vertices();
  for (std::size_t guard = 0; guard <= window_store.size() + std::size_t(nv); ++guard) {
    path.push_back(corner_point(t.vertex_halfedge(v)));
    Index p = vertex_parent[v];
    if (p == kNone) return path;  // a source vertex
    double x = vertex_x[v];
    while (p >= 0) {  // back through the windows
      const Window& w = window_store[p];
      path.push_back(on_halfedge(t, w.h, x));
      if (w.parent < 0) {
        p = w.parent;
        break;
      }
      const Window& up = window_store[w.parent];
      // w sits on the twin of a side of face(up.h); the crossing at x on w.h in up.h's frame.
      const double L = t.halfedge_length(up.h);
      const Vec2 c = apex_of(t, up.h);
      const bool right = t.twin(w.h) == T::next(up.h);
      const Vec2 from = right ? Vec2(L, 0.0) : c, to = right ? c : Vec2(0.0, 0.0);
      const double f = 1.0 - x / t.halfedge_length(w.h);  // along the side, from its tail
      const Vec2 q = from + f * (to - from);
      const double xp = up.ix + (q.x() - up.ix) * (-up.iy) / (q.y() - up.iy);
      x = std::clamp(std::isfinite(xp) ? xp : up.b0, up.b0, up.b1);
      p = w.parent;
    }
    const Index origin = -1 - p;
    if (origin >= nv) {
      path.push_back(sources[origin - nv]);
      return path;
    }
    v = origin;
  }
  throw InvalidInput("path_to_source: the parent chain loops (a bug)");
}

Index ExactDistance::nearest_source(Index v) const {
  if (!has_paths) {
    throw InvalidInput("nearest_source: the exact distance was run without keep_paths");
  }
  if (v < 0 || v >= distance.size() || !std::isfinite(distance[v])) return -1;
  const Index nv = tri->n_vertices();
  for (std::size_t guard = 0; guard <= window_store.size() + std::size_t(nv); ++guard) {
    Index p = vertex_parent[v];
    if (p == kNone) {
      for (std::size_t k = 0; k < source_vertex.size(); ++k) {
        if (source_vertex[k] == v) return Index(k);
      }
      return -1;
    }
    while (p >= 0) p = window_store[p].parent;
    const Index origin = -1 - p;
    if (origin >= nv) return origin - nv;
    v = origin;
  }
  return -1;
}

}  // namespace ifem::intrinsic
