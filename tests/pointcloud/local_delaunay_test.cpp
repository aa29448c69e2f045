#include "pointcloud/local_delaunay.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <set>

#include "intrinsic/core/errors.h"
#include "pointcloud/knn.h"

namespace ifem::pointcloud {
namespace {

using Pairs = std::vector<std::array<int, 2>>;

// Brute force: (0, q_a, q_b) is a Delaunay triangle iff it is non-degenerate and no other point
// lies strictly inside its circumcircle.
std::set<std::array<int, 2>> brute_star(const std::vector<Eigen::Vector2d>& q) {
  std::set<std::array<int, 2>> out;
  const int n = static_cast<int>(q.size());
  for (int a = 0; a < n; ++a) {
    for (int b = 0; b < n; ++b) {
      const double det = q[a].x() * q[b].y() - q[a].y() * q[b].x();
      if (!(det > 1e-12)) continue;  // counter-clockwise only
      // circumcentre of 0, q_a, q_b
      const double la = q[a].squaredNorm(), lb = q[b].squaredNorm();
      const Eigen::Vector2d c((la * q[b].y() - lb * q[a].y()) / (2 * det),
                              (lb * q[a].x() - la * q[b].x()) / (2 * det));
      const double r2 = c.squaredNorm();
      bool empty = true;
      for (int j = 0; j < n && empty; ++j) {
        if (j != a && j != b && (q[j] - c).squaredNorm() < r2 * (1 - 1e-9)) empty = false;
      }
      if (empty) out.insert({a, b});
    }
  }
  return out;
}

TEST(LocalDelaunay, HexagonIsAClosedFan) {
  std::vector<Eigen::Vector2d> q;
  for (int i = 0; i < 6; ++i)
    q.emplace_back(std::cos(i * M_PI / 3 + 0.1), std::sin(i * M_PI / 3 + 0.1));
  q.emplace_back(5, 5);  // far away: not a Delaunay neighbour
  Pairs out;
  EXPECT_EQ(delaunay_star(q, out), 6);
  std::set<int> seen;
  for (const auto& ab : out) {
    EXPECT_EQ(ab[1], (ab[0] + 1) % 6);
    seen.insert(ab[0]);
  }
  EXPECT_EQ(seen.size(), 6u);
}

// Neighbourhoods sorted nearest first, as the pipeline gives them: the pre-filter (hull of the
// nearest points) drops most far points; the triangles must not change, nor their order
// (compared with the same points given far first, where the filter finds nothing to drop).
TEST(LocalDelaunay, SortedNeighbourhoodsMatchBruteForce) {
  std::mt19937 rng(11);
  std::normal_distribution<double> g(0.0, 1.0);
  for (int trial = 0; trial < 300; ++trial) {
    std::vector<Eigen::Vector2d> q;
    for (int j = 0; j < 21 + trial % 50; ++j) {
      Eigen::Vector2d x(g(rng), g(rng));
      if (trial % 4 == 0) x.x() = std::round(4 * x.x()) / 4;  // grid-like ties, cocircular
      if (trial % 4 == 0) x.y() = std::round(4 * x.y()) / 4;
      if (trial % 5 == 1) x.x() += 1.5;  // centre near the boundary: open star
      q.push_back(x);
    }
    std::sort(q.begin(), q.end(), [](const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
      return a.squaredNorm() != b.squaredNorm() ? a.squaredNorm() < b.squaredNorm()
             : a.x() != b.x()                   ? a.x() < b.x()
                                                : a.y() < b.y();
    });
    // no exact duplicates (they keep the smallest index, which the reversal below changes)
    q.erase(std::unique(q.begin(), q.end()), q.end());
    const int n = static_cast<int>(q.size());
    Pairs out;
    delaunay_star(q, out);
    const std::set<std::array<int, 2>> got(out.begin(), out.end());
    EXPECT_EQ(got.size(), out.size());
    // (the brute force keeps every triangle of a cocircular tie: skip it on the grid trials)
    if (trial % 4 != 0) {
      EXPECT_EQ(got, brute_star(q)) << "trial " << trial;
    }
    // reversed input order: nothing filtered; map the indices back and compare in order
    std::vector<Eigen::Vector2d> rev(q.rbegin(), q.rend());
    Pairs out_rev;
    delaunay_star(rev, out_rev);
    std::set<std::array<int, 2>> got_rev;
    for (const auto& ab : out_rev) got_rev.insert({n - 1 - ab[0], n - 1 - ab[1]});
    EXPECT_EQ(got_rev, got) << "trial " << trial;
  }
}

TEST(LocalDelaunay, MatchesBruteForce) {
  std::mt19937 rng(4);
  std::normal_distribution<double> g(0.0, 1.0);
  for (int trial = 0; trial < 200; ++trial) {
    std::vector<Eigen::Vector2d> q;
    const int n = 3 + trial % 30;
    for (int j = 0; j < n; ++j) q.emplace_back(g(rng) + (trial % 3 == 0 ? 2.0 : 0.0), g(rng));
    Pairs out;
    delaunay_star(q, out);
    const std::set<std::array<int, 2>> got(out.begin(), out.end());
    EXPECT_EQ(got.size(), out.size());
    EXPECT_EQ(got, brute_star(q)) << "trial " << trial;
  }
}

TEST(LocalDelaunay, DegenerateNeighbourhoods) {
  Pairs out;
  EXPECT_EQ(delaunay_star({}, out), 0);
  EXPECT_EQ(delaunay_star({{1, 0}}, out), 0);
  EXPECT_EQ(delaunay_star({{0, 0}, {0, 0}, {0, 0}}, out), 0);            // all at the centre
  EXPECT_EQ(delaunay_star({{1, 0}, {2, 0}, {-1, 0}, {-3, 0}}, out), 0);  // collinear
  EXPECT_EQ(delaunay_star({{1, 1}, {1, 1}, {1, 1}}, out), 0);            // one distinct neighbour
  EXPECT_TRUE(out.empty());
  // duplicates count once (smallest index), the centre's duplicates are ignored
  EXPECT_EQ(delaunay_star({{1, 0}, {0, 1}, {1, 0}, {0, 0}, {-1, -1}, {0, 1}}, out), 3);
  for (const auto& ab : out) {
    EXPECT_NE(ab[0], 2);
    EXPECT_NE(ab[1], 5);
    EXPECT_NE(ab[0], 3);
  }
  // centre on the boundary (all neighbours in a half-plane): an open fan
  out.clear();
  EXPECT_EQ(delaunay_star({{1, 0.01}, {0.7, 0.7}, {0, 1}, {-1, 0.02}}, out), 3);
  // NaN and inf are ignored, never propagated
  out.clear();
  const double nan = std::nan("");
  EXPECT_EQ(delaunay_star({{1, 0}, {0, 1}, {-1, -1}, {nan, 1}, {1e300 * 1e10, 0}}, out), 3);
  // huge and tiny scales give the same star
  std::vector<Eigen::Vector2d> q = {{1, 0.2}, {0.1, 1}, {-1, 0.3}, {-0.2, -1}, {0.8, -0.9}};
  Pairs a, b, c;
  delaunay_star(q, a);
  for (auto& x : q) x *= 1e-150;
  delaunay_star(q, b);
  for (auto& x : q) x *= 1e290;
  delaunay_star(q, c);
  EXPECT_EQ(a, b);
  EXPECT_EQ(a, c);
}

TEST(Knn, MatchesBruteForce) {
  std::mt19937 rng(2);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  Positions p(500, 3);
  for (Eigen::Index i = 0; i < p.rows(); ++i) p.row(i) << u(rng), u(rng), 6e5 + u(rng);
  const Neighbours nb = k_nearest(p, 12);
  ASSERT_EQ(nb.k, 12);
  for (Index i = 0; i < 500; ++i) {
    std::vector<std::pair<double, Index>> d;
    for (Index j = 0; j < 500; ++j) {
      if (j != i) d.emplace_back((p.row(i) - p.row(j)).squaredNorm(), j);
    }
    std::sort(d.begin(), d.end());
    for (int j = 0; j < 12; ++j) EXPECT_EQ(nb.of(i)[j], d[j].second) << i << " " << j;
  }
  EXPECT_EQ(k_nearest(p.topRows(3), 30).k, 2);
  EXPECT_EQ(k_nearest(p.topRows(1), 30).k, 0);
  EXPECT_THROW(k_nearest(p, 0), InvalidInput);
}

}  // namespace
}  // namespace ifem::pointcloud
