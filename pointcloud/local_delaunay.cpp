#include "pointcloud/local_delaunay.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace ifem::pointcloud {
namespace {

using Inverted = StarWorkspace::Point;

double cross(const Inverted& o, const Inverted& a, const Inverted& b) {
  return (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x);
}

// Lexicographic order of inverted points (x, then y, then index: the origin, −1, first).
struct LexLess {
  bool operator()(const Inverted& a, const Inverted& b) const {
    if (a.x != b.x) return a.x < b.x;
    if (a.y != b.y) return a.y < b.y;
    return a.index < b.index;
  }
};

// Andrew's monotone chain over n lexicographically sorted points p, counter-clockwise,
// collinear points dropped, into h (room for 2n points); returns the point count k, the last
// point repeating the first.
inline int monotone_chain(const Inverted* p, int n, Inverted* h) {
  int k = 0;
  for (int i = 0; i < n; ++i) {
    while (k >= 2 && cross(h[k - 2], h[k - 1], p[i]) <= 0.0) --k;
    h[k++] = p[i];
  }
  for (int i = n - 2, lower = k + 1; i >= 0; --i) {
    while (k >= lower && cross(h[k - 2], h[k - 1], p[i]) <= 0.0) --k;
    h[k++] = p[i];
  }
  return k;
}

// Inverts the finite points of q farther than min_relative_distance × r from the origin into
// w (origin first), where r is the largest finite |q|; returns r (0 when there is none).
double invert_points(const std::vector<Eigen::Vector2d>& q, double min_relative_distance,
                     std::vector<Inverted>& w) {
  double r = 0.0;
  for (const auto& p : q) {
    if (p.allFinite()) r = std::max(r, p.norm());
  }
  if (!(r > 0.0)) return r;
  // Inversion about the origin, scaled by r so coordinates stay O(1 / relative distance):
  // w = r q / |q|². The circle through 0, q_a, q_b maps to the line through w_a, w_b, and the
  // circle's inside to the far side of that line, so (0, q_a, q_b) is a Delaunay triangle iff
  // w_a w_b is an edge of the convex hull of {0} ∪ {w} with the origin inside.
  const double min_dist = min_relative_distance * r;
  w.clear();
  w.push_back({0.0, 0.0, -1});
  for (int j = 0; j < static_cast<int>(q.size()); ++j) {
    const Eigen::Vector2d& p = q[j];
    if (!p.allFinite()) continue;
    const double d = p.norm();
    if (!(d > min_dist)) continue;
    const double s = r / (d * d);
    w.push_back({p.x() * s, p.y() * s, j});
  }
  return r;
}

constexpr std::size_t kProbe = 10;

// Squared distance from the origin to the nearest edge line of the hull H of the origin and
// the first kProbe points of w, shrunk by a rounding margin; 0 when the origin is not strictly
// inside H (no filter possible).
double probe_inradius2(const std::vector<Inverted>& w) {
  Inverted sub[kProbe + 1], h[2 * kProbe + 2];
  std::copy(w.begin(), w.begin() + kProbe + 1, sub);  // w[0] is the origin
  std::sort(sub, sub + kProbe + 1, LexLess());
  const int m = monotone_chain(sub, static_cast<int>(kProbe) + 1, h) - 1;
  double rho2 = std::numeric_limits<double>::infinity();
  const Inverted o{0.0, 0.0, -1};
  for (int i = 0; i < m && m >= 3; ++i) {
    const Inverted& a = h[i];
    const Inverted& b = h[i + 1];
    const double c = cross(a, b, o);  // > 0: origin strictly left of a → b (inside)
    const double ex = b.x - a.x, ey = b.y - a.y;
    const double len2 = ex * ex + ey * ey;
    if (!(c > 0.0) || !(len2 > 0.0)) {
      rho2 = 0.0;  // origin on or outside H (or degenerate): no filter
      break;
    }
    rho2 = std::min(rho2, c * c / len2);
  }
  if (m < 3) rho2 = 0.0;
  return rho2 * (1.0 - 1e-6);  // margin for rounding: filtering fewer points is always safe
}

// Pre-filter (same result, less sorting): the hull H of the origin and the first few points
// (the nearest ones when q is sorted by distance: the largest |w|). If the origin is strictly
// inside H, at distance ρ from every edge line, then every w with |w| < ρ lies strictly
// inside H, hence strictly inside the full hull: not a hull vertex, never in a triangle. The
// lexicographically smallest point is always a hull vertex, so the chain below starts at the
// same point and returns the same triangles in the same order.
void drop_inner_points(std::vector<Inverted>& w) {
  if (w.size() <= 2 * kProbe) return;
  const double rho2 = probe_inradius2(w);
  if (rho2 > 0.0 && std::isfinite(rho2)) {
    std::size_t out_n = kProbe + 1;
    for (std::size_t j = kProbe + 1; j < w.size(); ++j) {
      if (w[j].x * w[j].x + w[j].y * w[j].y >= rho2) w[out_n++] = w[j];
    }
    w.resize(out_n);
  }
}

}  // namespace

int delaunay_star(const std::vector<Eigen::Vector2d>& q, std::vector<std::array<int, 2>>& out,
                  double min_relative_distance) {
  StarWorkspace ws;
  return delaunay_star(q, out, ws, min_relative_distance);
}

int delaunay_star(const std::vector<Eigen::Vector2d>& q, std::vector<std::array<int, 2>>& out,
                  StarWorkspace& ws, double min_relative_distance) {
  std::vector<Inverted>& w = ws.w;
  if (!(invert_points(q, min_relative_distance, w) > 0.0)) return 0;
  if (w.size() < 3) return 0;
  drop_inner_points(w);
  std::sort(w.begin(), w.end(), LexLess());
  // exact duplicates: keep the first (smallest index; the origin sorts first as index −1)
  w.erase(
      std::unique(w.begin(), w.end(),
                  [](const Inverted& a, const Inverted& b) { return a.x == b.x && a.y == b.y; }),
      w.end());
  const int n = static_cast<int>(w.size());
  if (n < 3) return 0;
  std::vector<Inverted>& hull = ws.hull;
  if (hull.size() < 2 * static_cast<std::size_t>(n)) hull.resize(2 * static_cast<std::size_t>(n));
  const int m = monotone_chain(w.data(), n, hull.data()) - 1;  // the last point repeats the first
  if (m < 3) return 0;                                         // all collinear
  int added = 0;
  for (int i = 0; i < m; ++i) {
    const Inverted& a = hull[i];
    const Inverted& b = hull[(i + 1) % m];
    if (a.index < 0 || b.index < 0) continue;  // an edge at the origin: centre on the boundary
    out.push_back({a.index, b.index});
    ++added;
  }
  return added;
}

}  // namespace ifem::pointcloud
