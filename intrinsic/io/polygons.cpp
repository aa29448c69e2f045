// Triangulation of the polygons a reader collected (see PolygonSink and triangulate_polygons in
// detail.h). The rule: no new diagonal may coincide with an edge that already exists — a side of
// any polygon in the file or a diagonal chosen before — so no triangle repeats and no edge gets
// more faces than the polygons imply; among such choices short diagonals are preferred.
// Everything is linear in the number of polygon corners: bounded work per corner.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cstdint>
#include <limits>
#include <vector>

#include "intrinsic/io/detail.h"

namespace ifem::io::detail {
namespace {

/// Polygons up to this many corners are ear-clipped (quadratic in the corner count, so bounded
/// work per corner); larger ones become a fan whose apex avoids collisions.
constexpr std::size_t kMaxEarClipCorners = 32;
/// Apexes a large polygon's fan tries before settling for the one with the fewest collisions.
constexpr std::size_t kFanApexTries = 4;

/// Open-addressing hash set of undirected vertex pairs (64-bit keys).
class EdgeSet {
 public:
  explicit EdgeSet(std::size_t expected) { rehash(capacity_for(expected)); }

  static std::uint64_t key(Index a, Index b) {
    if (a > b) std::swap(a, b);
    return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(a)) << 32) |
           static_cast<std::uint32_t>(b);
  }
  bool contains(Index a, Index b) const {
    const std::uint64_t k = key(a, b);
    for (std::size_t i = slot(k);; i = (i + 1) & mask_) {
      if (slots_[i] == k) return true;
      if (slots_[i] == kEmpty) return false;
    }
  }
  void insert(Index a, Index b) {
    if (2 * (size_ + 1) > slots_.size()) rehash(2 * slots_.size());
    if (place(key(a, b))) ++size_;
  }

 private:
  static constexpr std::uint64_t kEmpty = ~std::uint64_t{0};  // no pair of Index ≥ 0 maps here

  static std::size_t capacity_for(std::size_t expected) {
    std::size_t c = 16;
    while (c < 2 * expected) c *= 2;
    return c;
  }
  std::size_t slot(std::uint64_t k) const {
    return static_cast<std::size_t>((k * 0x9E3779B97F4A7C15ull) >> 32) & mask_;
  }
  /// Stores `k`; false when it was already there.
  bool place(std::uint64_t k) {
    std::size_t i = slot(k);
    while (slots_[i] != kEmpty) {
      if (slots_[i] == k) return false;
      i = (i + 1) & mask_;
    }
    slots_[i] = k;
    return true;
  }
  void rehash(std::size_t capacity) {
    std::vector<std::uint64_t> old(capacity, kEmpty);
    old.swap(slots_);
    mask_ = capacity - 1;
    for (std::uint64_t k : old) {
      if (k != kEmpty) place(k);
    }
  }
  std::vector<std::uint64_t> slots_;
  std::size_t mask_ = 0;
  std::size_t size_ = 0;
};

/// The corners of the polygon the sink stored as the fan triangles [begin, end): (v0, v1, v2),
/// (v0, v2, v3), ... → v0, v1, ..., v(n−1).
void polygon_corners(const std::vector<Triangle>& t, std::size_t begin, std::size_t end,
                     std::vector<Index>& corners) {
  corners.clear();
  corners.push_back(t[begin][0]);
  for (std::size_t k = begin; k < end; ++k) corners.push_back(t[k][1]);
  corners.push_back(t[end - 1][2]);
}

/// Shared state of one triangulation pass.
struct Pass {
  const Positions& positions;
  EdgeSet edges;
  std::vector<Index> stamp;  ///< per vertex: last polygon (+1) that visited it, to find repeats
  std::vector<Index> corners;

  Eigen::Vector3d at(Index v) const { return positions.row(v).transpose(); }
};

/// An ear's rank: collisions first, then geometry (a reflex ear or one holding another corner),
/// then the squared length of the diagonal it closes. Lower is better.
struct EarRank {
  bool collides = true;
  bool bad_shape = true;
  double length2 = std::numeric_limits<double>::infinity();
  bool operator<(const EarRank& o) const {
    if (collides != o.collides) return !collides;
    if (bad_shape != o.bad_shape) return !bad_shape;
    return length2 < o.length2;
  }
};

/// Ear clipping of a small polygon: repeatedly cuts the best-ranked ear (ties: the earliest
/// corner after v0, so a square keeps the fan from v0). Writes n − 2 triangles to `out`.
class EarClipper {
 public:
  EarClipper(Pass& pass, const std::vector<Index>& v) : pass_(pass), v_(v), n_(v.size()) {
    Eigen::Vector3d normal = Eigen::Vector3d::Zero();  // Newell's normal
    for (std::size_t i = 0; i < n_; ++i) {
      normal += pass_.at(v_[i]).cross(pass_.at(v_[(i + 1) % n_]));
    }
    normal_ = normal;
    for (std::size_t i = 0; i < n_; ++i) {
      prev_[i] = (i + n_ - 1) % n_;
      next_[i] = (i + 1) % n_;
    }
    for (std::size_t i = 0; i < n_; ++i) rank_[i] = rank(i);
  }

  void run(Triangle* out) {
    std::array<bool, kMaxEarClipCorners> removed{};
    for (std::size_t left = n_; left > 3; --left) {
      std::size_t best = n_;
      for (std::size_t k = 1; k <= n_; ++k) {
        const std::size_t i = k % n_;
        if (!removed[i] && (best == n_ || rank_[i] < rank_[best])) best = i;
      }
      const std::size_t p = prev_[best];
      const std::size_t q = next_[best];
      *out++ = {v_[p], v_[best], v_[q]};
      pass_.edges.insert(v_[p], v_[q]);
      removed[best] = true;
      next_[p] = q;
      prev_[q] = p;
      rank_[p] = rank(p);
      rank_[q] = rank(q);
    }
    std::size_t first = 0;
    while (removed[first]) ++first;
    *out = {v_[first], v_[next_[first]], v_[next_[next_[first]]]};
  }

 private:
  /// Whether corner c lies on the inner side of the directed side a→b (about the normal).
  bool left_of(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c) const {
    return (b - a).cross(c - a).dot(normal_) >= 0;
  }
  EarRank rank(std::size_t i) const {
    const std::size_t p = prev_[i];
    const std::size_t q = next_[i];
    const Eigen::Vector3d a = pass_.at(v_[p]);
    const Eigen::Vector3d b = pass_.at(v_[i]);
    const Eigen::Vector3d c = pass_.at(v_[q]);
    EarRank r;
    r.collides = pass_.edges.contains(v_[p], v_[q]);
    r.length2 = (c - a).squaredNorm();
    r.bad_shape = (b - a).cross(c - b).dot(normal_) <= 0;
    for (std::size_t j = next_[q]; !r.bad_shape && j != p; j = next_[j]) {
      const Eigen::Vector3d x = pass_.at(v_[j]);
      r.bad_shape = left_of(a, b, x) && left_of(b, c, x) && left_of(c, a, x);
    }
    return r;
  }

  Pass& pass_;
  const std::vector<Index>& v_;
  std::size_t n_;
  Eigen::Vector3d normal_;
  std::array<std::size_t, kMaxEarClipCorners> prev_{}, next_{};
  std::array<EarRank, kMaxEarClipCorners> rank_{};
};

/// Diagonals of the fan from corner `apex` that already exist, counting up to `stop`.
std::size_t fan_collisions(const Pass& pass, const std::vector<Index>& v, std::size_t apex,
                           std::size_t stop) {
  const std::size_t n = v.size();
  std::size_t hits = 0;
  for (std::size_t k = 2; k + 1 < n && hits < stop; ++k) {
    hits += pass.edges.contains(v[apex], v[(apex + k) % n]) ? 1 : 0;
  }
  return hits;
}

/// A large polygon as a fan: tries a few spread-out apexes (v0 first) and takes the first whose
/// diagonals are all new, else the one with the fewest collisions. O(n) per try.
void fan(Pass& pass, const std::vector<Index>& v, Triangle* out) {
  const std::size_t n = v.size();
  std::size_t apex = 0;
  std::size_t fewest = std::numeric_limits<std::size_t>::max();
  for (std::size_t t = 0; t < kFanApexTries && fewest > 0; ++t) {
    const std::size_t candidate = t * n / kFanApexTries;
    const std::size_t hits = fan_collisions(pass, v, candidate, fewest);
    if (hits < fewest) {
      fewest = hits;
      apex = candidate;
    }
  }
  for (std::size_t k = 1; k + 1 < n; ++k) {
    const Index b = v[(apex + k) % n];
    const Index c = v[(apex + k + 1) % n];
    *out++ = {v[apex], b, c};
    if (k + 2 < n) pass.edges.insert(v[apex], c);
  }
}

/// True when the polygon repeats a vertex (such polygons keep their fan).
bool repeats_vertex(Pass& pass, const std::vector<Index>& v, Index polygon) {
  bool repeated = false;
  for (Index x : v) {
    repeated = repeated || pass.stamp[x] == polygon + 1;
    pass.stamp[x] = polygon + 1;
  }
  return repeated;
}

/// Calls f(begin, end) for each polygon's run of triangles.
template <class F>
void for_each_polygon(const SurfaceInput& s, F&& f) {
  const std::size_t n = s.triangles.size();
  for (std::size_t begin = 0, end = 0; begin < n; begin = end) {
    end = begin + 1;
    while (end < n && s.triangle_polygon[end] == s.triangle_polygon[begin]) ++end;
    f(begin, end);
  }
}

/// The sides of every polygon whose two ends both belong to some non-triangle polygon (only such
/// pairs can ever be a diagonal).
void insert_sides(const SurfaceInput& s, const std::vector<char>& in_polygon, Pass& pass) {
  for_each_polygon(s, [&](std::size_t begin, std::size_t end) {
    polygon_corners(s.triangles, begin, end, pass.corners);
    const std::vector<Index>& v = pass.corners;
    for (std::size_t i = 0; i < v.size(); ++i) {
      const Index a = v[i];
      const Index b = v[(i + 1) % v.size()];
      if (in_polygon[a] && in_polygon[b] && a != b) pass.edges.insert(a, b);
    }
  });
}

}  // namespace

void triangulate_polygons(SurfaceInput& s) {
  if (s.n_non_triangles == 0) return;
  const auto n_vertices = static_cast<std::size_t>(s.positions.rows());
  std::vector<char> in_polygon(n_vertices, 0);
  std::size_t corners = 0;
  for_each_polygon(s, [&](std::size_t begin, std::size_t end) {
    if (end - begin < 2) return;
    corners += end - begin + 2;
    for (std::size_t k = begin; k < end; ++k) {
      for (Index x : s.triangles[k]) in_polygon[x] = 1;
    }
  });
  Pass pass{s.positions, EdgeSet(2 * corners), std::vector<Index>(n_vertices, 0), {}};
  insert_sides(s, in_polygon, pass);
  for_each_polygon(s, [&](std::size_t begin, std::size_t end) {
    if (end - begin < 2) return;
    polygon_corners(s.triangles, begin, end, pass.corners);
    if (repeats_vertex(pass, pass.corners, s.triangle_polygon[begin])) return;
    Triangle* out = s.triangles.data() + begin;
    if (pass.corners.size() <= kMaxEarClipCorners) {
      EarClipper(pass, pass.corners).run(out);
    } else {
      fan(pass, pass.corners, out);
    }
  });
}

}  // namespace ifem::io::detail
