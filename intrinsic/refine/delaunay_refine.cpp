#include "intrinsic/refine/delaunay_refine.h"

#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <iomanip>
#include <limits>
#include <optional>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "intrinsic/core/geometry.h"
#include "intrinsic/refine/conforming.h"

namespace ifem::intrinsic {
namespace {

using T = IntrinsicTriangulation;

// Triangles per (area / max_area) of a triangulation refined to max_area, over 2 (vertices):
// estimate_refinement()'s size term.
constexpr double kSizeTermFactor = 0.65;

// The refinement algorithm below is written once, over a "host": the triangulation it refines
// and the operations that change it. Hosts: a triangulation that keeps its correspondence with
// the input (signposts or integer coordinates: every operation also keeps the inserted vertices
// located on the input) and a bare Δ-complex. A host provides
//   const IntrinsicTriangulation& tri() const;
//   FlipReport flip_to_delaunay();
//   FlipReport flip_to_delaunay_from(const std::vector<Index>& queue, std::vector<Index>* touched);
//   Index insert_vertex(Index f, const Eigen::Vector3d& bary);
//   Index split_edge(Index e, double t);

// Every host takes the constrained edges' flags (may be null): its flips never flip those.

// A triangulation that keeps a correspondence with the input under every operation
// (SignpostTriangulation, NormalCoordinateTriangulation: the same operations by the same names).
template <class Tracked>
class TrackedHost {
 public:
  TrackedHost(Tracked& t, const std::vector<char>* fixed) : t_(t), fixed_(fixed) {}
  const IntrinsicTriangulation& tri() const { return t_.intrinsic(); }
  FlipReport flip_to_delaunay() {
    return fixed_ ? t_.flip_to_delaunay(*fixed_) : t_.flip_to_delaunay();
  }
  FlipReport flip_to_delaunay_from(const std::vector<Index>& queue, std::vector<Index>* touched) {
    return fixed_ ? t_.flip_to_delaunay_from(queue, touched, *fixed_)
                  : t_.flip_to_delaunay_from(queue, touched);
  }
  Index insert_vertex(Index f, const Eigen::Vector3d& bary) { return t_.insert_vertex(f, bary); }
  Index split_edge(Index e, double t) { return t_.split_edge(e, t); }

 private:
  Tracked& t_;
  const std::vector<char>* fixed_;
};

class PlainHost {
 public:
  PlainHost(IntrinsicTriangulation& tri, const std::vector<char>* fixed)
      : tri_(tri), fixed_(fixed) {}
  const IntrinsicTriangulation& tri() const { return tri_; }
  FlipReport flip_to_delaunay() { return tri_.flip_to_delaunay(flipper()); }
  FlipReport flip_to_delaunay_from(const std::vector<Index>& queue, std::vector<Index>* touched) {
    return tri_.flip_to_delaunay_from(queue, touched, flipper());
  }
  Index insert_vertex(Index f, const Eigen::Vector3d& bary) {
    return tri_.insert_vertex_in_face(f, bary);
  }
  Index split_edge(Index e, double t) { return tri_.split_edge(e, t); }

 private:
  std::function<bool(Index)> flipper() {
    return [this](Index e) { return !is_flagged(fixed_, e) && tri_.flip_edge(e); };
  }
  IntrinsicTriangulation& tri_;
  const std::vector<char>* fixed_;
};

// Sides a fan, a trace or an encroachment test stops at: boundary sides and the sides of
// constrained edges (flags may be null).
struct Barriers {
  const IntrinsicTriangulation& tri;
  const std::vector<char>* flags;
  bool constrained(Index e) const { return is_flagged(flags, e); }
  bool operator()(Index h) const {
    return tri.twin(h) == kInvalidIndex || constrained(tri.edge(h));
  }
  // the side glued to h, or kInvalidIndex at a barrier
  Index across(Index h) const { return (*this)(h) ? kInvalidIndex : tri.twin(h); }
};

// Total angle of the fan (cone) that the corner at tail(h) belongs to, and whether that fan
// reaches the boundary. At an ordinary vertex this is the vertex's angle sum; a pinched vertex
// (several fans: nonmanifold input, the input vertices of a tufted cover) is several cone
// points at once. Returns a value ≥ `limit` as soon as it is known to reach it (then
// `boundary` may be incomplete): first from the corners' cosines alone (one corner above the
// limit), then by adding up the angles.
double fan_angle(const Barriers& bar, Index h, double limit, bool* boundary) {
  const IntrinsicTriangulation& tri = bar.tri;
  const double cos_limit = std::cos(std::min(limit, kPi));
  const Index guard = tri.n_halfedges();
  // visits the corners of h's fan (counter-clockwise from h, then clockwise if open) until
  // `f` returns false; true if it never did
  auto walk = [&](auto&& f) {
    Index x = h;
    for (Index k = 0; k < guard; ++k) {
      if (!f(x)) return false;
      x = bar.across(T::prev(x));
      if (x == h) return true;
      if (x == kInvalidIndex) break;
    }
    x = bar.across(h);
    for (Index k = 0; k < guard && x != kInvalidIndex; ++k) {
      x = T::next(x);
      if (!f(x)) return false;
      x = bar.across(x);
    }
    return true;
  };
  const bool all_below = walk([&](Index x) {
    const double b = tri.halfedge_length(x), c = tri.halfedge_length(T::prev(x)),
                 a = tri.halfedge_length(T::next(x));
    return !(b * b + c * c - a * a < cos_limit * 2.0 * b * c);
  });
  if (!all_below) return limit;
  double sum = 0.0;
  *boundary = false;
  walk([&](Index x) {
    if (bar(x) || bar(T::prev(x))) *boundary = true;
    sum += corner_angle(tri, x);
    return sum < limit;
  });
  return sum;
}

// Which corners no insertion can fix: those whose fan's total angle is below the bound on the
// boundary, or below twice the bound inside (a second corner there would be too small).
// Decided per fan, not by a pinched vertex's total: a tufted cover doubles every input
// vertex's angle over two fans, and a needle tip of 0.8° (conrod.off) is a 1.7° fan next to
// a 720° total; judged by the total, refinement would never stop there. Fan angles are fixed
// by flips and insertions; inserted vertices are flat, so they are never needles. Vertices
// that start with a corner below the bound get their answer cached (every fan walked once:
// the pole of a needle sphere has 2000 corners); other corners walk their fan when asked,
// which on an ordinary mesh stops at the next corner.
class Cones {
 public:
  // constraints (flags, may be null) split fans like the boundary does
  Cones(const IntrinsicTriangulation& tri, double bound, const std::vector<char>* flags)
      : bound_(bound), flags_(flags) {
    const Barriers bar{tri, flags};
    const Index nv = tri.n_vertices(), nf = tri.n_faces(), nh = tri.n_halfedges();
    state_.assign(nv, 0);
    boundary_.assign(nv, 0);
    const double cos_bound = std::cos(bound);
    for (Index f = 0; f < nf; ++f) {
      const double l[3] = {tri.halfedge_length(3 * f), tri.halfedge_length(3 * f + 1),
                           tri.halfedge_length(3 * f + 2)};
      for (int k = 0; k < 3; ++k) {
        const Index h = 3 * f + k;
        if (bar(h)) boundary_[tri.tail(h)] = boundary_[tri.head(h)] = 1;
        const double b = l[k], c = l[(k + 2) % 3], a = l[(k + 1) % 3];
        if (b * b + c * c - a * a > cos_bound * 2.0 * b * c) state_[tri.tail(h)] = kCached;
      }
    }
    std::vector<char> seen(nh, 0);
    for (Index h = 0; h < nh; ++h) {
      if (seen[h] || !(state_[tri.tail(h)] & kCached)) continue;
      bool fan_boundary = false;
      const double theta = fan_angle(bar, h, 2.0 * bound_, &fan_boundary);
      state_[tri.tail(h)] |= unfixable(theta, fan_boundary) ? kSomeUnfixable : kSomeFixable;
      corners_.clear();
      Index x = h;  // mark the fan's corners (from h both ways)
      for (Index k = 0; k < nh && x != kInvalidIndex && !seen[x]; ++k) {
        seen[x] = 1;
        corners_.push_back(x);
        x = bar.across(T::prev(x));
      }
      x = bar.across(h);
      for (Index k = 0; k < nh && x != kInvalidIndex && !seen[T::next(x)]; ++k) {
        seen[T::next(x)] = 1;
        corners_.push_back(T::next(x));
        x = bar.across(T::next(x));
      }
      if (fan_boundary && unfixable(theta, true)) add_needle_sides(bar);
    }
    std::sort(needle_sides_.begin(), needle_sides_.end());
  }
  /// Whether the corner at tail(h) lies in a fan no insertion can fix.
  bool unfixable(const IntrinsicTriangulation& tri, Index h) const {
    const Index v = tri.tail(h);
    if (v >= static_cast<Index>(state_.size())) return false;  // inserted: flat
    const char known = state_[v] & (kSomeUnfixable | kSomeFixable);
    if (known == kSomeUnfixable || known == kSomeFixable) return known == kSomeUnfixable;
    bool fan_boundary = false;  // not cached, or fans of both kinds
    const double theta = fan_angle(Barriers{tri, flags_}, h, 2.0 * bound_, &fan_boundary);
    return unfixable(theta, fan_boundary);
  }
  /// Whether the edge from original vertex `apex` to original vertex `end` is a side of a
  /// needle at apex: a fan between two barrier sides (boundary or constrained) whose angle is
  /// below the bound.
  bool is_needle_side(Index apex, Index end) const {
    return std::binary_search(needle_sides_.begin(), needle_sides_.end(), std::pair{apex, end});
  }
  /// A vertex with a side without twin (or a constrained edge) starting or ending at it.
  bool is_boundary(Index v) const { return boundary_[v] != 0; }
  /// Records inserted vertex v (flat: never a needle).
  void add_vertex(Index v, bool boundary) {
    boundary_.resize(static_cast<std::size_t>(v) + 1, 0);
    boundary_[v] = boundary ? 1 : 0;
  }

 private:
  static constexpr char kSomeUnfixable = 1, kSomeFixable = 2, kCached = 4;
  // records the barrier sides of the fan whose corners are corners_ (a needle)
  void add_needle_sides(const Barriers& bar) {
    for (const Index x : corners_) {
      const Index v = bar.tri.tail(x);
      if (bar(x)) needle_sides_.push_back({v, bar.tri.head(x)});
      if (bar(T::prev(x))) needle_sides_.push_back({v, bar.tri.tail(T::prev(x))});
    }
  }
  bool unfixable(double theta, bool boundary) const {
    return boundary ? theta < bound_ : theta < 2.0 * bound_;
  }
  double bound_;
  const std::vector<char>* flags_;
  std::vector<char> state_;     // per input vertex: kCached, and which kinds of fans it has
  std::vector<char> boundary_;  // per vertex
  std::vector<std::pair<Index, Index>> needle_sides_;  // (apex, other end), sorted
  std::vector<Index> corners_;                         // scratch: one fan's corners
};

}  // namespace

double min_corner_angle(const IntrinsicTriangulation& tri, Index f) {
  // the smallest angle is opposite the shortest side
  const Index h = 3 * f;
  const double l0 = tri.halfedge_length(h), l1 = tri.halfedge_length(h + 1),
               l2 = tri.halfedge_length(h + 2);
  if (l0 <= l1 && l0 <= l2) return opposite_angle(l0, l1, l2);
  if (l1 <= l2) return opposite_angle(l1, l2, l0);
  return opposite_angle(l2, l0, l1);
}

namespace {

// Priority buckets of the bad-face queue, highest first: faces with a fixable corner below the
// bound, by that corner's angle θ, smallest first (kAngleBuckets even steps of sin(θ/2) over
// [0, sin 15°], ≈ 0.25° each); then faces bad only by size or by facing an encroached boundary
// side, by area, largest first (kAreaSub buckets per factor of 2).
constexpr int kAreaSub = 4;
constexpr int kAreaBuckets = 2200 * kAreaSub;  // binary exponents of doubles, subnormals included
constexpr int kAngleBuckets = 120;

int area_bucket(double area) {
  int e = 0;
  const double mant = std::frexp(area, &e);  // in [0.5, 1)
  const int sub = std::clamp(static_cast<int>((mant - 0.5) * 2.0 * kAreaSub), 0, kAreaSub - 1);
  return std::clamp((e + 1100) * kAreaSub + sub, 0, kAreaBuckets - 1);
}

int angle_bucket(double sin_half_angle) {
  const double sin15 = 0.25881904510252074;
  const int k =
      std::clamp(static_cast<int>(sin_half_angle / sin15 * kAngleBuckets), 0, kAngleBuckets - 1);
  return kAreaBuckets + kAngleBuckets - 1 - k;
}

// Bad faces, highest bucket first, LIFO inside a bucket: O(1) push and pop (a heap's sifting
// dominated big refinements). A face whose bucket changed while queued is pushed again into
// the new one; where_[f] names the bucket of its live entry, and other entries are skipped when
// popped, so the order follows the faces' current shapes.
class BadFaceQueue {
 public:
  explicit BadFaceQueue(Index n_faces)
      : buckets_(kAreaBuckets + kAngleBuckets), where_(n_faces, kNowhere) {}
  void push(Index f, int bucket) {
    if (static_cast<std::size_t>(f) >= where_.size()) where_.resize(2 * f + 1024, kNowhere);
    if (where_[f] == bucket) return;
    where_[f] = static_cast<std::int16_t>(bucket);
    buckets_[bucket].push_back(f);
    top_ = std::max(top_, bucket);
  }
  Index pop() {
    for (;;) {
      while (top_ >= 0 && buckets_[top_].empty()) --top_;
      if (top_ < 0) return kInvalidIndex;
      const Index f = buckets_[top_].back();
      buckets_[top_].pop_back();
      if (where_[f] != top_) continue;  // stale: queued again elsewhere, or already taken
      where_[f] = kNowhere;
      return f;
    }
  }

 private:
  static constexpr std::int16_t kNowhere = -1;
  static_assert(kAreaBuckets + kAngleBuckets <= 32767, "bucket ids are 16-bit");
  std::vector<std::vector<Index>> buckets_;
  std::vector<std::int16_t> where_;  // per face: the bucket of its live entry, or kNowhere
  int top_ = -1;
};

// The insertion cap: options.max_insertions, or 10 per input vertex, plus 2000 for the
// rings a tiny (mollified, degenerate) feature of a small mesh needs
// (cgal_fused_vertices.off: 40 vertices, 855 insertions), and room for 4× the triangles a
// size bound asks for.
double insertion_cap_for(const IntrinsicTriangulation& tri, const RefineOptions& options) {
  if (options.max_insertions >= 0) return double(options.max_insertions);
  double c = 10.0 * double(std::max<Index>(tri.n_vertices(), 10)) + 2000.0;
  if (options.max_area > 0.0) c += 4.0 * total_area(tri) * tri.multiplicity() / options.max_area;
  return std::min(c, 1.5e9);
}

// options.max_memory_bytes, or the default budget when 0.
double memory_budget(const RefineOptions& options) {
  return options.max_memory_bytes > 0.0 ? options.max_memory_bytes : default_memory_budget();
}

// A face with a fixable small corner whose shortest side is below this fraction of its local
// scale (Refiner::init_scale(): the shortest edge at its vertices before refinement) is left
// alone. Refinement that terminates never gets near it (Ruppert's and Chew's bounds keep edges
// above a constant fraction of the local feature size); insertions that cascade towards a point
// (a minimum angle above what Chew's algorithm guarantees, about 26.5°, near a boundary corner)
// halve the lengths every few insertions and would underflow after some 400 rounds: 2^-20
// stops them after 20 (docs/decisions.md D-121).
constexpr double kScaleFloor = 0x1.0p-20;

// Constrained edges shorter than this fraction of the mean edge length are not split (see
// split_boundary()).
constexpr double kConstrainedFloor = 1.0 / 1024.0;

// Curve and boundary edges shorter than this fraction of the mean edge length are not split by
// the conforming step (conforming.h): about 30 halvings of an average edge, where the weight test
// still has about 7 digits (rounding of the neighbouring sides, ~1e-16 of the mean, against the
// edge). Far below kConstrainedFloor: the conforming splits converge at small angles between
// curves (concentric shells) where the angle-driven splits above do not (docs/decisions.md D-140).
constexpr double kConformFloor = 0x1p-30;

// How far from the midpoint of a bad face's shortest side an off-center goes, as a fraction of
// the distance at which the isosceles triangle on that side has exactly the bound at its apex
// (Üngör 2004); 0.95 as in Shewchuk's Triangle, so that the new triangle is just above it.
constexpr double kOffCenterFactor = 0.95;

// Chew's second algorithm over a host (see above), in named steps: the constructor checks the
// options and sets the insertion cap, run() makes the triangulation Delaunay, queues the bad
// faces and inserts until none is left (or the cap), then measures the result.
template <class Host>
class Refiner {
 public:
  Refiner(Host& host, const RefineOptions& options, EdgeConstraints* constraints)
      : host_(host),
        tri_(host.tri()),
        options_(options),
        cons_(constraints),
        flags_(constraints ? constraints->flags : nullptr),
        bar_{host.tri(), flags_} {
    if (!(options.min_angle_degrees > 0.0 && options.min_angle_degrees <= 30.0)) {
      throw InvalidInput("delaunay_refine: minimum angle must be in (0, 30] degrees, got " +
                         std::to_string(options.min_angle_degrees));
    }
    if (!(options.max_area >= 0.0)) {
      throw InvalidInput("delaunay_refine: max_area must be ≥ 0");
    }
    bound_ = options.min_angle_degrees * kDeg;
    cos_bound_ = std::cos(bound_);
    max_area_ = options.max_area > 0.0 ? options.max_area : 0.0;
    rep_.vertices_before = tri_.n_vertices();
    cap_ = insertion_cap();
  }

  RefineReport run() {
    const double expected =
        options_.on_progress ? estimate_refinement(tri_, options_).insertions : 1.0;
    ProgressMeter meter(options_.on_progress, "refine", std::max(expected, 1.0), true);
    grow_flags();
    rep_.flips += host_.flip_to_delaunay().flips;
    mean_length_ = mean_edge_length(tri_);
    constrained_floor_ = kConstrainedFloor * mean_length_;
    double before = kPi;
    for (Index f = 0; f < tri_.n_faces(); ++f) before = std::min(before, min_corner_angle(tri_, f));
    rep_.min_angle_before = before / kDeg;
    for (Index f = 0; f < tri_.n_faces(); ++f) check_face(f, "", true);
    init_scale();
    cones_.emplace(tri_, bound_, flags_);
    BadFaceQueue queue(tri_.n_faces());
    for (Index f = 0; f < tri_.n_faces(); ++f) {
      const Verdict v = classify(f);
      if (v.kind == 1) queue.push(f, v.bucket);
    }
    for (Index f = queue.pop(); f != kInvalidIndex; f = queue.pop()) {
      const Verdict verdict = classify(f);
      if (verdict.kind != 1) continue;
      if (rep_.insertions >= cap_) {
        rep_.hit_insertion_cap = true;
        break;
      }
      const Index v = insert_for(f, verdict);
      if (v == kInvalidIndex) continue;
      ++rep_.insertions;
      meter.update(double(rep_.insertions));
      restore_delaunay_around(v, queue);
      // a split of a boundary or curve edge instead of f's point may leave f as it was, away
      // from the flips: keep it queued
      const Verdict again = classify(f);
      if (again.kind == 1) queue.push(f, again.bucket);
    }
    if (flags_ && options_.conform) conform();
    measure_result();
    meter.finish();
    return rep_;
  }

 private:
  static constexpr double kDeg = kPi / 180.0;

  // kind 0 = good, 1 = bad, 2 = needle (every small corner unfixable), 3 = bad but below the
  // scale floor (left alone); a bad face's queue bucket.
  struct Verdict {
    int kind = 0;
    int bucket = 0;
  };

  // the cap on insertions: options.max_insertions, or 10 per input vertex, plus 2000 for the
  // rings a tiny (mollified, degenerate) feature of a small mesh needs
  // (cgal_fused_vertices.off: 40 vertices, 855 insertions), and room for 4× the triangles a
  // size bound asks for
  // (insertion_cap_for()), and no more than the memory budget pays for
  Index insertion_cap() const {
    const double cap = insertion_cap_for(tri_, options_);
    const double affordable =
        memory_budget(options_) / kRefineBytesPerVertex - double(tri_.n_vertices());
    return static_cast<Index>(std::max(0.0, std::min(cap, affordable)));
  }

  // Whether face f needs an insertion and how urgently. The angle θ at a corner is below the
  // bound iff its cosine b² + c² − a² over 2bc is above cos(bound), and
  // sin²(θ/2) = (a² − (b − c)²) / 4bc: no trigonometry.
  Verdict classify(Index f) {
    Verdict v;
    bool small = false;
    double worst = 2.0;  // sin(θ/2) of the smallest fixable small corner
    const double l[3] = {tri_.halfedge_length(3 * f), tri_.halfedge_length(3 * f + 1),
                         tri_.halfedge_length(3 * f + 2)};
    for (int k = 0; k < 3; ++k) {
      // corner k sits between sides k and k+2, opposite side k+1
      const double b = l[k], c = l[(k + 2) % 3], a = l[(k + 1) % 3];
      if (b * b + c * c - a * a > cos_bound_ * 2.0 * b * c) {
        small = true;
        if (!cones_->unfixable(tri_, 3 * f + k)) {
          const double s2 = (a * a - (b - c) * (b - c)) / (4.0 * b * c);
          worst = std::min(worst, std::sqrt(std::max(s2, 0.0)));
        }
      }
    }
    v.kind = 1;
    if (worst <= 1.0 && !in_needle_shadow(l, f)) {
      if (std::min({l[0], l[1], l[2]}) < kScaleFloor * face_scale(f)) {
        v.kind = 3;
        return v;
      }
      v.bucket = angle_bucket(worst);
      return v;
    }
    if (max_area_ > 0.0) {
      const double area = face_area(tri_, f);
      if (area > max_area_) {
        v.bucket = area_bucket(area);
        return v;
      }
    }
    if (options_.split_encroached_boundary) {
      for (int k = 0; k < 3; ++k) {
        // side k faces the corner k+2: obtuse there ⇔ b² + c² < a²; its circumcenter then lies
        // across side k, so inserting it splits that boundary edge
        // (only for an interior apex: an apex on the boundary can cascade, as in Ruppert's
        // small-input-angle case)
        if (!bar_(3 * f + k)) continue;
        if (cones_->is_boundary(tri_.tail(3 * f + (k + 2) % 3))) continue;
        const double a = l[k], b = l[(k + 1) % 3], c = l[(k + 2) % 3];
        if (b * b + c * c - a * a < -1e-12 * (b * b + c * c)) {
          v.bucket = area_bucket(face_area(tri_, f));
          return v;
        }
      }
    }
    v.kind = small ? 2 : 0;
    return v;
  }

  // Whether face f (side lengths l) lies in the shadow of a needle (a boundary or constrained
  // fan whose angle is below the bound): its shortest side joins two vertices of that needle
  // (its apex, or vertices inserted on its two sides). Its small corners are then forced by the
  // needle: inside a wedge of angle α, a triangle with corners on both sides has a corner of at
  // most about α unless its sides are as short as the wedge is wide there, so fixing it makes a
  // smaller one nearer the apex, round after round (Ruppert's small-input-angle case), until
  // the lengths underflow. Such faces are left alone, like the needle's own corner.
  bool in_needle_shadow(const double l[3], Index f) const {
    if (chain_.empty()) return false;  // no barrier split yet: no vertex on a needle's side
    int k = 0;
    for (int j = 1; j < 3; ++j) {
      if (l[j] < l[k]) k = j;
    }
    const Index u = tri_.tail(3 * f + k), w = tri_.tail(3 * f + (k + 1) % 3);
    const std::array<Index, 2> cu = chain(u), cw = chain(w);
    // u (or w) is the apex itself, or lies on a side of the needle there
    auto on_needle = [this](Index apex, Index x, const std::array<Index, 2>& c) {
      if (x == apex) return true;
      if (c[0] != apex && c[1] != apex) return false;
      return cones_->is_needle_side(apex, c[0] == apex ? c[1] : c[0]);
    };
    for (const Index apex : cu) {
      if (apex == kInvalidIndex || !on_needle(apex, u, cu) || !on_needle(apex, w, cw)) continue;
      if (cu != cw || u == apex || w == apex) return true;  // across the needle, or at its apex
    }
    return false;
  }

  // The local scale: for a vertex there before refinement, its shortest edge in the initial
  // Delaunay triangulation; an inserted vertex takes the smallest scale of the bad face it was
  // inserted for (so a cascade keeps the scale where it started).
  void init_scale() {
    scale_.assign(static_cast<std::size_t>(tri_.n_vertices()),
                  std::numeric_limits<double>::infinity());
    for (Index e = 0; e < tri_.n_edges(); ++e) {
      const Index h = tri_.edge_halfedge(e);
      for (const Index x : {tri_.tail(h), tri_.head(h)}) {
        scale_[x] = std::min(scale_[x], tri_.length(e));
      }
    }
  }
  // Every vertex made by refinement gets a scale (the faces around it are classified by it).
  void set_scale(Index v, double scale) {
    if (scale_.size() <= static_cast<std::size_t>(v)) {
      scale_.resize(static_cast<std::size_t>(v) + 1, std::numeric_limits<double>::infinity());
    }
    scale_[v] = scale;
  }
  double face_scale(Index f) const {
    return std::min(
        {scale_[tri_.tail(3 * f)], scale_[tri_.tail(3 * f + 1)], scale_[tri_.tail(3 * f + 2)]});
  }

  // The original vertices at the ends of the barrier side vertex v lies on: {v, v} for a vertex
  // there before refinement, the side's ends for a vertex inserted on a barrier (boundary or
  // constrained) edge, none (kInvalidIndex) for other inserted vertices.
  std::array<Index, 2> chain(Index v) const {
    if (v < rep_.vertices_before) return {v, v};
    const std::size_t i = static_cast<std::size_t>(v - rep_.vertices_before);
    return i < chain_.size() ? chain_[i] : std::array<Index, 2>{kInvalidIndex, kInvalidIndex};
  }

  // Records the chain (see chain()) of vertex m inserted on barrier edge (x, y).
  void record_chain(Index m, Index x, Index y) {
    std::array<Index, 2> c = {x, y};
    if (x >= rep_.vertices_before && chain(x)[0] != kInvalidIndex)
      c = chain(x);
    else if (y >= rep_.vertices_before && chain(y)[0] != kInvalidIndex)
      c = chain(y);
    const std::size_t i = static_cast<std::size_t>(m - rep_.vertices_before);
    if (chain_.size() <= i) chain_.resize(i + 1, {kInvalidIndex, kInvalidIndex});
    chain_[i] = c;
  }

  // The point to insert for bad face f in its layout p: the circumcenter, or the off-center
  // for an angle-bad face when asked.
  Eigen::Vector2d target_point(const Eigen::Vector2d p[3], const Verdict& verdict) const {
    const Eigen::Vector2d b = p[1], c = p[2];
    const double dd = 2.0 * (b.x() * c.y() - b.y() * c.x());
    Eigen::Vector2d target((c.y() * b.squaredNorm() - b.y() * c.squaredNorm()) / dd,
                           (b.x() * c.squaredNorm() - c.x() * b.squaredNorm()) / dd);
    if (options_.off_centers && verdict.bucket >= kAreaBuckets) {
      int s = 0;  // shortest side
      for (int k = 1; k < 3; ++k) {
        if ((p[(k + 1) % 3] - p[k]).squaredNorm() < (p[(s + 1) % 3] - p[s]).squaredNorm()) s = k;
      }
      const Eigen::Vector2d m = 0.5 * (p[s] + p[(s + 1) % 3]);
      const double to_cc = (target - m).norm();
      const double h =
          kOffCenterFactor * 0.5 * (p[(s + 1) % 3] - p[s]).norm() / std::tan(0.5 * bound_);
      if (h < to_cc) target = m + (h / to_cc) * (target - m);
    }
    return target;
  }

  // Traces from f's centroid to its target point and inserts a vertex where the trace ends
  // (in a face, on a side, or at a boundary edge it splits). Returns the new vertex, or
  // kInvalidIndex when the trace or the insertion failed (counted in failed_traces).
  Index insert_for(Index f, const Verdict& verdict) {
    const double scale = face_scale(f);
    Eigen::Vector2d p[3];
    face_layout(tri_, f, p);
    const Eigen::Vector2d target = target_point(p, verdict);
    const Eigen::Vector2d centroid = (p[0] + p[1] + p[2]) / 3.0;
    const Eigen::Vector2d w = target - centroid;
    const double dist = w.norm();
    if (!std::isfinite(dist) || !(dist > 0.0)) {
      ++rep_.failed_traces;
      return kInvalidIndex;
    }
    SurfacePoint start;
    start.face = f;
    start.bary = Eigen::Vector3d::Constant(1.0 / 3.0);
    try {
      const TraceResult r = trace_straight(tri_, start, w / dist, dist, -1, false, false,
                                           4 * tri_.n_faces() + 1000, flags_);
      bool on_boundary = false;
      const Index refused = rep_.constrained_floor;
      const Index v = insert_at(r, &on_boundary);
      if (v == kInvalidIndex) {
        if (rep_.constrained_floor == refused) ++rep_.failed_traces;  // else counted there
        return kInvalidIndex;
      }
      cones_->add_vertex(v, on_boundary);
      set_scale(v, scale);
      return v;
    } catch (const TraceError&) {  // the trace, or locating the new vertex (signposts)
      ++rep_.failed_traces;
      return kInvalidIndex;
    }
  }

  // A barrier side whose diametral circle holds point x (in face g's layout p): of g, or of a
  // face glued to a side of g (x carried into its layout across that side); kInvalidIndex if
  // none.
  Index encroached_side(Index g, const Eigen::Vector2d p[3], const Eigen::Vector2d& x) const {
    for (int s = 0; s < 3; ++s) {
      if (bar_(3 * g + s) && (p[s] - x).dot(p[(s + 1) % 3] - x) < 0.0) return 3 * g + s;
    }
    for (int s = 0; s < 3; ++s) {
      const Index t = bar_.across(3 * g + s);
      if (t == kInvalidIndex || T::face(t) == g) continue;
      // x relative to side s (from p[s] to p[s+1]): along and across it
      const Eigen::Vector2d e = p[(s + 1) % 3] - p[s];
      const double len2 = e.squaredNorm();
      if (!(len2 > 0.0)) continue;
      const double along = (x - p[s]).dot(e) / len2, across = cross2(e, x - p[s]) / len2;
      Eigen::Vector2d q[3];
      face_layout(tri_, T::face(t), q);
      const int st = T::side(t);  // t runs from p[s+1] to p[s]: the other face's side st
      const Eigen::Vector2d a = q[(st + 1) % 3], b = q[st];  // images of p[s], p[s+1]
      const Eigen::Vector2d f = b - a;
      const Eigen::Vector2d y = a + along * f + across * Eigen::Vector2d(-f.y(), f.x());
      for (int k = 0; k < 3; ++k) {
        const Index h = 3 * T::face(t) + k;
        if (h != t && bar_(h) && (q[k] - y).dot(q[(k + 1) % 3] - y) < 0.0) return h;
      }
    }
    return kInvalidIndex;
  }

  // Inserts at the end of trace r: splits the boundary edge it hit, a boundary side whose
  // diametral circle the point encroaches (Chew), the side it lies on (within rounding), or
  // inserts in the face. kInvalidIndex when the edge to split cannot be split.
  Index insert_at(const TraceResult& r, bool* on_boundary) {
    if (r.hit_boundary) return split_boundary(tri_.edge(r.boundary_halfedge), on_boundary);
    const Index g = r.end.face;
    const Eigen::Vector3d& bary = r.end.bary;
    int k = 0;
    for (int j = 1; j < 3; ++j) {
      if (bary[j] < bary[k]) k = j;
    }
    // Chew: a circumcenter inside the diametral circle of a boundary side of the face it
    // lands in, or of a face glued to it, splits that side at its midpoint instead
    Eigen::Vector2d p[3];
    face_layout(tri_, g, p);
    const Eigen::Vector2d x = bary[0] * p[0] + bary[1] * p[1] + bary[2] * p[2];
    const Index encroached = encroached_side(g, p, x);
    if (encroached != kInvalidIndex) return split_boundary(tri_.edge(encroached), on_boundary);
    if (bary[k] < 1e-9) {
      // on (or within rounding of) a side: split that edge
      const int s = (k + 1) % 3;
      const Index h = 3 * g + s;
      const Index e = tri_.edge(h);
      double u = bary[(s + 1) % 3] / (bary[s] + bary[(s + 1) % 3]);
      if (tri_.edge_halfedge(e) != h) u = 1.0 - u;
      if (bar_(h)) return split_boundary(e, on_boundary);
      ++rep_.edge_splits;
      if (!tri_.can_split_edge(e)) return kInvalidIndex;
      return split(e, std::clamp(u, 1e-3, 1.0 - 1e-3));
    }
    const Index v = host_.insert_vertex(g, bary);
    grow_flags();
    ++rep_.face_insertions;
    return v;
  }

  // Splits edge e at fraction t (host), keeping the constraints: the flags grow with the new
  // edges, and the half of a constrained edge beyond the new vertex is constrained too.
  Index split(Index e, double t) {
    const bool constrained = bar_.constrained(e);
    const Index h = tri_.edge_halfedge(e);
    const bool barrier = bar_(h);
    const Index x = tri_.tail(h), y = tri_.head(h);
    const Index new_edge = tri_.n_edges();  // split_edge's first new edge: new vertex → old head
    const Index v = host_.split_edge(e, t);
    grow_flags();
    if (barrier) record_chain(v, x, y);
    if (constrained) {
      (*flags_)[new_edge] = 1;
      if (cons_->on_split) cons_->on_split(e, new_edge, v, t);
    }
    return v;
  }

  void grow_flags() {
    if (flags_) flags_->resize(static_cast<std::size_t>(tri_.n_edges()), 0);
  }

  // Splits boundary or constrained edge e at its midpoint (kInvalidIndex if it cannot be
  // split, or if it is a constrained edge shorter than the floor: two curves meeting at a small
  // angle make midpoint splits cascade towards their common vertex, Ruppert's small-input-angle
  // case, and the floor stops that after about ten halvings).
  Index split_boundary(Index e, bool* on_boundary) {
    if (!tri_.can_split_edge(e)) return kInvalidIndex;
    if (bar_.constrained(e) && tri_.length(e) < constrained_floor_) {
      ++rep_.constrained_floor;
      return kInvalidIndex;
    }
    ++(tri_.is_boundary_edge(e) ? rep_.boundary_splits : rep_.constrained_splits);
    *on_boundary = true;
    return split(e, 0.5);
  }

  // The conforming step (conforming.h): constrained and boundary edges with a negative cotan
  // weight are split, corners being the vertices that existed before refinement; capped by
  // 10 splits per edge and by the memory budget.
  void conform() {
    const double affordable =
        memory_budget(options_) / kRefineBytesPerVertex - double(tri_.n_vertices());
    const double cap = std::max(0.0, std::min(affordable, 10.0 * double(tri_.n_edges())));
    const detail::ConformHost ch{
        tri_,
        flags_,
        [this](Index e, double t) { return conforming_split(e, t); },
        [this](const std::vector<Index>& queue, std::vector<Index>* touched) {
          return host_.flip_to_delaunay_from(queue, touched).flips;
        },
        rep_.vertices_before,
        kConformFloor * mean_length_,
        static_cast<Index>(cap)};
    const detail::ConformOutcome c = detail::conform_barriers(ch);
    rep_.conforming_splits = c.splits;
    rep_.conforming_shell_splits = c.shell_splits;
    rep_.conforming_hit_cap = c.hit_cap;
    rep_.flips += c.flips;
    rep_.negative_barrier_weights = c.negative_left;
    rep_.negative_barrier_floor = c.floor_left;
    rep_.min_relative_barrier_weight = c.min_relative_weight;
  }

  // A split of the conforming step. Signposts may fail to locate the new vertex on the input
  // (TraceError) after the split is made: the constraints are then kept all the same (counted
  // as a failed trace). kInvalidIndex if no vertex was made.
  Index conforming_split(Index e, double t) {
    const Index n_before = tri_.n_vertices(), new_edge = tri_.n_edges();
    const bool constrained = bar_.constrained(e);
    const Index h = tri_.edge_halfedge(e);
    const double scale = std::min(scale_[tri_.tail(h)], scale_[tri_.head(h)]);
    Index v = kInvalidIndex;
    try {
      v = split(e, t);
    } catch (const TraceError&) {
      ++rep_.failed_traces;
      if (tri_.n_vertices() == n_before) return kInvalidIndex;
      v = n_before;
      grow_flags();
      if (constrained) {
        (*flags_)[new_edge] = 1;
        if (cons_->on_split) cons_->on_split(e, new_edge, v, t);
      }
    }
    cones_->add_vertex(v, true);
    set_scale(v, scale);
    return v;
  }

  // Restores Delaunay around the new vertex v (the sides opposite v, then whatever flips
  // reach) and queues the faces it touched that are bad.
  void restore_delaunay_around(Index v, BadFaceQueue& queue) {
    touched_.clear();
    flip_queue_.clear();
    const Index h0 = tri_.vertex_halfedge(v);
    Index h = h0;
    for (int guard = 0; guard < 64; ++guard) {
      touched_.push_back(T::face(h));
      flip_queue_.push_back(tri_.edge(T::next(h)));
      const Index n = tri_.twin(T::prev(h));
      if (n == kInvalidIndex || n == h0) break;
      h = n;
    }
    rep_.flips += host_.flip_to_delaunay_from(flip_queue_, &touched_).flips;
    std::sort(touched_.begin(), touched_.end());
    touched_.erase(std::unique(touched_.begin(), touched_.end()), touched_.end());
    for (const Index x : touched_) check_face(x, "after inserting vertex " + std::to_string(v));
    for (const Index x : touched_) {
      const Verdict vx = classify(x);
      if (vx.kind == 1) queue.push(x, vx.bucket);
    }
  }

  // Throws Error naming face f and `when` unless f's side lengths are finite and positive and
  // its area is: the Laplacian and mass matrix of the result must be finite. `input`: f is a
  // face of the input's intrinsic Delaunay triangulation (before any insertion), else one that
  // refinement made.
  void check_face(Index f, const std::string& when, bool input = false) const {
    const double a = tri_.halfedge_length(3 * f), b = tri_.halfedge_length(3 * f + 1),
                 c = tri_.halfedge_length(3 * f + 2);
    const double area = face_area(tri_, f);
    if (std::isfinite(a) && std::isfinite(b) && std::isfinite(c) && a > 0.0 && b > 0.0 && c > 0.0 &&
        std::isfinite(area) && area > 0.0) {
      return;
    }
    std::ostringstream m;
    m << std::setprecision(6) << "delaunay_refine: ";
    if (input) {
      m << "face " << f << " of the input's intrinsic Delaunay triangulation has side lengths " << a
        << ", " << b << ", " << c << " and area " << area
        << ": its cotan weights and mass would not be finite. The input is degenerate there "
        << "(coincident vertices, zero-area faces); repair it or raise the mollification";
    } else {
      m << when << " (insertion " << rep_.insertions << "), face " << f << " has side lengths " << a
        << ", " << b << ", " << c << " and area " << area
        << ": refinement made a degenerate triangle (the input's faces were valid). This is a "
        << "defect of the refinement, not of the input; please report it with the input. "
        << "A smaller minimum angle avoids it";
    }
    throw Error(m.str());
  }

  // The report's final counts and angles; every face checked (check_face()).
  void measure_result() {
    if (scale_.size() != static_cast<std::size_t>(tri_.n_vertices())) {
      throw Error("delaunay_refine: internal error: " + std::to_string(tri_.n_vertices()) +
                  " vertices but " + std::to_string(scale_.size()) + " local scales");
    }
    for (Index f = 0; f < tri_.n_faces(); ++f) check_face(f, "at the end of refinement");
    rep_.vertices_after = tri_.n_vertices();
    rep_.insertions = rep_.vertices_after - rep_.vertices_before;
    double after = kPi, after_ok = kPi;
    for (Index f = 0; f < tri_.n_faces(); ++f) {
      const double a = min_corner_angle(tri_, f);
      after = std::min(after, a);
      const int c = classify(f).kind;
      if (c == 2) {
        ++rep_.needle_faces;
      } else {
        after_ok = std::min(after_ok, a);
        if (c == 1 || c == 3) ++rep_.bad_faces_left;
        if (c == 3) ++rep_.scale_floor_faces;
      }
    }
    rep_.min_angle_after = after / kDeg;
    rep_.min_angle_after_excluding_needles = after_ok / kDeg;
  }

  Host& host_;
  const IntrinsicTriangulation& tri_;
  const RefineOptions& options_;
  EdgeConstraints* cons_;     // may be null
  std::vector<char>* flags_;  // cons_->flags, or null
  Barriers bar_;
  double bound_ = 0.0, cos_bound_ = 1.0, max_area_ = 0.0;
  Index cap_ = 0;
  double constrained_floor_ = 0.0;  // shortest constrained edge split (absolute)
  double mean_length_ = 0.0;        // mean edge length after the first Delaunay flips
  RefineReport rep_;
  std::optional<Cones> cones_;  // made after the first Delaunay flips
  // per inserted vertex (v − vertices_before), for those on a barrier side: chain()
  std::vector<std::array<Index, 2>> chain_;
  std::vector<double> scale_;  // per vertex: the local scale (init_scale())
  std::vector<Index> touched_, flip_queue_;
};

template <class Host>
RefineReport refine(Host& host, const RefineOptions& options, EdgeConstraints* constraints) {
  return Refiner<Host>(host, options, constraints).run();
}

}  // namespace

double default_memory_budget() {
  double budget = 4.0 * 1024 * 1024 * 1024;
  const long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGE_SIZE);
  if (pages > 0 && page > 0) budget = 0.5 * double(pages) * double(page);
  rlimit lim{};
  if (getrlimit(RLIMIT_AS, &lim) == 0 && lim.rlim_cur != RLIM_INFINITY) {
    budget = std::min(budget, 0.8 * double(lim.rlim_cur));
  }
  return budget;
}

RefineEstimate estimate_refinement(const IntrinsicTriangulation& tri,
                                   const RefineOptions& options) {
  options.validate();
  RefineEstimate e;
  const double n_v = double(tri.n_vertices());
  if (options.max_area > 0.0) {
    e.size_term = kSizeTermFactor * total_area(tri) * tri.multiplicity() / options.max_area;
  }
  e.angle_term = n_v;
  e.insertions = std::min(std::max(e.size_term, e.angle_term), insertion_cap_for(tri, options));
  e.vertices = n_v + e.insertions;
  e.bytes = e.vertices * kRefineBytesPerVertex;
  e.budget = memory_budget(options);
  return e;
}

void check_refinement_budget(const IntrinsicTriangulation& tri, const RefineOptions& options) {
  const RefineEstimate e = estimate_refinement(tri, options);
  if (!(e.bytes > e.budget)) return;
  auto gb = [](double bytes) {
    std::ostringstream m;
    m << std::setprecision(3) << bytes / 1e9 << " GB";
    return m.str();
  };
  std::ostringstream m;
  m << std::setprecision(3) << "refinement would insert about " << e.insertions << " vertices ("
    << e.vertices << " in all; the size bound asks for about " << e.size_term
    << ", the angle bound about " << e.angle_term << ", at most the insertion cap "
    << insertion_cap_for(tri, options) << "), about " << gb(e.bytes) << " at "
    << kRefineBytesPerVertex / 1024 << " KiB per vertex, above the memory budget of "
    << gb(e.budget) << ". Ask for less (a larger resolution or max area, a smaller minimum "
    << "angle) or raise the budget: RefineOptions::max_memory_bytes / SurfaceRefineOptions::"
    << "max_memory_bytes, `--memory-budget GB` in the CLI (default: half the physical memory, "
    << "or 80% of ulimit -v)";
  throw InvalidInput(m.str());
}

RefineReport delaunay_refine(SignpostTriangulation& st, const RefineOptions& options,
                             EdgeConstraints* constraints) {
  check_refinement_budget(st.intrinsic(), options);
  TrackedHost<SignpostTriangulation> host(st, constraints ? constraints->flags : nullptr);
  return refine(host, options, constraints);
}

RefineReport delaunay_refine(NormalCoordinateTriangulation& nc, const RefineOptions& options,
                             EdgeConstraints* constraints) {
  check_refinement_budget(nc.intrinsic(), options);
  TrackedHost<NormalCoordinateTriangulation> host(nc, constraints ? constraints->flags : nullptr);
  return refine(host, options, constraints);
}

RefineReport delaunay_refine(IntrinsicTriangulation& tri, const RefineOptions& options,
                             EdgeConstraints* constraints) {
  check_refinement_budget(tri, options);
  PlainHost host(tri, constraints ? constraints->flags : nullptr);
  return refine(host, options, constraints);
}

namespace {

// smallest corner angle of the planar triangle (a, b, c)
double planar_min_angle(const Eigen::Vector2d& a, const Eigen::Vector2d& b,
                        const Eigen::Vector2d& c) {
  const double la = (b - c).norm(), lb = (c - a).norm(), lc = (a - b).norm();
  if (la <= lb && la <= lc) return opposite_angle(la, lb, lc);
  if (lb <= lc) return opposite_angle(lb, lc, la);
  return opposite_angle(lc, la, lb);
}

void angle_stats(const IntrinsicTriangulation& tri, double& min_deg, double& mean_deg) {
  double mn = kPi, sum = 0.0;
  for (Index f = 0; f < tri.n_faces(); ++f) {
    const double a = min_corner_angle(tri, f);
    mn = std::min(mn, a);
    sum += a;
  }
  min_deg = mn * 180.0 / kPi;
  mean_deg = tri.n_faces() > 0 ? sum / tri.n_faces() * 180.0 / kPi : 0.0;
}

}  // namespace

namespace {

// ODT relaxation is written once over the triangulation that keeps the correspondence
// (SignpostTriangulation, NormalCoordinateTriangulation: the same operations by the same names:
// n_input_vertices(), is_boundary_vertex(), move_inserted_vertex(), split_edge(),
// flip_to_delaunay(); both lay out a star with inserted_vertex_star(), core/geometry.h).

// Splits the edges longer than options.max_edge_length at their midpoints, round after round
// (a split edge's halves may still be too long), each round followed by Delaunay flips.
template <class Tracked>
void split_long_edges(Tracked& st, const RelaxOptions& options, Index cap, RelaxReport& rep) {
  const IntrinsicTriangulation& tri = st.intrinsic();
  std::vector<Index> longer;
  for (;;) {
    longer.clear();
    for (Index e = 0; e < tri.n_edges(); ++e) {
      if (tri.length(e) > options.max_edge_length) longer.push_back(e);
    }
    if (longer.empty()) return;
    bool split_any = false;
    for (const Index e : longer) {  // edge ids survive splits (new edges are appended)
      if (rep.splits >= cap) {
        rep.hit_split_cap = true;
        break;
      }
      if (!(tri.length(e) > options.max_edge_length)) continue;
      if (!tri.can_split_edge(e)) continue;  // an edge with both sides in one face
      try {
        st.split_edge(e, 0.5);
      } catch (const TraceError&) {
        continue;  // the midpoint could not be located on the input: not counted as a split
      }
      ++rep.splits;
      split_any = true;
    }
    rep.flips += st.flip_to_delaunay().flips;
    if (!split_any || rep.hit_split_cap) return;
  }
}

// Throws InvalidInput for options relax_inserted_vertices() cannot use.
void check_relax_options(const RelaxOptions& options) {
  options.validate();
  if (options.iterations < 0) {
    throw InvalidInput("relax_inserted_vertices: iterations must be ≥ 0");
  }
  if (!(options.max_edge_length >= 0.0)) {
    throw InvalidInput("relax_inserted_vertices: max_edge_length must be ≥ 0");
  }
}

// The ODT target of a vertex at the origin with the flattened ring `ring`: the area-weighted
// mean of the circumcenters of (origin, ring[i], ring[i+1]); old_min and old_sum: the smallest
// and the sum of the triangles' smallest angles. False if a triangle or the star is not
// positively oriented.
bool odt_target(const std::vector<Eigen::Vector2d>& ring, Eigen::Vector2d& target, double& old_min,
                double& old_sum) {
  const Eigen::Vector2d origin = Eigen::Vector2d::Zero();
  const std::size_t n = ring.size();
  Eigen::Vector2d acc = Eigen::Vector2d::Zero();
  double area = 0.0;
  old_min = kPi;
  old_sum = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector2d& b = ring[i];
    const Eigen::Vector2d& c = ring[(i + 1) % n];
    const double dd = 2.0 * cross2(b, c);
    if (!(dd > 0.0)) return false;
    const Eigen::Vector2d cc((c.y() * b.squaredNorm() - b.y() * c.squaredNorm()) / dd,
                             (b.x() * c.squaredNorm() - c.x() * b.squaredNorm()) / dd);
    acc += 0.25 * dd * cc;  // area = dd / 4
    area += 0.25 * dd;
    const double a = planar_min_angle(origin, b, c);
    old_min = std::min(old_min, a);
    old_sum += a;
  }
  if (!(area > 0.0)) return false;
  target = acc / area;
  return true;
}

// Whether the vertex at p keeps the smallest and the sum of its triangles' smallest angles at
// least old_min and old_sum.
bool keeps_min_angles(const Eigen::Vector2d& p, const std::vector<Eigen::Vector2d>& ring,
                      double old_min, double old_sum) {
  const std::size_t n = ring.size();
  double new_min = kPi, new_sum = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    const double a = planar_min_angle(p, ring[i], ring[(i + 1) % n]);
    new_min = std::min(new_min, a);
    new_sum += a;
  }
  return new_min >= old_min && new_sum >= old_sum;
}

// Moves inserted vertex v toward its ODT target (the whole way, half, a quarter: the first
// allowed); counts it as moved or rejected.
template <class Tracked>
void relax_vertex(Tracked& st, Index v, const RelaxOptions& options, std::vector<Index>& spokes,
                  std::vector<Eigen::Vector2d>& ring, RelaxReport& rep) {
  if (st.is_boundary_vertex(v)) {
    ++rep.skipped_boundary;
    return;
  }
  Eigen::Vector2d target;
  double old_min = kPi, old_sum = 0.0;
  if (!inserted_vertex_star(st.intrinsic(), v, st.n_input_vertices(), &spokes, &ring) ||
      !odt_target(ring, target, old_min, old_sum)) {
    ++rep.skipped_irregular;
    return;
  }
  if (!target.allFinite()) {
    ++rep.rejected;
    return;
  }
  for (const double fraction : {1.0, 0.5, 0.25}) {
    const Eigen::Vector2d p = fraction * target;
    if (options.keep_min_angle && !keeps_min_angles(p, ring, old_min, old_sum)) continue;
    if (st.move_inserted_vertex(v, p)) {
      ++rep.moved;
      rep.max_displacement = std::max(rep.max_displacement, p.norm());
      return;
    }
  }
  ++rep.rejected;
}

template <class Tracked>
RelaxReport relax(Tracked& st, const RelaxOptions& options) {
  check_relax_options(options);
  const IntrinsicTriangulation& tri = st.intrinsic();
  RelaxReport rep;
  const Index split_cap =
      options.max_splits >= 0 ? options.max_splits : 10 * std::max<Index>(tri.n_vertices(), 10);
  angle_stats(tri, rep.min_angle_before, rep.mean_min_angle_before);
  std::vector<Index> spokes;
  std::vector<Eigen::Vector2d> ring;
  for (int pass = 0; pass < options.iterations; ++pass) {
    ++rep.passes;
    for (Index v = st.n_input_vertices(); v < tri.n_vertices(); ++v) {
      relax_vertex(st, v, options, spokes, ring, rep);
    }
    rep.flips += st.flip_to_delaunay().flips;
    if (options.max_edge_length > 0.0) split_long_edges(st, options, split_cap, rep);
  }
  angle_stats(tri, rep.min_angle_after, rep.mean_min_angle_after);
  for (Index e = 0; e < tri.n_edges(); ++e) {
    rep.max_edge_after = std::max(rep.max_edge_after, tri.length(e));
  }
  return rep;
}

}  // namespace

RelaxReport relax_inserted_vertices(SignpostTriangulation& st, const RelaxOptions& options) {
  return relax(st, options);
}

RelaxReport relax_inserted_vertices(NormalCoordinateTriangulation& nc,
                                    const RelaxOptions& options) {
  return relax(nc, options);
}

}  // namespace ifem::intrinsic
