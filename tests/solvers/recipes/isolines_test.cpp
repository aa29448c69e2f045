// Isolines (solvers/recipes/isolines.h): every point on an edge the level crosses, with f
// interpolated there equal to the level; pieces as the topology says (sphere, torus, flat grid
// with boundary), vertices exactly at the level, bad input.
#include "solvers/recipes/isolines.h"

#include <gtest/gtest.h>

#include <cmath>
#include <set>

#include "intrinsic/core/errors.h"
#include "intrinsic/generators/mesh_generators.h"

namespace ifem {
namespace {

using intrinsic::TriangleMesh;
using recipes::Isoline;
using recipes::IsolinePoint;

// Standing torus: the ring (radius R) in the xz-plane, tube radius r; nu × nv vertices.
TriangleMesh standing_torus(int nu, int nv, double R, double r) {
  TriangleMesh m;
  m.positions.resize(nu * nv, 3);
  for (int i = 0; i < nu; ++i) {
    const double u = 2 * M_PI * i / nu;
    for (int j = 0; j < nv; ++j) {
      const double v = 2 * M_PI * j / nv;
      const double rho = R + r * std::cos(v);
      m.positions.row(i * nv + j) << rho * std::cos(u), r * std::sin(v), rho * std::sin(u);
    }
  }
  for (int i = 0; i < nu; ++i) {
    for (int j = 0; j < nv; ++j) {
      const Index a = i * nv + j, b = ((i + 1) % nu) * nv + j,
                  c = ((i + 1) % nu) * nv + (j + 1) % nv, d = i * nv + (j + 1) % nv;
      m.faces.push_back({a, b, c});
      m.faces.push_back({a, c, d});
    }
  }
  return m;
}

Eigen::VectorXd column(const TriangleMesh& m, int axis) { return m.positions.col(axis); }

// Every point: on an edge crossed by the level (or a vertex at it), f interpolated = c to
// 1e-12, the position and the surface point agree; consecutive points distinct.
void expect_on_level(const TriangleMesh& m, const Eigen::VectorXd& f, const Isoline& line) {
  const double c = line.value;
  ASSERT_GE(line.points.size(), 2u);
  for (std::size_t i = 0; i < line.points.size(); ++i) {
    const IsolinePoint& p = line.points[i];
    if (p.below == p.above) {
      EXPECT_EQ(f[p.above], c);
      EXPECT_EQ(p.t, 0.0);
    } else {
      EXPECT_LT(f[p.below], c);
      EXPECT_GT(f[p.above], c);
    }
    EXPECT_NEAR((1 - p.t) * f[p.below] + p.t * f[p.above], c, 1e-12);
    const Eigen::Vector3d x = (1 - p.t) * m.positions.row(p.below).transpose() +
                              p.t * m.positions.row(p.above).transpose();
    EXPECT_LT((x - p.position).norm(), 1e-14);
    ASSERT_GE(p.face, 0);
    Eigen::Vector3d y = Eigen::Vector3d::Zero();
    for (int k = 0; k < 3; ++k) {
      EXPECT_GE(p.bary[k], 0.0);
      y += p.bary[k] * m.positions.row(m.faces[std::size_t(p.face)][k]).transpose();
    }
    EXPECT_NEAR(p.bary.sum(), 1.0, 1e-15);
    EXPECT_LT((y - p.position).norm(), 1e-14);
    const IsolinePoint& q = line.points[(i + 1) % line.points.size()];
    if (i + 1 < line.points.size() || line.closed) {
      EXPECT_GT((q.position - p.position).norm(), 0.0) << "point " << i;
    }
  }
}

TEST(Isolines, DistanceOnSphereIsOneClosedLoopPerLevel) {
  for (int n : {6, 17}) {
    const TriangleMesh m = intrinsic::icosphere(n);
    Eigen::VectorXd f(m.positions.rows());  // geodesic distance from (0, 0, 1)
    for (Index v = 0; v < f.size(); ++v) f[v] = std::acos(std::clamp(m.positions(v, 2), -1.0, 1.0));
    const std::vector<double> levels = recipes::isoline_levels(f, 7);
    const std::vector<Isoline> lines = recipes::isolines(m.positions, m.faces, f, levels);
    ASSERT_EQ(lines.size(), 7u) << "n = " << n;
    for (std::size_t i = 0; i < lines.size(); ++i) {
      EXPECT_TRUE(lines[i].closed);
      EXPECT_EQ(lines[i].level, Index(i));
      EXPECT_EQ(lines[i].value, levels[i]);
      expect_on_level(m, f, lines[i]);
      // the loop is near the circle of geodesic radius c (chords: within the edge length)
      for (const IsolinePoint& p : lines[i].points) {
        EXPECT_NEAR(p.position.z(), std::cos(levels[i]), 2.0 / n);
      }
    }
  }
}

TEST(Isolines, TorusHeightLoopCounts) {
  const double R = 2.0, r = 0.75;
  const TriangleMesh m = standing_torus(48, 20, R, r);
  const Eigen::VectorXd z = column(m, 2);
  // one loop near the top and bottom, two between the saddles at ±(R − r)
  const std::vector<double> levels{2.5, 0.3, -0.9, -2.5};
  const std::vector<Isoline> lines = recipes::isolines(m.positions, m.faces, z, levels);
  std::vector<int> count(levels.size(), 0);
  for (const Isoline& l : lines) {
    EXPECT_TRUE(l.closed);
    expect_on_level(m, z, l);
    ++count[std::size_t(l.level)];
  }
  EXPECT_EQ(count, (std::vector<int>{1, 2, 2, 1}));
}

TEST(Isolines, SaddleVertexExactlyAtTheLevel) {
  const TriangleMesh m = standing_torus(48, 20, 2.0, 0.75);
  const Eigen::VectorXd z = column(m, 2);
  const Index saddle = 12 * 20 + 10;  // u = π/2, v = π: the inner top point, z = R − r
  ASSERT_NEAR(z[saddle], 1.25, 1e-12);
  const std::vector<Isoline> lines = recipes::isolines(m.positions, m.faces, z, {z[saddle]});
  // a figure eight: two loops through the saddle, each point once
  ASSERT_EQ(lines.size(), 2u);
  std::set<std::pair<Index, Index>> seen;
  for (const Isoline& l : lines) {
    EXPECT_TRUE(l.closed);
    expect_on_level(m, z, l);
    EXPECT_EQ(l.points.front().below, saddle);
    EXPECT_EQ(l.points.front().above, saddle);
    for (std::size_t i = 1; i < l.points.size(); ++i) {
      EXPECT_TRUE(seen.insert({l.points[i].below, l.points[i].above}).second);
    }
  }
}

TEST(Isolines, OpenCurvesEndOnTheBoundary) {
  const TriangleMesh m = intrinsic::grid(10, 8, 1.0, 1.0);
  Eigen::VectorXd f(m.positions.rows());
  for (Index v = 0; v < f.size(); ++v) f[v] = m.positions(v, 0) + 0.3 * m.positions(v, 1);
  auto on_boundary = [](const Eigen::Vector3d& x) {
    return std::min({x.x(), 1 - x.x(), x.y(), 1 - x.y()}) < 1e-14;
  };
  const std::vector<double> levels{0.05, 0.41, 0.777, 1.2};
  const std::vector<Isoline> lines = recipes::isolines(m.positions, m.faces, f, levels);
  ASSERT_EQ(lines.size(), levels.size());
  for (const Isoline& l : lines) {
    EXPECT_FALSE(l.closed);
    expect_on_level(m, f, l);
    EXPECT_TRUE(on_boundary(l.points.front().position));
    EXPECT_TRUE(on_boundary(l.points.back().position));
    for (std::size_t i = 1; i + 1 < l.points.size(); ++i) {
      EXPECT_FALSE(on_boundary(l.points[i].position)) << i;
    }
    // f is linear: the isoline is the exact straight line
    for (const IsolinePoint& p : l.points) {
      EXPECT_NEAR(p.position.x() + 0.3 * p.position.y(), l.value, 1e-14);
    }
  }
}

TEST(Isolines, ColumnOfVerticesAtTheLevelIsOneLineWithoutDuplicates) {
  for (bool alternate : {true, false}) {
    const TriangleMesh m = intrinsic::grid(8, 5, 1.0, 1.0, alternate);
    const Eigen::VectorXd x = column(m, 0);
    const std::vector<Isoline> lines = recipes::isolines(m.positions, m.faces, x, {0.5});
    ASSERT_EQ(lines.size(), 1u);
    EXPECT_FALSE(lines[0].closed);
    EXPECT_EQ(lines[0].points.size(), 6u);  // the 6 vertices at x = 0.5, each once
    for (const IsolinePoint& p : lines[0].points) EXPECT_EQ(p.below, p.above);
    expect_on_level(m, x, lines[0]);
    // the extreme levels: the max is the side x = 1 (its edges have a corner below on one
    // side), the min gives nothing (no corner below)
    const std::vector<Isoline> ends = recipes::isolines(m.positions, m.faces, x, {1.0, 0.0});
    ASSERT_EQ(ends.size(), 1u);
    EXPECT_EQ(ends[0].level, 0);
    EXPECT_EQ(ends[0].points.size(), 6u);
    expect_on_level(m, x, ends[0]);
  }
}

TEST(Isolines, UnreachableVerticesAreSkipped) {
  const TriangleMesh m = intrinsic::grid(6, 6, 1.0, 1.0);
  Eigen::VectorXd f = column(m, 0);
  for (Index v = 0; v < f.size(); ++v) {
    if (m.positions(v, 1) > 0.6) f[v] = std::numeric_limits<double>::infinity();
  }
  const std::vector<Isoline> lines = recipes::isolines(m.positions, m.faces, f, {0.55});
  ASSERT_EQ(lines.size(), 1u);
  expect_on_level(m, f, lines[0]);
  for (const IsolinePoint& p : lines[0].points) EXPECT_LE(p.position.y(), 0.6 + 1e-12);
}

TEST(Isolines, BadInput) {
  const TriangleMesh m = intrinsic::grid(3, 3);
  const Eigen::VectorXd x = column(m, 0);
  auto message = [&](const Eigen::VectorXd& f, std::vector<double> values,
                     std::vector<Triangle> faces) {
    try {
      recipes::isolines(m.positions, faces, f, values);
    } catch (const InvalidInput& e) {
      return std::string(e.what());
    }
    return std::string("no throw");
  };
  EXPECT_NE(message(x, {1.5}, m.faces).find("outside the field's range [0, 1]"), std::string::npos);
  EXPECT_NE(message(x, {-0.1}, m.faces).find("outside"), std::string::npos);
  EXPECT_NE(message(x, {NAN}, m.faces).find("outside"), std::string::npos);
  EXPECT_NE(message(x.head(5), {0.5}, m.faces).find("5 values"), std::string::npos);
  std::vector<Triangle> bad = m.faces;
  bad[2][1] = 99;
  EXPECT_NE(message(x, {0.5}, bad).find("out of [0, 16)"), std::string::npos);
  const Eigen::VectorXd none = Eigen::VectorXd::Constant(16, NAN);
  EXPECT_NE(message(none, {0.5}, m.faces).find("no finite value"), std::string::npos);
  EXPECT_THROW(recipes::isoline_levels(x, 0), InvalidInput);
  EXPECT_EQ(recipes::isoline_levels(x, 3), (std::vector<double>{0.25, 0.5, 0.75}));
}

}  // namespace
}  // namespace ifem
