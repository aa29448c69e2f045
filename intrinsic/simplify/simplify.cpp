// Intrinsic simplification (simplify.h): a working copy of the gluing map with dead faces,
// per-fan representative halfedges, tracked points per face, and a lazy priority queue.
#include "intrinsic/simplify/simplify.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <numeric>
#include <queue>
#include <set>
#include <string>
#include <tuple>
#include <utility>

#include "intrinsic/core/geometry.h"
#include "intrinsic/core/union_find.h"

namespace ifem::intrinsic {

void SimplifyOptions::validate() const {
  const bool has_target = target_vertices != 0;
  const bool has_ratio = ratio != 0.0;
  if (has_target == has_ratio) {
    throw InvalidInput(
        "SimplifyOptions: set exactly one of target_vertices (> 0) and ratio (in (0, 1])");
  }
  if (has_target && target_vertices < 0) {
    throw InvalidInput("SimplifyOptions.target_vertices must be > 0, got " +
                       std::to_string(target_vertices));
  }
  if (has_ratio && !(ratio > 0.0 && ratio <= 1.0)) {
    throw InvalidInput("SimplifyOptions.ratio must be in (0, 1], got " + std::to_string(ratio));
  }
}

namespace {

using T = IntrinsicTriangulation;
constexpr double kPi = 3.14159265358979323846;
// Relative margin every face made by a flip or a removal keeps in its triangle inequality
// (validate() asks for 1e-12): a + b − c ≥ kMargin · (a + b + c).
constexpr double kMargin = 1e-9;

bool good_triangle(double a, double b, double c) {
  const double m = kMargin * (a + b + c);
  return std::isfinite(a + b + c) && a + b - c >= m && b + c - a >= m && c + a - b >= m;
}

// Barycentric coordinates of p in triangle (p0, p1, p2), clamped to ≥ 0 and normalised.
Eigen::Vector3d bary_of(const Eigen::Vector2d& p, const Eigen::Vector2d& p0,
                        const Eigen::Vector2d& p1, const Eigen::Vector2d& p2) {
  const double area = cross2(p1 - p0, p2 - p0);
  Eigen::Vector3d b(cross2(p1 - p, p2 - p), cross2(p2 - p, p0 - p), cross2(p0 - p, p1 - p));
  b /= area;
  return b;
}

Eigen::Vector3d clamp_bary(Eigen::Vector3d b) {
  b = b.cwiseMax(0.0);
  const double s = b.sum();
  if (!(s > 0.0) || !std::isfinite(s)) return Eigen::Vector3d::Constant(1.0 / 3.0);
  return b / s;
}

// The convex polygon inscribed in a circle with sides l (d ≥ 3, in order): its corners' half
// central angles beta (Σ = π; the largest side's is obtuse when the centre lies outside) and
// radius. False when there is none with the margin (the largest side not below the others' sum).
bool cyclic_polygon(const std::vector<double>& l, std::vector<double>& beta, double& radius) {
  const std::size_t d = l.size();
  const std::size_t imax = std::max_element(l.begin(), l.end()) - l.begin();
  const double total = std::accumulate(l.begin(), l.end(), 0.0), lmax = l[imax];
  if (!std::isfinite(total) || !(total - 2.0 * lmax > kMargin * total)) return false;
  auto sum_others = [&](double R) {
    double s = 0.0;
    for (std::size_t i = 0; i < d; ++i) {
      if (i != imax) s += std::asin(std::min(1.0, l[i] / (2.0 * R)));
    }
    return s;
  };
  const double r0 = 0.5 * lmax;
  const bool inside = sum_others(r0) + 0.5 * kPi >= kPi;  // the centre inside the polygon
  // inside: Σ asin(l_i / 2R) = π, decreasing in R; outside: Σ_others = asin(lmax / 2R)
  auto excess = [&](double R) {
    const double m = std::asin(std::min(1.0, lmax / (2.0 * R)));
    return inside ? sum_others(R) + m - kPi : sum_others(R) - m;
  };
  double lo = r0, hi = 2.0 * r0;
  for (int k = 0; k < 200 && (inside ? excess(hi) > 0.0 : excess(hi) < 0.0); ++k) hi *= 2.0;
  for (int k = 0; k < 200 && hi - lo > 1e-15 * hi; ++k) {
    const double mid = 0.5 * (lo + hi);
    if ((excess(mid) > 0.0) == inside) {
      lo = mid;
    } else {
      hi = mid;
    }
  }
  radius = 0.5 * (lo + hi);
  beta.resize(d);
  double others = 0.0;
  for (std::size_t i = 0; i < d; ++i) {
    if (i == imax) continue;
    beta[i] = std::asin(std::min(1.0, l[i] / (2.0 * radius)));
    others += beta[i];
  }
  beta[imax] = kPi - others;  // closes the circle exactly (obtuse when the centre is outside)
  return std::isfinite(radius) && radius > 0.0 && beta[imax] > 0.0;
}

// Removal order (D-340): a vertex's cost rounded down to a bucket of relative width
// 2^-kCostBits (its binary exponent and leading kCostBits mantissa bits: the bit pattern of a
// non-negative double orders as its value), then its id. Exact greedy order visits the mesh at
// random (the costs of a uniform surface differ in their last bits): a cache miss per step on
// large meshes. Ids are near in memory and, for meshes written in any local order, near on the
// surface, so a bucket is swept in a few passes over memory. 1 bit (buckets of 1.5×, 1.33×):
// the multigrid's PCG iterations as with the exact order; 0 bits moved more area on meshes with
// sharp features (fandisk, ogre).
constexpr int kCostBits = 1;
constexpr int kBuckets = 1 << (11 + kCostBits);  // every finite non-negative double's bucket

std::uint64_t queue_key(double cost, Index v) {
  const double c = cost > 0.0 ? cost : 0.0;
  std::uint64_t bits = 0;
  std::memcpy(&bits, &c, sizeof bits);
  return ((bits >> (52 - kCostBits)) << 32) | std::uint32_t(v);
}

// A min-queue of queue_key()s in the same order as a binary heap of them, without its random
// accesses: one vector per cost bucket, the current bucket sorted once when it is reached, and a
// small heap for the keys pushed into it (or below it) after that. Each vertex is queued once.
class BucketQueue {
 public:
  BucketQueue() : buckets_(kBuckets) {}
  bool empty() const { return size_ == 0; }
  void push(std::uint64_t key) {
    ++size_;
    const int b = int(key >> 32);
    if (b <= current_) {
      late_.push(key);
    } else {
      buckets_[b].push_back(key);
    }
  }
  // the smallest key, removed; the queue must not be empty
  std::uint64_t pop() {
    --size_;
    for (;;) {
      const bool have_sorted = cursor_ < sorted_.size();
      if (!late_.empty() && (!have_sorted || late_.top() < sorted_[cursor_])) {
        const std::uint64_t k = late_.top();
        late_.pop();
        return k;
      }
      if (have_sorted) return sorted_[cursor_++];
      // the current bucket is done: the next non-empty one, sorted
      do {
        ++current_;
      } while (buckets_[current_].empty());
      sorted_.swap(buckets_[current_]);
      buckets_[current_].clear();
      buckets_[current_].shrink_to_fit();
      cursor_ = 0;
      std::sort(sorted_.begin(), sorted_.end());
    }
  }

 private:
  std::vector<std::vector<std::uint64_t>> buckets_;
  std::vector<std::uint64_t> sorted_;  // the current bucket's keys, from cursor_ on
  std::size_t cursor_ = 0, size_ = 0;
  int current_ = -1;
  std::priority_queue<std::uint64_t, std::vector<std::uint64_t>, std::greater<std::uint64_t>> late_;
};

// Working order (D-340): faces breadth first across glued sides from face 0 (face_old: the
// input face of each working face), vertices by their first corner in that order, unreferenced
// ones last (vertex_new: the working id of each input vertex). Ids near in memory are then near
// on the surface whatever the input's order; Simplifier::finish() maps back to the input's ids.
void working_order(const IntrinsicTriangulation& fine, std::vector<Index>& face_old,
                   std::vector<Index>& vertex_new) {
  const Index nf = fine.n_faces(), nv = fine.n_vertices();
  std::vector<char> seen(nf, 0);
  face_old.clear();
  face_old.reserve(nf);
  for (Index seed = 0; seed < nf; ++seed) {
    if (seen[seed]) continue;
    seen[seed] = 1;
    face_old.push_back(seed);
    for (std::size_t q = face_old.size() - 1; q < face_old.size(); ++q) {
      for (int k = 0; k < 3; ++k) {
        const Index t = fine.twin(3 * face_old[q] + k);
        if (t < 0 || seen[T::face(t)]) continue;
        seen[T::face(t)] = 1;
        face_old.push_back(T::face(t));
      }
    }
  }
  vertex_new.assign(nv, kInvalidIndex);
  Index n_ordered = 0;
  for (Index f : face_old) {
    for (int k = 0; k < 3; ++k) {
      Index& id = vertex_new[fine.tail(3 * f + k)];
      if (id == kInvalidIndex) id = n_ordered++;
    }
  }
  for (Index v = 0; v < nv; ++v) {
    if (vertex_new[v] == kInvalidIndex) vertex_new[v] = n_ordered++;
  }
}

class Simplifier {
 public:
  explicit Simplifier(const IntrinsicTriangulation& fine);
  void run(Index target, const ProgressCallback& on_progress);
  void drain(ProgressMeter& meter);  // down to target_
  Simplification finish(const IntrinsicTriangulation& fine);

 private:
  // ---- mesh ----
  Index head(Index h) const { return sd_[T::next(h)].tail; }
  double angle(Index h) const {  // corner angle of face(h) at tail(h)
    const Index f0 = 3 * T::face(h);
    if (angle_[f0] < 0.0) {  // the face's three angles, once per change of its sides
      for (Index k = f0; k < f0 + 3; ++k) {
        angle_[k] = opposite_angle(sd_[T::next(k)].len, sd_[k].len, sd_[T::prev(k)].len);
      }
    }
    return angle_[h];
  }
  double area(Index f) const {
    return triangle_area(sd_[3 * f].len, sd_[3 * f + 1].len, sd_[3 * f + 2].len);
  }
  void set_side(Index slot, Index tail, Index twin, double len) {
    sd_[slot].tail = tail;
    sd_[slot].twin = twin;
    sd_[slot].len = len;
    angle_[3 * T::face(slot)] = -1.0;
    if (twin >= 0) sd_[twin].twin = slot;
  }
  void set_length(Index slot, double len) {  // a side's length only (the face's angles recomputed)
    sd_[slot].len = len;
    angle_[3 * T::face(slot)] = -1.0;
  }
  bool fan(Index rep, std::vector<Index>& out, bool& boundary) const;
  bool flip(Index h, bool loop = false);
  bool flip_loop(Index v, Index h);
  bool faces_of(Index v, std::vector<Index>& faces);
  bool rebuild_reps(Index v, const std::vector<Index>& faces);
  bool flip_loops(Index v);
  bool is_delaunay(Index h) const;
  void delaunay_repair(std::vector<Index>& stack);  // consumes the stack
  void remap_reps(Index v, const Index* from, const Index* to, int n);
  void touch_face(Index f);

  // ---- removal ----
  double cost(Index v);
  bool try_remove(Index v);
  bool flip_fan_down(Index v, bool boundary, std::vector<Index>& hs);
  void remove_interior(Index v, const std::vector<Index>& hs, bool place_v);
  void remove_ear(Index v, Index h0, bool place_v);
  bool removable(Index v, const std::vector<Index>& hs, bool boundary) const;
  void remove_degree_two(Index v, const std::vector<Index>& hs, bool place_v);
  bool is_pillow(Index v, const std::vector<Index>& hs) const;
  bool plan_fans(Index v, Index n_fans, Index& home);
  bool flip_outer(Index v, Index o);
  bool plan_pillows(const std::vector<std::vector<Index>>& fans, Index n_fans, bool has_home);
  void remove_pillow(const std::vector<Index>& hs, std::vector<Index>& points);
  bool equalize_digon(Index v, const std::vector<Index>& hs);
  void undo_digons(std::size_t flips_before);
  struct Digon {
    Index o0, o1;   // the outer sides of a fan of two faces
    double l0, l1;  // their lengths before equalize_digon()
  };
  std::vector<Digon> digons_;  // equalized for the removal being planned
  // removal by flattening: the link polygon of a closed fan laid out convex and triangulated
  struct PolygonPlan {
    std::vector<Index> ends;              // a_i: far end of spoke i, corner i of the polygon
    std::vector<double> side, beta, cum;  // l_i (a_i → a_i+1), half central angles, their sums
    double radius = 0.0;
    std::vector<std::array<int, 3>> tris;  // d − 2 corner triples i < k < j (counter-clockwise)
    std::vector<int> apex;                 // scratch of triangulate_polygon()
  };
  bool plan_polygon(Index v, const std::vector<Index>& hs, PolygonPlan& plan) const;
  bool triangulate_polygon(PolygonPlan& plan) const;
  void remove_polygon(Index v, const std::vector<Index>& hs, bool place_v,
                      std::vector<Index>& stack);
  void locate_in_plan(const std::vector<std::pair<Index, Eigen::Vector2d>>& moving,
                      const std::vector<Eigen::Vector2d>& pos, const std::vector<Index>& F);
  bool loop_longer_than_three(Index v, Index h0) const;
  void move_point(Index p, Index f, const Eigen::Vector3d& b) {
    pt_face_[p] = f;
    pt_bary_[p] = b;
    pts_[f].push_back(p);
  }

  Index nv_ = 0;
  int multiplicity_ = 1;
  // the working id of each input vertex (the constructor's order); every array below is indexed
  // by working ids, faces by working face ids
  std::vector<Index> vertex_new_;
  struct Side {
    Index tail, twin;  // vertex at the start; glued side or kInvalidIndex
    double len;
  };
  std::vector<Side> sd_;  // #H: a face's three sides in one cache line
  // #H: angle(h), cached per face (each removal asks for its star's angles several times: the
  // costs of its neighbours, the flips to degree 3); the face's first entry < 0: not computed
  mutable std::vector<double> angle_;
  std::vector<char> face_alive_, vertex_alive_;
  // CSR: one outgoing halfedge per fan of each vertex, v's in [rep_start_[v], rep_end_[v])
  // (a deleted pillow's fan leaves the range)
  std::vector<Index> rep_start_, rep_end_, rep_;
  std::vector<Index> comp_;           // component of each vertex
  std::vector<Index> comp_vertices_;  // alive vertices per component
  std::vector<char> comp_closed_;
  std::vector<double> comp_area0_, comp_density_;
  std::vector<std::vector<Index>> pts_;  // per face: removed fine vertices inside it
  std::vector<Index> pt_face_;
  std::vector<Eigen::Vector3d> pt_bary_;
  std::vector<Index> touched_;  // vertices whose star a rewrite changed
  // scratch buffers, kept between calls (no allocation per removal)
  std::vector<Index> moving_, hs_, ends_, sorted_, stack_;
  std::vector<double> gap_;
  std::vector<std::pair<double, Index>> candidates_;
  std::vector<std::vector<Index>> fans_;
  std::vector<char> bnd_, keep_, kind_;
  std::vector<Index> pillow_points_;
  std::vector<std::pair<Index, Eigen::Vector3d>> moving_bary_;
  PolygonPlan plan_;
  std::vector<Index> orphans_;    // plan_pillows(): pillow corners that die with v
  Index keeper_ = kInvalidIndex;  // plan_pillows(): a pillow corner keeping a fan
  Index target_ = 0;
  bool flatten_ = false;   // second pass: any closed fan may be flattened
  std::set<Index> tried_;  // self-edges flip_loops() tried
  Index alive_count_ = 0;
  SimplifyReport report_;
};

// Outgoing halfedges of the fan of `rep` in rotation order (twin(prev(h)) is the next one),
// starting at its boundary side if the fan has one. False if the fan is not a simple walk.
bool Simplifier::fan(Index rep, std::vector<Index>& out, bool& boundary) const {
  out.clear();
  boundary = false;
  const Index v = sd_[rep].tail;
  for (Index h = rep;;) {  // forward from rep: the next outgoing halfedge is twin(prev(h))
    if (sd_[h].tail != v || out.size() > 4096) return false;
    out.push_back(h);
    const Index t = sd_[T::prev(h)].twin;
    if (t == rep) return true;  // closed
    if (t < 0) break;
    h = t;
  }
  boundary = true;  // the ones before rep, back to the boundary side: next(twin(h)) each
  const std::size_t n_after = out.size();
  for (Index h = rep; sd_[h].twin >= 0;) {
    h = T::next(sd_[h].twin);
    if (sd_[h].tail != v || out.size() > 8192) return false;
    out.push_back(h);
  }
  std::reverse(out.begin() + n_after, out.end());
  std::rotate(out.begin(), out.begin() + n_after, out.end());
  return true;
}

bool Simplifier::is_delaunay(Index h) const {
  const Index t = sd_[h].twin;
  if (t < 0) return true;
  const double ca = opposite_cotan(sd_[h].len, sd_[T::next(h)].len, sd_[T::prev(h)].len);
  const double cb = opposite_cotan(sd_[t].len, sd_[T::next(t)].len, sd_[T::prev(t)].len);
  return !(ca + cb < -1e-12);
}

void Simplifier::remap_reps(Index v, const Index* from, const Index* to, int n) {
  for (Index k = rep_start_[v]; k < rep_end_[v]; ++k) {
    for (int i = 0; i < n; ++i) {
      if (rep_[k] == from[i] && sd_[to[i]].tail == v) {
        rep_[k] = to[i];
        break;
      }
    }
  }
}

void Simplifier::touch_face(Index f) {
  for (int s = 0; s < 3; ++s) touched_.push_back(sd_[3 * f + s].tail);
}

// Flips the edge of h in its diamond (a, b, c | b, a, d) to the diagonal c–d, moving the
// points of both faces. False (nothing changed) unless the diamond is strictly convex and
// both new faces keep the margin.
bool Simplifier::flip(Index h, bool loop) {
  const Index t = sd_[h].twin;
  if (t < 0) return false;
  const Index f = T::face(h), g = T::face(t);
  if (f == g) return false;
  const Index h1 = T::next(h), h2 = T::prev(h), t1 = T::next(t), t2 = T::prev(t);
  for (Index o : {h1, h2, t1, t2}) {
    const Index w = sd_[o].twin;
    if (w >= 0 && (T::face(w) == f || T::face(w) == g)) return false;
  }
  const Index a = sd_[h].tail, b = sd_[h1].tail, c = sd_[h2].tail, d = sd_[t2].tail;
  // four distinct vertices: a repeated one (a self-edge in the diamond) could join or split its
  // fans, which the per-fan representatives do not follow
  // (loop: the edge a = b is a self-edge, c and d distinct from it and each other; the caller
  // rebuilds a's representatives)
  if (c == d || a == c || a == d || b == c || b == d || (a == b) != loop) return false;
  const double lab = sd_[h].len, lbc = sd_[h1].len, lca = sd_[h2].len, lad = sd_[t1].len,
               ldb = sd_[t2].len;
  const Eigen::Vector2d A(0.0, 0.0), B(lab, 0.0);
  const Eigen::Vector2d C = triangle_apex(lab, lbc, lca);
  Eigen::Vector2d D = triangle_apex(lab, ldb, lad);
  D.y() = -D.y();
  const double sa = cross2(D - C, A - C), sb = cross2(D - C, B - C);
  if (!(sa < 0.0 && sb > 0.0)) return false;  // A right of C→D, B left: strictly convex
  const double lcd = (C - D).norm();
  if (!good_triangle(lca, lad, lcd) || !good_triangle(ldb, lbc, lcd)) return false;
  // old corner positions by slot, then the points of both faces
  Eigen::Vector2d pf[3], pg[3];
  pf[T::side(h)] = A, pf[T::side(h1)] = B, pf[T::side(h2)] = C;
  pg[T::side(t)] = B, pg[T::side(t1)] = A, pg[T::side(t2)] = D;
  std::vector<Index>& moving = moving_;
  moving.assign(pts_[f].begin(), pts_[f].end());
  const std::size_t nf = moving.size();
  moving.insert(moving.end(), pts_[g].begin(), pts_[g].end());
  pts_[f].clear();
  pts_[g].clear();
  const Index tw_h1 = sd_[h1].twin, tw_h2 = sd_[h2].twin, tw_t1 = sd_[t1].twin,
              tw_t2 = sd_[t2].twin;
  set_side(3 * f + 0, c, tw_h2, lca);
  set_side(3 * f + 1, a, tw_t1, lad);
  set_side(3 * f + 2, d, 3 * g + 2, lcd);
  set_side(3 * g + 0, d, tw_t2, ldb);
  set_side(3 * g + 1, b, tw_h1, lbc);
  set_side(3 * g + 2, c, 3 * f + 2, lcd);
  for (std::size_t i = 0; i < moving.size(); ++i) {
    const Index p = moving[i];
    const Eigen::Vector3d& w = pt_bary_[p];
    const Eigen::Vector2d* q = i < nf ? pf : pg;
    const Eigen::Vector2d P = w[0] * q[0] + w[1] * q[1] + w[2] * q[2];
    const Eigen::Vector3d bf = bary_of(P, C, A, D), bg = bary_of(P, D, B, C);
    if (bf.minCoeff() >= bg.minCoeff()) {
      move_point(p, f, clamp_bary(bf));
    } else {
      move_point(p, g, clamp_bary(bg));
    }
  }
  const Index from[6] = {h, t, h1, h2, t1, t2};
  const Index to[6] = {3 * f + 1, 3 * g + 1, 3 * g + 1, 3 * f + 0, 3 * f + 1, 3 * g + 0};
  for (Index x : {a, b, c, d}) remap_reps(x, from, to, 6);
  // (from[] names slots by their old roles; remap_reps only checks the new tail)
  touch_face(f);
  touch_face(g);
  ++report_.flips;
  return true;
}

// Flips non-Delaunay edges reachable from the halfedges on the stack (a cap against loops).
void Simplifier::delaunay_repair(std::vector<Index>& stack) {
  std::size_t budget = 64 + 16 * stack.size();
  while (!stack.empty() && budget > 0) {
    const Index h = stack.back();
    stack.pop_back();
    if (!face_alive_[T::face(h)] || sd_[h].twin < 0 || is_delaunay(h)) continue;
    const Index f = T::face(h), g = T::face(sd_[h].twin);
    if (!flip(h)) continue;
    --budget;
    for (Index s : {3 * f, 3 * f + 1, 3 * g, 3 * g + 1}) stack.push_back(s);
  }
}

Simplifier::Simplifier(const IntrinsicTriangulation& fine)
    : nv_(fine.n_vertices()), multiplicity_(fine.multiplicity()), sd_(fine.tails().size()) {
  const Index nh = fine.n_halfedges(), nf = fine.n_faces();
  std::vector<Index> face_old;
  working_order(fine, face_old, vertex_new_);
  std::vector<Index> face_new(nf);
  for (Index f = 0; f < nf; ++f) face_new[face_old[f]] = f;
  for (Index f = 0; f < nf; ++f) {
    for (int k = 0; k < 3; ++k) {
      const Index h = 3 * face_old[f] + k, t = fine.twin(h);
      sd_[3 * f + k] = {vertex_new_[fine.tail(h)],
                        t < 0 ? kInvalidIndex : 3 * face_new[T::face(t)] + T::side(t),
                        fine.halfedge_length(h)};
    }
  }
  angle_.assign(sd_.size(), -1.0);
  face_alive_.assign(nf, 1);
  pts_.resize(nf);
  pt_face_.assign(nv_, kInvalidIndex);
  pt_bary_.assign(nv_, Eigen::Vector3d::Zero());
  // fans: one representative per fan, found by walking every halfedge once
  std::vector<char> seen(nh, 0);
  std::vector<std::vector<Index>> reps(nv_);
  std::vector<Index> hs;
  for (Index h = 0; h < nh; ++h) {
    if (seen[h]) continue;
    bool boundary = false;
    if (!fan(h, hs, boundary)) hs.assign(1, h);  // not a simple walk: h alone (never removed)
    for (Index x : hs) seen[x] = 1;
    reps[sd_[h].tail].push_back(hs.front());
  }
  rep_start_.assign(nv_ + 1, 0);
  for (Index v = 0; v < nv_; ++v) rep_start_[v + 1] = rep_start_[v] + Index(reps[v].size());
  for (Index v = 0; v < nv_; ++v) rep_.insert(rep_.end(), reps[v].begin(), reps[v].end());
  rep_end_.assign(rep_start_.begin() + 1, rep_start_.end());
  // components (by faces), their vertex counts, areas and whether they are closed
  UnionFind uf(nv_);
  for (Index h = 0; h < nh; ++h) uf.unite(sd_[h].tail, head(h));
  comp_.resize(nv_);
  std::vector<Index> root_id(nv_, kInvalidIndex);
  for (Index v = 0; v < nv_; ++v) {
    const Index r = uf.find(v);
    if (root_id[r] == kInvalidIndex) {
      root_id[r] = Index(comp_vertices_.size());
      comp_vertices_.push_back(0);
    }
    comp_[v] = root_id[r];
    ++comp_vertices_[comp_[v]];
  }
  comp_closed_.assign(comp_vertices_.size(), 1);
  comp_area0_.assign(comp_vertices_.size(), 0.0);
  for (Index h = 0; h < nh; ++h) {
    if (sd_[h].twin < 0) comp_closed_[comp_[sd_[h].tail]] = 0;
  }
  for (Index f = 0; f < nf; ++f) comp_area0_[comp_[sd_[3 * f].tail]] += area(f);
  comp_density_.resize(comp_area0_.size());
  for (std::size_t c = 0; c < comp_area0_.size(); ++c) {
    comp_density_[c] = comp_area0_[c] > 0.0 ? 4.0 * kPi / comp_area0_[c] : 0.0;
  }
  vertex_alive_.assign(nv_, 1);
  alive_count_ = nv_;
}

// Removal cost (simplify.h): star area × (|angle defect| + 4π / component area); +inf when v
// cannot be removed as it is (no face, several fans one of which has a boundary, a boundary
// angle ≥ π, a closed component at 4 vertices).
double Simplifier::cost(Index v) {
  const Index n_fans = rep_end_[v] - rep_start_[v];
  if (n_fans == 0) return HUGE_VAL;
  if (comp_closed_[comp_[v]] && comp_vertices_[comp_[v]] <= 4) return HUGE_VAL;
  std::vector<Index>& hs = hs_;
  double star = 0.0, defect = 0.0;
  for (Index k = rep_start_[v]; k < rep_end_[v]; ++k) {
    bool boundary = false;
    if (!fan(rep_[k], hs, boundary)) return HUGE_VAL;
    if (boundary && n_fans > 1) return HUGE_VAL;
    double theta = 0.0;
    for (Index h : hs) {
      theta += angle(h);
      star += area(T::face(h));
    }
    if (boundary && theta >= kPi * (1.0 - 1e-6)) return HUGE_VAL;
    defect += std::abs((boundary ? kPi : 2.0 * kPi) - theta);
  }
  return star * (defect + star * comp_density_[comp_[v]]);
}

// True if the boundary loop through v (h0: v's outgoing boundary side) has 4+ vertices.
bool Simplifier::loop_longer_than_three(Index v, Index h0) const {
  Index h = h0;
  for (int step = 0; step < 3; ++step) {
    // the next boundary side: from head(h), rewind its fan to the boundary side
    Index x = T::next(h);
    for (int k = 0; sd_[x].twin >= 0; ++k) {
      x = T::next(sd_[x].twin);
      if (k > 4096) return false;
    }
    h = x;
    if (sd_[h].tail == v) return false;
  }
  return true;
}

// The three spokes of the closed fan hs (outgoing halfedges in rotation order) to keep when
// flipping it down to degree 3: their far ends (vertex ids), chosen so that the three angles
// at v between them are below π and their largest is smallest (v well inside the face that
// replaces them). False if there are none (an angle sum of 3π or more).
bool keep_three(const std::vector<double>& gap, const std::vector<Index>& ends,
                std::vector<char>& keep) {
  const std::size_t d = gap.size();
  std::vector<double> phi(d + 1, 0.0);
  for (std::size_t i = 0; i < d; ++i) phi[i + 1] = phi[i] + gap[i];
  double best = kPi;
  for (std::size_t i = 0; i < d; ++i) {
    for (std::size_t j = i + 1; j < d; ++j) {
      if (phi[j] - phi[i] >= best) break;
      for (std::size_t k = j + 1; k < d; ++k) {
        const double worst = std::max({phi[j] - phi[i], phi[k] - phi[j], phi[d] - phi[k] + phi[i]});
        if (worst >= best || ends[i] == ends[j] || ends[j] == ends[k] || ends[k] == ends[i]) {
          continue;  // (a repeated end: the face would have a self-edge)
        }
        best = worst;
        keep.assign(d, 0);
        keep[i] = keep[j] = keep[k] = 1;
      }
    }
  }
  return best < kPi;
}

// Flips the spokes of the fan hs of v (outgoing halfedges in rotation order) until it has 3
// faces (closed: the spokes keep_three() picks stay) or 1 face (boundary), each time the
// flippable spoke whose far end has the smallest angle in its two faces (an ear of the star).
// hs follows the flips. False when no spoke can be flipped.
bool Simplifier::flip_fan_down(Index v, bool boundary, std::vector<Index>& hs) {
  const std::size_t want = boundary ? 1 : 3;
  std::vector<Index>& ends = ends_;
  std::vector<double>& gap = gap_;
  ends.resize(hs.size());
  gap.resize(hs.size());
  for (std::size_t i = 0; i < hs.size(); ++i) ends[i] = head(hs[i]), gap[i] = angle(hs[i]);
  std::vector<Index>& sorted = sorted_;
  sorted.assign(ends.begin(), ends.end());
  std::sort(sorted.begin(), sorted.end());
  if (std::binary_search(sorted.begin(), sorted.end(), v)) return false;  // a self-edge
  // a far end twice: allowed around a closed fan (a zipped boundary of the tufted cover: point
  // clouds), not on a boundary fan
  if (boundary && std::adjacent_find(sorted.begin(), sorted.end()) != sorted.end()) return false;
  std::vector<char>& keep = keep_;  // per spoke of hs: one of the three kept
  keep.assign(hs.size(), 0);
  if (!boundary && hs.size() > 3 && !keep_three(gap, ends, keep)) return false;
  std::vector<std::pair<double, Index>>& candidates = candidates_;
  for (;;) {
    if (hs.size() <= want) return hs.size() == want || (!boundary && hs.size() == 2);
    candidates.clear();
    for (std::size_t i = 0; i < hs.size(); ++i) {
      const Index h = hs[i], t = sd_[h].twin;  // t: u→v in the previous face
      if (t < 0 || keep[i]) continue;
      const double at_u = angle(T::next(h)) + angle(t);
      const double at_v = angle(h) + angle(T::next(t));
      if (at_u < kPi && at_v < kPi) candidates.emplace_back(at_u, h);
    }
    std::sort(candidates.begin(), candidates.end());
    Index flipped = kInvalidIndex;
    for (const auto& c : candidates) {
      if (flip(c.second)) {
        flipped = c.second;
        break;
      }
    }
    if (flipped == kInvalidIndex) return false;
    // the fan without the flipped spoke: the spoke before it (in the other face of the diamond)
    // became v's side 3f+1 of the flipped face f; no other spoke moved
    const std::size_t i = std::find(hs.begin(), hs.end(), flipped) - hs.begin();
    hs[(i + hs.size() - 1) % hs.size()] = 3 * T::face(flipped) + 1;
    hs.erase(hs.begin() + i);
    keep.erase(keep.begin() + i);
  }
}

// Replaces the degree-3 fan hs of v by the face of its three outer sides (reusing the first
// face's slots). The points of the three faces (and v, when place_v) go to the new face: v at
// the barycentric coordinates given by the three faces' areas (its own, when the star is flat),
// each face (v, a_i, a_i+1) mapped linearly onto (that point, a_i, a_i+1).
void Simplifier::remove_interior(Index v, const std::vector<Index>& hs, bool place_v) {
  Index F[3], o[3], a[3], tw[3];
  double l[3], A[3];
  for (int i = 0; i < 3; ++i) {
    F[i] = T::face(hs[i]);
    o[i] = T::next(hs[i]);
    a[i] = sd_[o[i]].tail;
    A[i] = area(F[i]);
    tw[i] = sd_[o[i]].twin;
    l[i] = sd_[o[i]].len;
  }
  Eigen::Vector3d q;
  for (int i = 0; i < 3; ++i) q[(i + 2) % 3] = A[i];
  q = clamp_bary(q);
  auto& moving = moving_bary_;
  moving.clear();
  for (int i = 0; i < 3; ++i) {
    const int sv = T::side(hs[i]), sa = T::side(o[i]), sb = T::side(T::prev(hs[i]));
    for (Index p : pts_[F[i]]) {
      const Eigen::Vector3d& w = pt_bary_[p];
      Eigen::Vector3d nb = w[sv] * q;
      nb[i] += w[sa];
      nb[(i + 1) % 3] += w[sb];
      moving.emplace_back(p, nb);
    }
    pts_[F[i]].clear();
  }
  face_alive_[F[1]] = face_alive_[F[2]] = 0;
  const Index f0 = F[0];
  for (int i = 0; i < 3; ++i) set_side(3 * f0 + i, a[i], tw[i], l[i]);
  for (int i = 0; i < 3; ++i) {
    for (Index k = rep_start_[a[i]]; k < rep_end_[a[i]]; ++k) {
      const Index fr = T::face(rep_[k]);
      if (fr == F[0] || fr == F[1] || fr == F[2]) rep_[k] = 3 * f0 + i;
    }
  }
  for (const auto& [p, nb] : moving) move_point(p, f0, clamp_bary(nb));
  if (place_v) move_point(v, f0, q);
  touch_face(f0);
}

// Cuts off the ear face(h0) = (v, x, y) of boundary vertex v (h0: v→x on the boundary); its
// points (and v, when place_v) go to their closest points on the side x–y of the face across it.
void Simplifier::remove_ear(Index v, Index h0, bool place_v) {
  const Index F = T::face(h0), o = T::next(h0), p = T::prev(h0), w = sd_[o].twin;
  const Index x = sd_[o].tail, y = sd_[p].tail;
  const double lxy = sd_[o].len;
  Eigen::Vector2d pos[3];
  pos[T::side(o)] = Eigen::Vector2d(0.0, 0.0);
  pos[T::side(p)] = Eigen::Vector2d(lxy, 0.0);
  pos[T::side(h0)] = triangle_apex(lxy, sd_[p].len, sd_[h0].len);
  const Index g = T::face(w);
  auto on_side = [&](const Eigen::Vector3d& wb) {
    const Eigen::Vector2d P = wb[0] * pos[0] + wb[1] * pos[1] + wb[2] * pos[2];
    const double t = std::clamp(P.x() / lxy, 0.0, 1.0);
    Eigen::Vector3d nb = Eigen::Vector3d::Zero();
    nb[T::side(w)] = t;                 // y
    nb[T::side(T::next(w))] = 1.0 - t;  // x
    return nb;
  };
  std::vector<Index> moving;
  moving.swap(pts_[F]);
  for (Index q : moving) move_point(q, g, on_side(pt_bary_[q]));
  if (place_v) {
    Eigen::Vector3d e = Eigen::Vector3d::Zero();
    e[T::side(h0)] = 1.0;
    move_point(v, g, on_side(e));
  }
  face_alive_[F] = 0;
  sd_[w].twin = kInvalidIndex;
  for (Index k = rep_start_[x]; k < rep_end_[x]; ++k) {
    if (T::face(rep_[k]) == F) rep_[k] = T::next(w);
  }
  for (Index k = rep_start_[y]; k < rep_end_[y]; ++k) {
    if (T::face(rep_[k]) == F) rep_[k] = w;
  }
  touch_face(g);
}

// Removes v from its two faces (v, a, b), (v, b, a) (a zipped boundary of the tufted cover):
// the faces go, their outer sides' partners are glued to each other (equal lengths, checked by
// removable()); the points of the two faces (and v, when place_v) go to their closest points
// on that edge, in the face of the first partner.
void Simplifier::remove_degree_two(Index v, const std::vector<Index>& hs, bool place_v) {
  const Index o0 = T::next(hs[0]), o1 = T::next(hs[1]);
  const Index w0 = sd_[o0].twin, w1 = sd_[o1].twin;  // w0: b→a, w1: a→b
  const Index a = sd_[o0].tail, b = sd_[o1].tail;
  const double lab = sd_[o0].len;
  auto along = [&](Index h, const Eigen::Vector3d& wb, bool from_a) {  // t from a to b
    Eigen::Vector2d pos[3];  // the face of spoke h (v→x) laid out with its outer side on x
    pos[T::side(T::next(h))] = Eigen::Vector2d(0.0, 0.0);
    pos[T::side(T::prev(h))] = Eigen::Vector2d(lab, 0.0);
    pos[T::side(h)] = triangle_apex(lab, sd_[T::prev(h)].len, sd_[h].len);
    const Eigen::Vector2d P = wb[0] * pos[0] + wb[1] * pos[1] + wb[2] * pos[2];
    const double t = std::clamp(P.x() / lab, 0.0, 1.0);
    return from_a ? t : 1.0 - t;
  };
  const Index g = T::face(w0);
  auto on_edge = [&](double t) {  // the point a + t·(b − a) in face g
    Eigen::Vector3d nb = Eigen::Vector3d::Zero();
    nb[T::side(w0)] = t;                 // b
    nb[T::side(T::next(w0))] = 1.0 - t;  // a
    return nb;
  };
  for (int i = 0; i < 2; ++i) {
    const Index f = T::face(hs[i]);
    std::vector<Index> moving;
    moving.swap(pts_[f]);
    for (Index q : moving) move_point(q, g, on_edge(along(hs[i], pt_bary_[q], i == 0)));
    face_alive_[f] = 0;
  }
  if (place_v) {
    Eigen::Vector3d e = Eigen::Vector3d::Zero();
    e[T::side(hs[0])] = 1.0;
    move_point(v, g, on_edge(along(hs[0], e, true)));
  }
  sd_[w0].twin = w1;
  sd_[w1].twin = w0;
  const Index f0 = T::face(hs[0]), f1 = T::face(hs[1]);
  for (Index k = rep_start_[a]; k < rep_end_[a]; ++k) {
    if (T::face(rep_[k]) == f0 || T::face(rep_[k]) == f1) rep_[k] = T::next(w0);
  }
  for (Index k = rep_start_[b]; k < rep_end_[b]; ++k) {
    if (T::face(rep_[k]) == f0 || T::face(rep_[k]) == f1) rep_[k] = w0;
  }
  touch_face(g);
  touch_face(T::face(w1));
}

// The checks a flipped-down fan must pass before anything is removed (simplify.h).
bool Simplifier::removable(Index v, const std::vector<Index>& hs, bool boundary) const {
  if (boundary) {
    const Index o = T::next(hs[0]);
    return hs.size() == 1 && sd_[o].twin >= 0 && sd_[o].tail != head(o) && sd_[o].tail != v &&
           head(o) != v;
  }
  if (hs.size() == 2) {  // two faces (v, a, b), (v, b, a) whose outer sides get glued
    const Index o0 = T::next(hs[0]), o1 = T::next(hs[1]);
    const Index w0 = sd_[o0].twin, w1 = sd_[o1].twin, a = sd_[o0].tail, b = sd_[o1].tail;
    const Index f0 = T::face(hs[0]), f1 = T::face(hs[1]);
    return a != b && a != v && b != v && f0 != f1 && w0 >= 0 && w1 >= 0 && w0 != o1 &&
           T::face(w0) != f0 && T::face(w0) != f1 && T::face(w1) != f0 && T::face(w1) != f1 &&
           std::abs(sd_[o0].len - sd_[o1].len) <= 1e-12 * sd_[o0].len;
  }
  if (hs.size() != 3) return false;
  Index a[3];
  double l[3];
  for (int i = 0; i < 3; ++i) {
    const Index o = T::next(hs[i]);
    a[i] = sd_[o].tail;
    l[i] = sd_[o].len;
    const Index w = sd_[o].twin;
    for (Index x : hs) {
      if (w >= 0 && T::face(w) == T::face(x)) return false;  // glued inside the star
    }
  }
  if (a[0] == a[1] || a[1] == a[2] || a[2] == a[0] || a[0] == v || a[1] == v || a[2] == v) {
    return false;
  }
  return good_triangle(l[0], l[1], l[2]);
}

// Triangulates the planned polygon into plan.tris: over every range of corners i..j, by
// dynamic programming (O(d³)), a triangle (i, k, j) keeping the margin, no new side from a
// vertex to itself (a polygon side may be one already), both sides triangulable, the apex k
// nearest the middle. False if there is none.
bool Simplifier::triangulate_polygon(PolygonPlan& plan) const {
  const int d = int(plan.ends.size());
  auto chord = [&](int x, int y) {  // x < y
    if (y == x + 1) return plan.side[x];
    if (x == 0 && y == d - 1) return plan.side[d - 1];
    return 2.0 * plan.radius * std::sin(plan.cum[y] - plan.cum[x]);
  };
  auto self_diagonal = [&](int x, int y) {  // a new side from a vertex to itself
    return y != x + 1 && !(x == 0 && y == d - 1) && plan.ends[x] == plan.ends[y];
  };
  std::vector<int>& apex = plan.apex;  // apex[i·d + j]: −1 none, 0 for j − i < 2
  apex.assign(std::size_t(d) * d, -1);
  for (int i = 0; i + 1 < d; ++i) apex[i * d + i + 1] = 0;
  for (int span = 2; span < d; ++span) {
    for (int i = 0; i + span < d; ++i) {
      const int j = i + span, mid = (i + j) / 2;
      for (int step = 0; step < 2 * span && apex[i * d + j] < 0; ++step) {
        const int k = step % 2 == 0 ? mid + step / 2 : mid - (step + 1) / 2;
        if (k <= i || k >= j || apex[i * d + k] < 0 || apex[k * d + j] < 0) continue;
        if (self_diagonal(i, k) || self_diagonal(k, j) || self_diagonal(i, j)) continue;
        if (good_triangle(chord(i, k), chord(k, j), chord(i, j))) {
          apex[i * d + j] = k;
        }
      }
    }
  }
  if (apex[d - 1] < 0) return false;
  std::vector<std::pair<int, int>> todo{{0, d - 1}};
  while (!todo.empty()) {
    const auto [i, j] = todo.back();
    todo.pop_back();
    if (j - i < 2) continue;
    const int k = apex[i * d + j];
    plan.tris.push_back({i, k, j});
    todo.emplace_back(i, k);
    todo.emplace_back(k, j);
  }
  return true;
}

// Plans v's removal from its closed fan hs by flattening (simplify.h): the link polygon
// a_0 … a_d−1 (sides the fan's outer sides, lengths kept) inscribed in a circle and triangulated.
// False when v is on its own link, an outer side is glued inside the star, or no such polygon or
// triangulation keeps the margin.
bool Simplifier::plan_polygon(Index v, const std::vector<Index>& hs, PolygonPlan& plan) const {
  const std::size_t d = hs.size();
  if (d < 3 || d > 1024) return false;
  plan.ends.resize(d);
  plan.side.resize(d);
  plan.tris.clear();
  for (std::size_t i = 0; i < d; ++i) {
    const Index o = T::next(hs[i]), w = sd_[o].twin;
    plan.ends[i] = sd_[o].tail;
    plan.side[i] = sd_[o].len;
    if (plan.ends[i] == v) return false;
    for (Index x : hs) {  // glued inside the star: only to another outer side (kept glued)
      if (w >= 0 && T::face(w) == T::face(x) && w != T::next(x)) return false;
    }
  }
  if (!cyclic_polygon(plan.side, plan.beta, plan.radius)) return false;
  plan.cum.assign(d + 1, 0.0);
  for (std::size_t i = 0; i < d; ++i) plan.cum[i + 1] = plan.cum[i] + plan.beta[i];
  return triangulate_polygon(plan);
}

// Moves each point (2D position in the planned polygon) to the new triangle of plan_ that holds
// it best (largest smallest barycentric coordinate, clamped): triangle t is face F[t].
void Simplifier::locate_in_plan(const std::vector<std::pair<Index, Eigen::Vector2d>>& moving,
                                const std::vector<Eigen::Vector2d>& pos,
                                const std::vector<Index>& F) {
  for (const auto& [p, P] : moving) {
    std::size_t best = 0;
    Eigen::Vector3d best_b(-HUGE_VAL, 0.0, 0.0);
    for (std::size_t t = 0; t < plan_.tris.size(); ++t) {
      const auto& c = plan_.tris[t];
      const Eigen::Vector3d b = bary_of(P, pos[c[0]], pos[c[1]], pos[c[2]]);
      if (b.minCoeff() > best_b.minCoeff()) best = t, best_b = b;
    }
    move_point(p, F[best], clamp_bary(best_b));
  }
}

// Removes v from its closed fan hs by the plan of plan_polygon() (which must hold): the d − 2
// triangles reuse the first d − 2 faces' slots. v goes to p_v, the mean of the corners weighted
// by 1 / spoke length (inside the convex polygon); each face (v, a_i, a_i+1) maps linearly onto
// (p_v, a_i, a_i+1), and its points are located in the new triangles. The new faces' sides are
// pushed on the stack (Delaunay repair).
void Simplifier::remove_polygon(Index v, const std::vector<Index>& hs, bool place_v,
                                std::vector<Index>& stack) {
  PolygonPlan& plan = plan_;
  if (!plan_polygon(v, hs, plan)) {  // checked by try_remove(); only gluing could change since
    throw Error("simplify: internal: a fan planned for flattening changed before its removal");
  }
  const int d = int(hs.size());
  std::vector<Index> F(d), o(d), tw(d), side_slot(d, kInvalidIndex);
  std::vector<Eigen::Vector2d> pos(d);
  Eigen::Vector2d pv = Eigen::Vector2d::Zero();
  double wsum = 0.0;
  for (int i = 0; i < d; ++i) {
    F[i] = T::face(hs[i]);
    o[i] = T::next(hs[i]);
    tw[i] = sd_[o[i]].twin;
    const double a = 2.0 * plan.cum[i];
    pos[i] = plan.radius * Eigen::Vector2d(std::cos(a), std::sin(a));
    const double w = 1.0 / std::max(sd_[hs[i]].len, 1e-300);
    pv += w * pos[i];
    wsum += w;
  }
  pv /= wsum;
  std::vector<std::pair<Index, Eigen::Vector2d>> moving;
  for (int i = 0; i < d; ++i) {
    const int sv = T::side(hs[i]), sa = T::side(o[i]), sb = T::side(T::prev(hs[i]));
    for (Index p : pts_[F[i]]) {
      const Eigen::Vector3d& w = pt_bary_[p];
      moving.emplace_back(p, w[sv] * pv + w[sa] * pos[i] + w[sb] * pos[(i + 1) % d]);
    }
    pts_[F[i]].clear();
  }
  if (place_v) moving.emplace_back(v, pv);
  // new rep of each link vertex whose rep was a slot of the star (by the old slot's role)
  std::vector<std::pair<Index, int>> rep_role;  // rep index, polygon corner
  std::vector<Index> distinct(plan.ends);
  std::sort(distinct.begin(), distinct.end());
  distinct.erase(std::unique(distinct.begin(), distinct.end()), distinct.end());
  for (Index u : distinct) {
    for (Index k = rep_start_[u]; k < rep_end_[u]; ++k) {
      for (int j = 0; j < d; ++j) {
        if (rep_[k] == o[j]) rep_role.emplace_back(k, j);
        if (rep_[k] == T::prev(hs[j])) rep_role.emplace_back(k, (j + 1) % d);
      }
    }
  }
  // the new faces and their gluing
  std::vector<std::tuple<int, int, Index>> diagonals;  // (from corner, to corner, slot)
  for (std::size_t t = 0; t < plan.tris.size(); ++t) {
    const auto& c = plan.tris[t];
    const Index f = F[t];
    for (int s = 0; s < 3; ++s) {
      const int x = c[s], y = c[(s + 1) % 3], slot = int(3 * f + s);
      if (y == (x + 1) % d) {  // a side of the polygon (glued to another one: below)
        const bool inner = std::find(o.begin(), o.end(), tw[x]) != o.end();
        set_side(slot, plan.ends[x], inner ? kInvalidIndex : tw[x], plan.side[x]);
        side_slot[x] = slot;
        continue;
      }
      const double len = 2.0 * plan.radius * std::sin(std::abs(plan.cum[y] - plan.cum[x]));
      Index partner = kInvalidIndex;
      for (const auto& [dx, dy, ds] : diagonals) {
        if (dx == y && dy == x) partner = ds;
      }
      set_side(slot, plan.ends[x], partner, len);
      diagonals.emplace_back(x, y, slot);
    }
    face_alive_[f] = 1;
    touch_face(f);
    for (int s = 0; s < 3; ++s) stack.push_back(3 * f + s);
  }
  for (int x = 0; x < d; ++x) {  // outer sides glued to each other stay glued
    const std::size_t y = std::find(o.begin(), o.end(), tw[x]) - o.begin();
    if (y < o.size()) sd_[side_slot[x]].twin = side_slot[y];
  }
  for (int i = int(plan.tris.size()); i < d; ++i) face_alive_[F[i]] = 0;
  for (const auto& [k, corner] : rep_role) rep_[k] = side_slot[corner];
  locate_in_plan(moving, pos, F);
  ++report_.flattened;
}

// Flips the outer side o of one of v's fans, across a face without v (so v's other fans stay as
// walked): the fan gains a face.
bool Simplifier::flip_outer(Index v, Index o) {
  const Index w = sd_[o].twin;
  if (w < 0) return false;
  for (int c = 0; c < 3; ++c) {
    if (sd_[3 * T::face(w) + c].tail == v) return false;
  }
  return flip(o);
}

// Walks v's fans and readies each for removal (simplify.h): a pillow as it is; a fan flipped
// down to 3 faces (an ear, 2 zipped faces); else a closed fan planned for flattening (a fan of
// two faces that cannot be zipped gets an outer side flipped first). `home`: the first fan that
// is not a pillow (none: v has only pillows, and goes to a corner of one that keeps a fan).
// False when some fan cannot be removed (flips made stay).
bool Simplifier::plan_fans(Index v, Index n_fans, Index& home) {
  std::vector<std::vector<Index>>& fans = fans_;
  std::vector<char>&kind = kind_, &bnd = bnd_;
  // first, before any fan is planned (plans read the outer sides' lengths): digons to zip (the
  // tufted cover only: manifold inputs as before)
  for (Index k = 0; multiplicity_ > 1 && k < n_fans; ++k) {
    bool b = false;
    if (!fan(rep_[rep_start_[v] + k], fans[k], b)) return false;
    if (!b && fans[k].size() == 2 && !is_pillow(v, fans[k]) && !removable(v, fans[k], b)) {
      equalize_digon(v, fans[k]);
    }
  }
  for (Index k = 0; k < n_fans; ++k) {
    bool b = false;
    if (!fan(rep_[rep_start_[v] + k], fans[k], b) || (b && n_fans > 1)) return false;
    bnd[k] = b;
    if (b && !loop_longer_than_three(v, fans[k][0])) return false;
    if (!b && is_pillow(v, fans[k])) {
      kind[k] = 2;
      continue;
    }
    if (home == kInvalidIndex) home = k;
    if (!b && fans[k].size() == 2 && !removable(v, fans[k], b)) {
      // outer sides of unequal lengths: one flipped makes three faces, which flattening can take
      if (flip_outer(v, T::next(fans[k][0])) || flip_outer(v, T::next(fans[k][1]))) {
        if (!fan(rep_[rep_start_[v] + k], fans[k], b) || b) return false;
      }
    }
    // flattening (closed fans only) where flips to 3 faces cannot be had: an angle sum of 3π
    // or more, or a vertex with several fans (all must go at once); otherwise a fan waits for
    // its star to change, and is flattened only in the second pass (run())
    double theta = 0.0;
    for (Index h : fans[k]) theta += angle(h);
    const bool may_flatten = flatten_ || n_fans > 1 || theta >= 3.0 * kPi * (1.0 - 1e-9);
    kind[k] = !(flip_fan_down(v, b, fans[k]) && removable(v, fans[k], b));
    if (kind[k] == 1 && (b || !may_flatten)) return false;
    // a link with a side as long as the others together: its longest side flipped outwards
    for (int tries = 0; kind[k] == 1 && !plan_polygon(v, fans[k], plan_); ++tries) {
      Index longest = T::next(fans[k][0]);
      for (Index h : fans[k]) {
        if (sd_[T::next(h)].len > sd_[longest].len) longest = T::next(h);
      }
      if (tries == 2 || !flip_outer(v, longest)) return false;
      if (!fan(rep_[rep_start_[v] + k], fans[k], b) || b) return false;
    }
  }
  // two fans of two faces glued to each other (a closed surface of v, a, b through two fans of
  // v): the first zip would glue the second's sides to each other
  std::vector<Index>& digon_faces = ends_;
  digon_faces.clear();
  for (Index k = 0; k < n_fans; ++k) {
    if (kind[k] == 0 && !bnd[k] && fans[k].size() == 2) {
      for (Index h : fans[k]) digon_faces.push_back(T::face(h));
    }
  }
  for (Index k = 0; k < n_fans && digon_faces.size() > 2; ++k) {
    if (kind[k] != 0 || bnd[k] || fans[k].size() != 2) continue;
    for (Index h : fans[k]) {
      const Index g = T::face(sd_[T::next(h)].twin);
      if (std::find(digon_faces.begin(), digon_faces.end(), g) != digon_faces.end()) return false;
    }
  }
  return plan_pillows(fans, n_fans, home != kInvalidIndex);
}

// A closed fan of v of two faces (v, a, b), (v, b, a) whose outer sides differ in length, so
// that they cannot be zipped (remove_degree_two()), and cannot be flipped out where the faces
// across them are v's own (the faces of its other fans, removed with it): both outer sides and
// their partners get one length, the mean or the nearest one every face they bound keeps the
// margin with (undone by undo_digons() if v is not removed). The metric
// changes only in v's star where both faces across have v (they are replaced anyway), else
// only where the two lengths agree to 1 %. False (nothing changed) when a face across would
// lose the margin, or the gluing is not that of two faces with two partners outside them.
bool Simplifier::equalize_digon(Index v, const std::vector<Index>& hs) {
  const Index o0 = T::next(hs[0]), o1 = T::next(hs[1]);
  const Index w0 = sd_[o0].twin, w1 = sd_[o1].twin, a = sd_[o0].tail, b = sd_[o1].tail;
  const Index f0 = T::face(hs[0]), f1 = T::face(hs[1]);
  if (a == b || a == v || b == v || f0 == f1 || w0 < 0 || w1 < 0 || w0 == o1) return false;
  const Index g0 = T::face(w0), g1 = T::face(w1);
  if (g0 == f0 || g0 == f1 || g1 == f0 || g1 == f1) return false;
  auto has_v = [&](Index g) {
    return sd_[3 * g].tail == v || sd_[3 * g + 1].tail == v || sd_[3 * g + 2].tail == v;
  };
  const double l0 = sd_[o0].len, l1 = sd_[o1].len;
  if (!(has_v(g0) && has_v(g1)) && std::abs(l0 - l1) > 0.01 * std::max(l0, l1)) return false;
  // the length nearest the mean that the four faces' other sides (x, y) allow: |x − y| < L < x + y
  double lo = 0.0, hi = HUGE_VAL;
  for (Index side : {o0, o1, w0, w1}) {
    if (side == w1 && g1 == g0) continue;  // two sides of one face: its third below 2L (checked)
    const double x = sd_[T::next(side)].len, y = sd_[T::prev(side)].len;
    lo = std::max(lo, std::abs(x - y) * (1.0 + 1e-6) + 4.0 * kMargin * (x + y));
    hi = std::min(hi, (x + y) * (1.0 - 1e-6));
  }
  if (!(lo < hi)) return false;
  const double mean = std::clamp(0.5 * (l0 + l1), lo, hi);
  const double m0 = sd_[w0].len, m1 = sd_[w1].len;  // (= l0, l1 unless glued oddly)
  for (Index side : {o0, w0, o1, w1}) set_length(side, mean);
  auto good = [&](Index g) {  // (with what earlier digons of v changed)
    return good_triangle(sd_[3 * g].len, sd_[3 * g + 1].len, sd_[3 * g + 2].len);
  };
  if (!good(g0) || !good(g1) || !good(f0) || !good(f1)) {
    set_length(o0, l0), set_length(w0, m0), set_length(o1, l1), set_length(w1, m1);
    return false;
  }
  digons_.push_back({o0, o1, l0, l1});
  return true;
}

// Puts back the lengths equalize_digon() changed (v was not removed), unless a flip was made
// since (its new side was measured with them: the equalized metric stays, every face valid).
// The digons' own faces are never flipped, so their sides still name the edges.
void Simplifier::undo_digons(std::size_t flips_before) {
  if (report_.flips != flips_before) {
    digons_.clear();
    return;
  }
  for (auto it = digons_.rbegin(); it != digons_.rend(); ++it) {
    set_length(it->o0, it->l0), set_length(sd_[it->o0].twin, it->l0);
    set_length(it->o1, it->l1), set_length(sd_[it->o1].twin, it->l1);
  }
  digons_.clear();
}

// The faces of v's fans (from its representatives, which must be exact). False if a walk fails.
bool Simplifier::faces_of(Index v, std::vector<Index>& faces) {
  faces.clear();
  std::vector<Index>& w = hs_;
  for (Index k = rep_start_[v]; k < rep_end_[v]; ++k) {
    bool b = false;
    if (!fan(rep_[k], w, b)) return false;
    for (Index h : w) faces.push_back(T::face(h));
  }
  std::sort(faces.begin(), faces.end());
  faces.erase(std::unique(faces.begin(), faces.end()), faces.end());
  return true;
}

// v's fan representatives walked again from its corners in `faces` (all faces with v as a
// corner: a flip of a self-edge at v, which can join or split its fans, keeps that set). False
// (nothing changed) if a walk leaves the set or there are more fans than v has room for.
bool Simplifier::rebuild_reps(Index v, const std::vector<Index>& faces) {
  std::vector<Index>& all = sorted_;
  all.clear();
  for (Index f : faces) {
    for (int s = 0; s < 3; ++s) {
      if (sd_[3 * f + s].tail == v) all.push_back(3 * f + s);
    }
  }
  std::vector<Index>& w = hs_;
  std::vector<Index> reps;
  std::vector<char> seen(all.size(), 0);
  for (std::size_t i = 0; i < all.size(); ++i) {
    if (seen[i]) continue;
    bool b = false;
    if (!fan(all[i], w, b)) return false;
    for (Index h : w) {
      const auto it = std::lower_bound(all.begin(), all.end(), h);
      if (it == all.end() || *it != h) return false;
      seen[it - all.begin()] = 1;
    }
    reps.push_back(w.front());
  }
  if (Index(reps.size()) > rep_start_[v + 1] - rep_start_[v]) return false;
  std::copy(reps.begin(), reps.end(), rep_.begin() + rep_start_[v]);
  rep_end_[v] = rep_start_[v] + Index(reps.size());
  return true;
}

// Flips the self-edge h (v → v) away (a strictly convex diamond with two other distinct
// corners) and rebuilds v's representatives; flipped back if they cannot be rebuilt.
bool Simplifier::flip_loop(Index v, Index h) {
  std::vector<Index> faces;
  if (!faces_of(v, faces)) return false;
  const Index f = T::face(h);
  if (!flip(h, /*loop=*/true)) return false;
  if (rebuild_reps(v, faces)) return true;
  if (!flip(3 * f + 2, /*loop=*/false) || !rebuild_reps(v, faces)) {  // back to the self-edge
    throw Error("simplify: internal: a self-edge flip could not be undone");
  }
  return false;
}

// Flips away the self-edges at v that can be (they put v on its own link: no removal).
bool Simplifier::flip_loops(Index v) {
  bool any = false;
  for (int round = 0; round < 8; ++round) {
    Index loop = kInvalidIndex;
    std::vector<Index>& w = ends_;
    for (Index k = rep_start_[v]; k < rep_end_[v] && loop == kInvalidIndex; ++k) {
      bool b = false;
      if (!fan(rep_[k], w, b)) return any;
      for (Index h : w) {
        if (head(h) == v && !tried_.count(h)) loop = h;
      }
    }
    if (loop == kInvalidIndex) return any;
    tried_.insert(loop);
    any = flip_loop(v, loop) || any;
  }
  return any;
}

// Readies every fan of v (plan_fans), removes them. False (after a Delaunay repair of what the
// flips changed) when v cannot be removed now.
bool Simplifier::try_remove(Index v) {
  tried_.clear();
  flip_loops(v);
  const Index n_fans = rep_end_[v] - rep_start_[v];
  if (n_fans == 0 || (comp_closed_[comp_[v]] && comp_vertices_[comp_[v]] <= 4)) return false;
  std::vector<std::vector<Index>>& fans = fans_;
  if (Index(fans.size()) < n_fans) fans.resize(n_fans);
  for (Index k = 0; k < n_fans; ++k) fans[k].clear();
  std::vector<char>& kind = kind_;  // per fan: 0 flipped down, 1 flattened, 2 a pillow
  kind.assign(n_fans, 0);
  std::vector<char>& bnd = bnd_;
  bnd.assign(n_fans, 0);
  Index home = kInvalidIndex;  // the fan whose coarse face v goes to: the first not a pillow
  digons_.clear();
  const std::size_t flips_before = report_.flips;
  const bool ok = plan_fans(v, n_fans, home);
  std::vector<Index>& stack = stack_;
  stack.clear();
  if (!ok) {
    undo_digons(flips_before);
    for (Index k = 0; k < n_fans; ++k) {
      for (Index h : fans[k]) stack.push_back(T::next(h));
    }
    delaunay_repair(stack);
    return false;
  }
  std::vector<Index>& pillow_points = pillow_points_;
  pillow_points.clear();
  for (Index k = 0; k < n_fans; ++k) {
    if (kind[k] == 2) {
      remove_pillow(fans[k], pillow_points);
    } else if (kind[k] == 1) {
      remove_polygon(v, fans[k], k == home, stack);
    } else if (bnd[k]) {
      const Index w = sd_[T::next(fans[k][0])].twin;
      remove_ear(v, fans[k][0], k == home);
      const Index g = T::face(w);
      for (int s = 0; s < 3; ++s) stack.push_back(3 * g + s);
      ++report_.boundary_removals;
    } else if (fans[k].size() == 2) {
      const Index w = sd_[T::next(fans[k][0])].twin;
      remove_degree_two(v, fans[k], k == home);
      for (int s = 0; s < 3; ++s) stack.push_back(3 * T::face(w) + s);
    } else {
      remove_interior(v, fans[k], k == home);
      const Index f0 = T::face(fans[k][0]);
      for (int s = 0; s < 3; ++s) stack.push_back(3 * f0 + s);
    }
  }
  if (home == kInvalidIndex) {  // only pillows: v goes to the corner of a neighbour's fan
    const Index h = rep_[rep_start_[keeper_]];  // (plan_pillows(): it keeps a fan)
    Eigen::Vector3d e = Eigen::Vector3d::Zero();
    e[T::side(h)] = 1.0;
    move_point(v, T::face(h), e);
  }
  for (Index p : pillow_points) move_point(p, pt_face_[v], pt_bary_[v]);  // where v went
  auto retire = [&](Index u) {
    vertex_alive_[u] = 0;
    --comp_vertices_[comp_[u]];
    --alive_count_;
    ++report_.removals;
  };
  for (Index u : orphans_) {  // corners of v's pillows left without a face: gone with them
    move_point(u, pt_face_[v], pt_bary_[v]);
    retire(u);
  }
  retire(v);
  delaunay_repair(stack);
  return true;
}

// A pillow: a closed fan of v that is a whole closed surface of its own (every outer side glued
// to another outer side of the fan; v not on its link), joined to the rest only at pinch
// points. Its simplest form is two faces (v, a, b), (v, b, a) glued along all three sides (an
// isolated triangle of a point cloud's local triangulations, zipped to its back); larger ones
// (links a, b, a, b, …) are a few such triangles glued around their edges.
bool Simplifier::is_pillow(Index v, const std::vector<Index>& hs) const {
  if (hs.size() < 2 || hs.size() > (multiplicity_ > 1 ? 64 : 2)) return false;  // (D-345)
  for (Index h : hs) {
    const Index o = T::next(h), w = sd_[o].twin;
    if (sd_[o].tail == v || head(o) == v || sd_[o].tail == head(o) || w < 0) return false;
    bool inside = false;
    for (Index x : hs) inside = inside || (w == T::next(x) && T::face(x) != T::face(h));
    if (!inside) return false;
  }
  return true;
}

// Checks v's pillows (kind 2): their corners other than v whose every fan lies in them die with
// them (orphans_: removed too, they go where v goes); keeper_: a corner that keeps a fan (where
// v goes when it has only pillows), or kInvalidIndex. False when v would have nowhere to go (only
// pillows, no corner keeping a fan: a component of its own) or the orphans would take the count
// below the target; on a manifold input (multiplicity 1) also when there are orphans or v has
// only pillows (as before D-345).
bool Simplifier::plan_pillows(const std::vector<std::vector<Index>>& fans, Index n_fans,
                              bool has_home) {
  std::vector<Index>& ends = ends_;
  std::vector<Index>& faces = sorted_;
  ends.clear();
  faces.clear();
  orphans_.clear();
  keeper_ = kInvalidIndex;
  for (Index k = 0; k < n_fans; ++k) {
    if (kind_[k] != 2) continue;
    for (Index h : fans[k]) ends.push_back(head(h)), faces.push_back(T::face(h));
  }
  std::sort(ends.begin(), ends.end());
  ends.erase(std::unique(ends.begin(), ends.end()), ends.end());
  std::sort(faces.begin(), faces.end());
  for (Index u : ends) {
    Index inside = 0;
    for (Index r = rep_start_[u]; r < rep_end_[u]; ++r) {
      inside += std::binary_search(faces.begin(), faces.end(), T::face(rep_[r]));
    }
    if (inside >= rep_end_[u] - rep_start_[u]) {
      // on a manifold input a pillow is what is left of a real piece (an hourglass's bulb
      // coarsened to three vertices): its corners keep it
      if (multiplicity_ == 1) return false;
      orphans_.push_back(u);
    } else if (keeper_ == kInvalidIndex) {
      keeper_ = u;
    }
  }
  return (has_home || (keeper_ != kInvalidIndex && multiplicity_ > 1)) &&
         alive_count_ - 1 - Index(orphans_.size()) >= target_;
}

// Deletes the pillow hs of v: its faces die, its other corners lose their fans in it; the points
// inside it are appended to `points` (they go where v goes).
void Simplifier::remove_pillow(const std::vector<Index>& hs, std::vector<Index>& points) {
  auto in_pillow = [&](Index f) {
    for (Index h : hs) {
      if (T::face(h) == f) return true;
    }
    return false;
  };
  for (Index h : hs) {
    const Index u = head(h);
    touched_.push_back(u);
    for (Index k = rep_start_[u]; k < rep_end_[u];) {
      if (in_pillow(T::face(rep_[k]))) {
        rep_[k] = rep_[--rep_end_[u]];
      } else {
        ++k;
      }
    }
  }
  for (Index h : hs) {
    const Index f = T::face(h);
    points.insert(points.end(), pts_[f].begin(), pts_[f].end());
    pts_[f].clear();
    face_alive_[f] = 0;
  }
  ++report_.pillows;
}

// Two passes: in the first a single fan below 3π is only flipped to degree 3 (an ear, zipped
// faces), so manifold inputs that reach their target that way keep their metric; if the
// target is missed, the second may flatten any closed fan (simplify.h).
void Simplifier::run(Index target, const ProgressCallback& on_progress) {
  std::vector<Index>& stack = stack_;
  for (Index h = 0; h < Index(sd_.size()); ++h) {
    if (sd_[h].twin > h) stack.push_back(h);
  }
  delaunay_repair(stack);
  target_ = target;
  const Index wanted = std::max<Index>(alive_count_ - target, 0);
  ProgressMeter meter(on_progress, "simplify", std::max<Index>(wanted, 1));
  for (int pass = 0; pass < 2 && alive_count_ > target; ++pass) {
    flatten_ = pass == 1;
    drain(meter);
  }
  report_.stuck = std::max<Index>(alive_count_ - target, 0);
  meter.finish();
}

// Lazy greedy: a vertex whose star changed is marked dirty, and its cost is recomputed (and
// the vertex queued again) only when it comes out of the queue; a vertex not queued (failed, or
// of infinite cost) is queued again when its star changes. The queue orders by cost bucket, then
// by vertex id (queue_key()): within a bucket the removals sweep the vertices in memory order.
void Simplifier::drain(ProgressMeter& meter) {
  touched_.clear();
  BucketQueue queue;
  std::vector<char> queued(nv_, 0), dirty(nv_, 0);
  for (Index v = 0; v < nv_; ++v) {
    if (!vertex_alive_[v]) continue;
    const double c = cost(v);
    if (c < HUGE_VAL) queue.push(queue_key(c, v)), queued[v] = 1;
  }
  while (alive_count_ > target_ && !queue.empty()) {
    const Index v = Index(queue.pop() & 0xffffffffu);
    queued[v] = 0;
    if (!vertex_alive_[v]) continue;
    if (dirty[v]) {
      dirty[v] = 0;
      const double c = cost(v);
      if (c < HUGE_VAL) queue.push(queue_key(c, v)), queued[v] = 1;
      continue;
    }
    touched_.clear();
    if (!try_remove(v)) continue;
    meter.update(report_.removals);
    // each vertex once: a duplicate would mark the vertex just queued dirty, a second cost
    std::sort(touched_.begin(), touched_.end());
    touched_.erase(std::unique(touched_.begin(), touched_.end()), touched_.end());
    for (Index u : touched_) {
      if (!vertex_alive_[u]) continue;
      if (queued[u]) {
        dirty[u] = 1;
      } else {
        const double c = cost(u);
        if (c < HUGE_VAL) queue.push(queue_key(c, u)), queued[u] = 1, dirty[u] = 0;
      }
    }
  }
}

Simplification Simplifier::finish(const IntrinsicTriangulation& fine) {
  // what the removals needed and finish() does not, freed before the coarse triangulation and
  // the map are built beside the rest
  std::vector<double>().swap(angle_);
  std::vector<std::vector<Index>>().swap(pts_);
  Simplification s;
  const Index nf = Index(face_alive_.size());
  std::vector<Index> face_id(nf, kInvalidIndex), vertex_id(nv_, kInvalidIndex);
  Index nfc = 0;
  for (Index f = 0; f < nf; ++f) {
    if (face_alive_[f]) face_id[f] = nfc++;
  }
  for (Index v_in = 0; v_in < nv_; ++v_in) {  // coarse vertices in the input's id order
    const Index v = vertex_new_[v_in];
    if (!vertex_alive_[v]) continue;
    vertex_id[v] = Index(s.coarse_to_fine.size());
    s.coarse_to_fine.push_back(v_in);
  }
  std::vector<double> comp_area(comp_area0_.size(), 0.0);
  for (Index f = 0; f < nf; ++f) {
    if (face_alive_[f]) comp_area[comp_[sd_[3 * f].tail]] += area(f);
  }
  std::vector<double> scale(comp_area.size(), 1.0);
  for (std::size_t c = 0; c < comp_area.size(); ++c) {
    if (!(comp_area[c] > 0.0) || !(comp_area0_[c] > 0.0)) continue;
    scale[c] = std::sqrt(comp_area0_[c] / comp_area[c]);
    report_.area_change_before_rescale =
        std::max(report_.area_change_before_rescale, std::abs(comp_area[c] / comp_area0_[c] - 1.0));
  }
  std::vector<Index> tail(3 * std::size_t(nfc)), twin(3 * std::size_t(nfc));
  std::vector<double> len(3 * std::size_t(nfc));
  for (Index f = 0; f < nf; ++f) {
    if (!face_alive_[f]) continue;
    for (int k = 0; k < 3; ++k) {
      const Index h = 3 * f + k, hc = 3 * face_id[f] + k;
      tail[hc] = vertex_id[sd_[h].tail];
      twin[hc] = sd_[h].twin < 0 ? kInvalidIndex
                                 : 3 * face_id[T::face(sd_[h].twin)] + T::side(sd_[h].twin);
      len[hc] = sd_[h].len * scale[comp_[sd_[h].tail]];
    }
  }
  s.coarse = IntrinsicTriangulation::from_gluing(std::move(tail), std::move(twin), len,
                                                 Index(s.coarse_to_fine.size()), multiplicity_);
  s.fine_in_coarse.resize(nv_);
  for (Index v_in = 0; v_in < nv_; ++v_in) {
    const Index v = vertex_new_[v_in];
    SurfacePoint& sp = s.fine_in_coarse[v_in];
    if (!vertex_alive_[v]) {
      sp.face = face_id[pt_face_[v]];
      sp.bary = pt_bary_[v];
    } else if (rep_end_[v] > rep_start_[v]) {
      const Index h = rep_[rep_start_[v]];
      sp.face = face_id[T::face(h)];
      sp.bary = Eigen::Vector3d::Zero();
      sp.bary[T::side(h)] = 1.0;
    }
  }
  report_.vertices_before = nv_;
  report_.vertices_after = Index(s.coarse_to_fine.size());
  report_.area_before = total_area(fine);
  s.report = report_;
  return s;
}

}  // namespace

Simplification simplify(const IntrinsicTriangulation& fine, const SimplifyOptions& options) {
  options.validate();
  const Index nv = fine.n_vertices();
  Index target = options.target_vertices;
  if (target > 0 && target >= nv) {
    throw InvalidInput("simplify: target_vertices (" + std::to_string(target) +
                       ") must be below the input's vertex count (" + std::to_string(nv) + ")");
  }
  if (target == 0) {
    target = std::max<Index>(1, Index(std::llround(options.ratio * double(nv))));
  }
  Simplifier s(fine);
  s.run(target, options.on_progress);
  return s.finish(fine);
}

}  // namespace ifem::intrinsic
