// The point-cloud Laplacian's k, pinned on neighbourhoods known exactly. The cloud is a row of
// "flowers", far apart: each a centre and k petals around it (radii and angles perturbed so
// that no two distances tie), so that every point's k nearest neighbours are exactly the other
// k points of its flower. The flower's planar Delaunay triangulation is the fan about its
// centre: the centre's star has k triangles through all k petals, each petal's star the 2 fan
// triangles at it. A star built from k − 1 neighbours (or k + 1) changes every count below.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <vector>

#include "intrinsic/core/triangle_formulas.h"
#include "pointcloud/knn.h"
#include "pointcloud/pointcloud_laplacian.h"

namespace ifem::pointcloud {
namespace {

using intrinsic::kPi;

// `flowers` flowers of k + 1 points each (centre first, then petals in angular order), 100
// apart along x, each in a plane of its own (tilted about the x axis) so that the tangent
// planes are not all the same.
Positions flower_cloud(int k, int flowers) {
  Positions p(static_cast<Eigen::Index>(flowers) * (k + 1), 3);
  for (int f = 0; f < flowers; ++f) {
    const double tilt = 0.3 * f;
    const Eigen::Vector3d centre(100.0 * f, 0.0, 0.0);
    const Eigen::Vector3d u(1, 0, 0), v(0, std::cos(tilt), std::sin(tilt));
    const Eigen::Index c = static_cast<Eigen::Index>(f) * (k + 1);
    p.row(c) = centre.transpose();
    for (int j = 0; j < k; ++j) {
      // radius 1 + 0.003 j: petal k − 1 is the centre's k-th (farthest) neighbour
      const double r = 1.0 + 0.003 * j;
      const double a = 2 * kPi * j / k + 0.01 * std::sin(1.0 + j);
      p.row(c + 1 + j) = (centre + r * (std::cos(a) * u + std::sin(a) * v)).transpose();
    }
  }
  return p;
}

// The other k points of point i's flower.
std::set<Index> flower_of(Index i, int k) {
  const Index first = i / (k + 1) * (k + 1);
  std::set<Index> s;
  for (Index j = first; j < first + k + 1; ++j) {
    if (j != i) s.insert(j);
  }
  return s;
}

class ExactNeighbourhoods : public ::testing::TestWithParam<int> {};

// k_nearest returns each point's k nearest, nearest first, and exactly k of them.
TEST_P(ExactNeighbourhoods, KNearestIsTheFlower) {
  const int k = GetParam();
  const Positions p = flower_cloud(k, 4);
  const Neighbours nb = k_nearest(p, k);
  ASSERT_EQ(nb.k, k);
  ASSERT_EQ(nb.ids.size(), static_cast<std::size_t>(p.rows()) * k);
  for (Index i = 0; i < p.rows(); ++i) {
    const Index* n = nb.of(i);
    EXPECT_EQ(std::set<Index>(n, n + k), flower_of(i, k)) << "point " << i;
    for (int j = 1; j < k; ++j) {
      EXPECT_LT((p.row(n[j - 1]) - p.row(i)).norm(), (p.row(n[j]) - p.row(i)).norm())
          << "point " << i << ": neighbours not nearest first";
    }
  }
}

// local_triangulations on those neighbours: the centre's star is the fan through all k petals
// (k triangles), each petal's the 2 fan triangles at it, and no star uses a point outside the
// flower.
TEST_P(ExactNeighbourhoods, StarsUseExactlyTheKNeighbours) {
  const int k = GetParam();
  const int flowers = 4;
  const Positions p = flower_cloud(k, flowers);
  Report rep;
  const std::vector<Triangle> tris = local_triangulations(p, k_nearest(p, k), nullptr, &rep);
  EXPECT_EQ(rep.starless_points, 0);
  EXPECT_EQ(rep.local_triangles, Index(3 * k * flowers));
  ASSERT_EQ(tris.size(), static_cast<std::size_t>(3 * k * flowers));
  std::vector<std::set<Index>> star_vertices(static_cast<std::size_t>(p.rows()));
  std::vector<int> star_size(static_cast<std::size_t>(p.rows()), 0);
  for (const Triangle& t : tris) {
    ++star_size[t[0]];
    star_vertices[t[0]].insert(t[1]);
    star_vertices[t[0]].insert(t[2]);
  }
  for (Index i = 0; i < p.rows(); ++i) {
    const std::set<Index> flower = flower_of(i, k);
    const bool centre = i % (k + 1) == 0;
    EXPECT_EQ(star_size[i], centre ? k : 2) << "point " << i;
    if (centre) {
      EXPECT_EQ(star_vertices[i], flower) << "centre " << i << ": its star must use all k";
    } else {
      // the centre and the two petals beside it
      const Index first = i / (k + 1) * (k + 1);
      const Index j = i - first - 1;
      const std::set<Index> fan = {first, first + 1 + (j + 1) % k, first + 1 + (j + k - 1) % k};
      EXPECT_EQ(star_vertices[i], fan) << "petal " << i;
    }
  }
}

// The whole pipeline with PointCloudOptions::k = k reports k and glues exactly the fans: every
// distinct triangle found in all three stars of its corners.
TEST_P(ExactNeighbourhoods, PipelineUsesK) {
  const int k = GetParam();
  const int flowers = 4;
  const Positions p = flower_cloud(k, flowers);
  PointCloudOptions o;
  o.k = k;
  Report rep;
  const intrinsic::IntrinsicTriangulation tri = pointcloud_triangulation(p, o, nullptr, &rep);
  EXPECT_EQ(rep.k, k);
  EXPECT_EQ(rep.local_triangles, Index(3 * k * flowers));
  EXPECT_EQ(rep.distinct_triangles, Index(k * flowers));
  EXPECT_EQ(rep.triangles_in_stars[0], 0);
  EXPECT_EQ(rep.triangles_in_stars[1], 0);
  EXPECT_EQ(rep.triangles_in_stars[2], Index(k * flowers));
  EXPECT_EQ(rep.starless_points, 0);
  EXPECT_EQ(rep.isolated_points, 0);
  EXPECT_EQ(tri.n_vertices(), p.rows());
}

INSTANTIATE_TEST_SUITE_P(K, ExactNeighbourhoods, ::testing::Values(5, 6, 8, 12));

}  // namespace
}  // namespace ifem::pointcloud
