#include "solvers/recipes/isolines.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numeric>
#include <string>
#include <unordered_map>
#include <utility>

#include "intrinsic/core/errors.h"

namespace ifem::recipes {
namespace {

std::string number(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

// The range of f's finite values. @throws InvalidInput when there is none
std::pair<double, double> finite_range(const Eigen::VectorXd& f) {
  double lo = std::numeric_limits<double>::infinity();
  double hi = -lo;
  for (Eigen::Index v = 0; v < f.size(); ++v) {
    if (!std::isfinite(f[v])) continue;
    lo = std::min(lo, f[v]);
    hi = std::max(hi, f[v]);
  }
  if (!(lo <= hi)) throw InvalidInput("isolines: the field has no finite value");
  return {lo, hi};
}

void check_inputs(const Positions& positions, const std::vector<Triangle>& triangles,
                  const Eigen::VectorXd& f) {
  const Index nv = checked_index(std::size_t(positions.rows()), "isolines: vertices");
  if (f.size() != nv) {
    throw InvalidInput("isolines: the field has " + std::to_string(f.size()) +
                       " values, the mesh " + std::to_string(nv) + " vertices");
  }
  if (!positions.allFinite()) throw InvalidInput("isolines: a vertex position is not finite");
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    for (Index v : triangles[t]) {
      if (v < 0 || v >= nv) {
        throw InvalidInput("isolines: triangle " + std::to_string(t) + " has vertex id " +
                           std::to_string(v) + ", out of [0, " + std::to_string(nv) + ")");
      }
    }
  }
}

// The cut points and segments of one level, points numbered in the order triangles create them.
class LevelCut {
 public:
  LevelCut(const Positions& x, const std::vector<Triangle>& tris, const Eigen::VectorXd& f,
           double c)
      : x_(x), tris_(tris), f_(f), c_(c), nv_(std::uint64_t(x.rows())) {}

  // Triangle t's segment (min f < c ≤ max f over its corners, all finite), unless it has
  // zero length (both cuts at the same vertex).
  void cut(Index t) {
    const Triangle& tri = tris_[std::size_t(t)];
    bool up[3];
    for (int k = 0; k < 3; ++k) up[k] = f_[tri[k]] >= c_;
    // the corner alone on its side, and the two edges from it
    const int odd = up[0] == up[1] ? 2 : (up[0] == up[2] ? 1 : 0);
    const Index a = point(t, odd, (odd + 1) % 3, up[odd]);
    const Index b = point(t, odd, (odd + 2) % 3, up[odd]);
    if (a != b) segments_.push_back({std::min(a, b), std::max(a, b)});
  }

  std::vector<IsolinePoint>& points() { return points_; }
  std::vector<std::pair<Index, Index>>& segments() { return segments_; }

 private:
  // The cut on triangle t's edge between corners k and m (k on side `k_up`, m on the other).
  Index point(Index t, int k, int m, bool k_up) {
    const Triangle& tri = tris_[std::size_t(t)];
    const int kb = k_up ? m : k, ka = k_up ? k : m;  // corners below and above
    const Index below = tri[kb], above = tri[ka];
    const bool at_vertex = f_[above] == c_;
    const std::uint64_t key = at_vertex ? std::uint64_t(above) * nv_ + std::uint64_t(above)
                                        : std::uint64_t(below) * nv_ + std::uint64_t(above);
    const auto [it, fresh] = id_.try_emplace(key, Index(points_.size()));
    if (!fresh) return it->second;
    IsolinePoint p;
    p.face = t;
    if (at_vertex) {
      p.below = p.above = above;
      p.bary[ka] = 1.0;
      p.position = x_.row(above).transpose();
    } else {
      p.below = below;
      p.above = above;
      p.t = std::clamp((c_ - f_[below]) / (f_[above] - f_[below]), 0.0, 1.0);
      p.bary[kb] = 1.0 - p.t;
      p.bary[ka] = p.t;
      p.position = (1.0 - p.t) * x_.row(below).transpose() + p.t * x_.row(above).transpose();
    }
    points_.push_back(p);
    return it->second;
  }

  const Positions& x_;
  const std::vector<Triangle>& tris_;
  const Eigen::VectorXd& f_;
  const double c_;
  const std::uint64_t nv_;
  std::unordered_map<std::uint64_t, Index> id_;
  std::vector<IsolinePoint> points_;
  std::vector<std::pair<Index, Index>> segments_;
};

// Chains the segments (each once) into polylines: walks start at points of degree ≠ 2 (ends,
// branch points), then what is left is loops of degree-2 points.
class Chainer {
 public:
  Chainer(Index n_points, const std::vector<std::pair<Index, Index>>& segments)
      : seg_(segments), offset_(std::size_t(n_points) + 1, 0), used_(segments.size(), 0) {
    for (const auto& s : seg_) {
      ++offset_[std::size_t(s.first) + 1];
      ++offset_[std::size_t(s.second) + 1];
    }
    std::partial_sum(offset_.begin(), offset_.end(), offset_.begin());
    incident_.resize(2 * seg_.size());
    std::vector<Index> fill(offset_.begin(), offset_.end() - 1);
    for (std::size_t i = 0; i < seg_.size(); ++i) {
      incident_[std::size_t(fill[std::size_t(seg_[i].first)]++)] = Index(i);
      incident_[std::size_t(fill[std::size_t(seg_[i].second)]++)] = Index(i);
    }
  }

  // Each chain: point ids in order, and whether it closes.
  std::vector<std::pair<std::vector<Index>, bool>> chains() {
    std::vector<std::pair<std::vector<Index>, bool>> out;
    const Index n = Index(offset_.size()) - 1;
    for (int pass = 0; pass < 2; ++pass) {
      for (Index p = 0; p < n; ++p) {
        if ((degree(p) == 2) != (pass == 1)) continue;
        for (Index s = next_unused(p); s != kInvalidIndex; s = next_unused(p)) {
          out.push_back(walk(p, s));
        }
      }
    }
    return out;
  }

 private:
  Index degree(Index p) const { return offset_[std::size_t(p) + 1] - offset_[std::size_t(p)]; }

  Index next_unused(Index p) const {
    for (Index i = offset_[std::size_t(p)]; i < offset_[std::size_t(p) + 1]; ++i) {
      if (!used_[std::size_t(incident_[std::size_t(i)])]) return incident_[std::size_t(i)];
    }
    return kInvalidIndex;
  }

  std::pair<std::vector<Index>, bool> walk(Index start, Index s) {
    std::vector<Index> pts{start};
    Index cur = start;
    while (true) {
      used_[std::size_t(s)] = 1;
      const auto& e = seg_[std::size_t(s)];
      const Index next = e.first == cur ? e.second : e.first;
      if (next == start) return {pts, true};
      pts.push_back(next);
      if (degree(next) != 2) return {pts, false};
      s = next_unused(next);
      if (s == kInvalidIndex) return {pts, false};
      cur = next;
    }
  }

  const std::vector<std::pair<Index, Index>>& seg_;
  std::vector<Index> offset_;    // CSR: segments at point p are incident_[offset_[p] ..]
  std::vector<Index> incident_;  // segment ids
  std::vector<char> used_;
};

// The polylines of one level from its cut triangles (ascending).
void level_isolines(const Positions& x, const std::vector<Triangle>& tris, const Eigen::VectorXd& f,
                    double c, Index level, const std::vector<Index>& cut_triangles,
                    std::vector<Isoline>& out) {
  LevelCut cut(x, tris, f, c);
  for (Index t : cut_triangles) cut.cut(t);
  auto& segments = cut.segments();
  // an edge with both ends at c is cut by each triangle on it with its third corner below
  std::sort(segments.begin(), segments.end());
  segments.erase(std::unique(segments.begin(), segments.end()), segments.end());
  Chainer chainer(Index(cut.points().size()), segments);
  for (auto& [ids, closed] : chainer.chains()) {
    Isoline line;
    line.value = c;
    line.level = level;
    line.closed = closed;
    line.points.reserve(ids.size());
    for (Index i : ids) line.points.push_back(cut.points()[std::size_t(i)]);
    out.push_back(std::move(line));
  }
}

}  // namespace

std::vector<double> isoline_levels(const Eigen::VectorXd& f, Index count) {
  if (count < 1) {
    throw InvalidInput("isolines: the count of levels must be ≥ 1, got " + std::to_string(count));
  }
  const auto [lo, hi] = finite_range(f);
  std::vector<double> levels(std::size_t(count), 0.0);
  for (Index i = 0; i < count; ++i) {
    levels[std::size_t(i)] = lo + double(i + 1) * (hi - lo) / double(count + 1);
  }
  return levels;
}

std::vector<Isoline> isolines(const Positions& positions, const std::vector<Triangle>& triangles,
                              const Eigen::VectorXd& f, const std::vector<double>& values) {
  check_inputs(positions, triangles, f);
  const auto [lo, hi] = finite_range(f);
  for (std::size_t i = 0; i < values.size(); ++i) {
    if (!std::isfinite(values[i]) || values[i] < lo || values[i] > hi) {
      throw InvalidInput("isolines: value " + number(values[i]) +
                         " is outside the field's range [" + number(lo) + ", " + number(hi) + "]");
    }
  }
  // the levels in ascending order: a triangle is cut by those in (min f, max f]
  std::vector<Index> order(values.size());
  std::iota(order.begin(), order.end(), Index(0));
  std::sort(order.begin(), order.end(),
            [&](Index a, Index b) { return values[std::size_t(a)] < values[std::size_t(b)]; });
  std::vector<double> sorted(values.size());
  for (std::size_t i = 0; i < order.size(); ++i) sorted[i] = values[std::size_t(order[i])];
  std::vector<std::vector<Index>> cut(values.size());
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    const Triangle& tri = triangles[t];
    const double a = f[tri[0]], b = f[tri[1]], c = f[tri[2]];
    if (!std::isfinite(a) || !std::isfinite(b) || !std::isfinite(c)) continue;
    const double fmin = std::min({a, b, c}), fmax = std::max({a, b, c});
    const auto first = std::upper_bound(sorted.begin(), sorted.end(), fmin);
    const auto last = std::upper_bound(first, sorted.end(), fmax);
    for (auto it = first; it != last; ++it) {
      cut[std::size_t(order[std::size_t(it - sorted.begin())])].push_back(Index(t));
    }
  }
  std::vector<Isoline> out;
  for (std::size_t i = 0; i < values.size(); ++i) {
    level_isolines(positions, triangles, f, values[i], Index(i), cut[i], out);
  }
  return out;
}

}  // namespace ifem::recipes
