// The signed heat method (solvers/vector/signed_heat.h, solvers/recipes/signed_distance.h)
// against Euclidean and spherical distances: a circle and a broken circle on a flat square, the
// equator of a sphere, oriented points on a plane sampled as a point cloud and on a tufted mesh.
#include "solvers/recipes/signed_distance.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "intrinsic/core/errors.h"
#include "intrinsic/io/mesh_io.h"
#include "solvers/test_util.h"

namespace ifem {
namespace {

using intrinsic::kPi;
using solvers::CurveCondition;

// [−1, 1]² as an n×n grid.
intrinsic::TriangleMesh square(int n) {
  intrinsic::TriangleMesh m = intrinsic::grid(n, n, 2.0, 2.0);
  m.positions.col(0).array() -= 1.0;
  m.positions.col(1).array() -= 1.0;
  return m;
}

Index nearest(const intrinsic::TriangleMesh& m, const Eigen::Vector3d& p) {
  Index best = 0;
  for (Index v = 1; v < m.positions.rows(); ++v) {
    if ((m.positions.row(v).transpose() - p).norm() <
        (m.positions.row(best).transpose() - p).norm()) {
      best = v;
    }
  }
  return best;
}

// The vertices nearest to k points of the circle of radius r, counter-clockwise, over the
// fraction `arc` of the turn.
std::vector<Index> circle_vertices(const intrinsic::TriangleMesh& m, double r, int k, double arc) {
  std::vector<Index> out;
  for (int i = 0; i < k; ++i) {
    const double a = 2.0 * kPi * arc * i / (arc < 1.0 ? k - 1 : k);
    const Index v = nearest(m, {r * std::cos(a), r * std::sin(a), 0.0});
    if (out.empty() || out.back() != v) out.push_back(v);
  }
  return out;
}

double segment_distance(const Eigen::Vector2d& p, const Eigen::Vector2d& a,
                        const Eigen::Vector2d& b) {
  const Eigen::Vector2d ab = b - a;
  const double s = std::clamp((p - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
  return (p - a - s * ab).norm();
}

// Euclidean distance from every vertex to the polygon through the given vertices (closed: the
// loop), negative inside a closed one (even–odd rule).
Eigen::VectorXd polygon_distance(const intrinsic::TriangleMesh& m, const std::vector<Index>& poly,
                                 bool closed) {
  Eigen::VectorXd d(m.positions.rows());
  const std::size_t n = poly.size(), ns = closed ? n : n - 1;
  for (Index v = 0; v < m.positions.rows(); ++v) {
    const Eigen::Vector2d p = m.positions.row(v).head<2>().transpose();
    double best = 1e300;
    bool inside = false;
    for (std::size_t i = 0; i < ns; ++i) {
      const Eigen::Vector2d a = m.positions.row(poly[i]).head<2>().transpose();
      const Eigen::Vector2d b = m.positions.row(poly[(i + 1) % n]).head<2>().transpose();
      best = std::min(best, segment_distance(p, a, b));
      if ((a.y() > p.y()) != (b.y() > p.y()) &&
          p.x() < a.x() + (p.y() - a.y()) * (b.x() - a.x()) / (b.y() - a.y())) {
        inside = !inside;
      }
    }
    d[v] = closed && inside ? -best : best;
  }
  return d;
}

solvers::CurveSurface curve_surface(const intrinsic::TriangleMesh& m, std::vector<Index> vertices,
                                    bool closed) {
  CurveCondition c;
  c.vertices = std::move(vertices);
  c.shape = closed ? intrinsic::CurveShape::kLoop : intrinsic::CurveShape::kPath;
  return solvers::prepare_curve_surface(test::as_input(m), {c});
}

struct Errors {
  double mean_abs = 0, max_abs = 0;
  int wrong_sign = 0, n = 0;
};

// |d| against |exact| over the vertices `use` accepts; the sign where |exact| > margin.
template <class Use>
Errors compare(const Eigen::VectorXd& d, const Eigen::VectorXd& exact, double margin, Use use) {
  Errors e;
  for (Eigen::Index v = 0; v < d.size(); ++v) {
    if (!use(v)) continue;
    const double err = std::abs(std::abs(d[v]) - std::abs(exact[v]));
    e.mean_abs += err;
    e.max_abs = std::max(e.max_abs, err);
    if (std::abs(exact[v]) > margin && d[v] * exact[v] <= 0) ++e.wrong_sign;
    ++e.n;
  }
  e.mean_abs /= std::max(e.n, 1);
  return e;
}

TEST(SignedDistance, CircleOnFlatSquare) {
  const intrinsic::TriangleMesh m = square(40);  // h = 0.05
  const std::vector<Index> loop = circle_vertices(m, 0.5, 40, 1.0);
  const solvers::CurveSurface s = curve_surface(m, loop, true);
  const Eigen::VectorXd exact = polygon_distance(m, loop, true);
  for (const auto level : {solvers::SignedLevelSet::kZeroSet, solvers::SignedLevelSet::kMean}) {
    solvers::SignedDistanceOptions o;
    o.level_set = level;
    const Eigen::VectorXd d = solvers::signed_distance(s, o);
    const Errors e = compare(d, exact, 0.05, [](Eigen::Index) { return true; });
    std::printf("circle %s: mean |err| %.4f, max %.4f, wrong signs %d of %d\n",
                solvers::to_string(level), e.mean_abs, e.max_abs, e.wrong_sign, e.n);
    EXPECT_EQ(e.wrong_sign, 0);
    EXPECT_LT(e.mean_abs, 0.01);  // 0.2 h (measured 0.1 h)
    EXPECT_LT(e.max_abs, 0.03);
    if (level == solvers::SignedLevelSet::kZeroSet) {
      for (const Index v : loop) EXPECT_EQ(d[v], 0.0);
    }
  }
  // the reversed loop flips the sign
  std::vector<Index> rev(loop.rbegin(), loop.rend());
  const Eigen::VectorXd dr = solvers::signed_distance(curve_surface(m, rev, true));
  const Eigen::VectorXd d = solvers::signed_distance(s);
  // FlipOut shortens the reversed loop in the other order and stops at its own tolerance, so the
  // two curves agree to that tolerance, not bit for bit, and the libm of the CPU moves the
  // difference (max |d + dr| 1.4e-3 on an AMD EPYC, below 1e-3 on the Intel machines before): the
  // values must agree to a tenth of the mesh size h = 0.05, a fifth of the method's mean error
  // bound above, and every vertex off the curve by more than that must change its sign.
  const double h = 0.05;
  EXPECT_LT((d + dr).cwiseAbs().maxCoeff(), 0.1 * h);
  int checked = 0;
  for (Eigen::Index v = 0; v < d.size(); ++v) {
    if (std::abs(d[v]) <= 0.1 * h) continue;
    ++checked;
    EXPECT_LT(d[v] * dr[v], 0.0) << "vertex " << v << ": " << d[v] << " and " << dr[v];
  }
  EXPECT_GT(checked, 1000);
}

TEST(SignedDistance, BrokenCircleKeepsItsSides) {
  const intrinsic::TriangleMesh m = square(40);
  const std::vector<Index> arc = circle_vertices(m, 0.5, 33, 0.8);  // 20 % of the arc missing
  const solvers::CurveSurface s = curve_surface(m, arc, false);
  const Eigen::VectorXd exact = polygon_distance(m, circle_vertices(m, 0.5, 40, 1.0), true);
  // away from the gap (angles in (0.8, 1)·2π, widened by 0.1·2π each way)
  auto away = [&](Eigen::Index v) {
    double a = std::atan2(m.positions(v, 1), m.positions(v, 0));
    if (a < 0) a += 2 * kPi;
    return a > 0.1 * 2 * kPi && a < 0.7 * 2 * kPi && std::abs(exact[v]) < 0.3;
  };
  for (const double m_t : {1.0, 4.0}) {  // the paper's default, and a smoother field
    solvers::SignedDistanceOptions o;
    o.time_factor = m_t;
    const Eigen::VectorXd d = solvers::signed_distance(s, o);
    const Errors e = compare(d, exact, 0.05, away);
    std::printf("broken circle, t = %g h²: mean |err| %.4f, max %.4f, wrong signs %d of %d\n", m_t,
                e.mean_abs, e.max_abs, e.wrong_sign, e.n);
    EXPECT_GT(e.n, 300);
    EXPECT_EQ(e.wrong_sign, 0);
    EXPECT_LT(e.mean_abs, 0.01);
    EXPECT_LT(e.max_abs, 0.04);
    EXPECT_LT(d[nearest(m, {0, 0, 0})], -0.3);  // the centre: inside, through the gap too
    EXPECT_GT(d[nearest(m, {0.95, -0.95, 0})], 0.5);
  }
}

TEST(SignedDistance, SphereEquatorSplitsHemispheres) {
  const int n_lat = 16, n_lon = 48;
  const intrinsic::TriangleMesh m = intrinsic::uv_sphere(n_lat, n_lon);
  std::vector<Index> eq;
  for (int k = 0; k < n_lon; ++k) eq.push_back(1 + (n_lat / 2 - 1) * n_lon + k);
  const Eigen::VectorXd d = solvers::signed_distance(curve_surface(m, eq, true));
  double err = 0, worst = 0;
  for (Index v = 0; v < m.positions.rows(); ++v) {
    const double z = m.positions(v, 2);
    const double exact = -std::asin(std::clamp(z, -1.0, 1.0));  // walking east: north is left
    if (std::abs(z) > 0.1) {
      EXPECT_GT(d[v] * exact, 0.0) << "vertex " << v;
    }
    err += std::abs(d[v] - exact);
    worst = std::max(worst, std::abs(d[v] - exact));
  }
  err /= double(m.positions.rows());
  std::printf("sphere equator: mean |err| %.4f, max %.4f (h ≈ %.3f)\n", err, worst, kPi / n_lat);
  EXPECT_LT(err, 0.01);
  EXPECT_LT(worst, 0.15);  // at the poles' needle fans
}

// Oriented points on the circle of radius 0.5: the normals point out (positive outside).
std::vector<solvers::InputDirection> circle_points(const intrinsic::TriangleMesh& m, int k) {
  std::vector<solvers::InputDirection> pts;
  for (const Index v : circle_vertices(m, 0.5, k, 1.0)) {
    Eigen::Vector3d n = m.positions.row(v).transpose();
    n.z() = 0;
    pts.push_back({v, n.normalized(), ""});
  }
  return pts;
}

Eigen::VectorXd circle_distance(const intrinsic::TriangleMesh& m) {
  Eigen::VectorXd d(m.positions.rows());
  for (Index v = 0; v < d.size(); ++v) d[v] = m.positions.row(v).head<2>().norm() - 0.5;
  return d;
}

TEST(SignedDistance, OrientedPointsOnPointCloudAndTuftedMesh) {
  const intrinsic::TriangleMesh m = square(40);
  const Eigen::VectorXd exact = circle_distance(m);
  auto all = [](Eigen::Index) { return true; };
  {  // the grid's vertices as a point cloud with normals
    io::SurfaceInput in = test::as_input(m);
    in.triangles.clear();
    in.n_polygons = 0;
    in.normals = Eigen::MatrixX3d::Zero(m.positions.rows(), 3);
    in.normals.col(2).setOnes();
    const solvers::PreparedSurface s = solvers::prepare_surface(std::move(in));
    ASSERT_EQ(s.path, intrinsic::SurfacePath::kPointCloud);
    const Eigen::VectorXd d = solvers::signed_distance(s, circle_points(m, 48));
    const Errors e = compare(d, exact, 0.05, all);
    std::printf("point cloud: mean |err| %.4f, max %.4f, wrong signs %d\n", e.mean_abs, e.max_abs,
                e.wrong_sign);
    EXPECT_EQ(e.wrong_sign, 0);
    EXPECT_LT(e.mean_abs, 0.014);
  }
  {  // the mesh with a fin on one edge: nonmanifold, the tufted path
    intrinsic::TriangleMesh fin = m;
    fin.positions.conservativeResize(m.positions.rows() + 1, 3);
    fin.positions.row(m.positions.rows()) << -0.725, -0.95, 0.05;  // over the edge 46–47
    fin.faces.push_back({46, 47, Index(m.positions.rows())});
    const solvers::PreparedSurface s = solvers::prepare_surface(test::as_input(fin));
    ASSERT_EQ(s.path, intrinsic::SurfacePath::kTufted);
    const Eigen::VectorXd d = solvers::signed_distance(s, circle_points(m, 48));
    const Errors e = compare(d.head(m.positions.rows()), exact, 0.05, all);
    std::printf("tufted: mean |err| %.4f, max %.4f, wrong signs %d\n", e.mean_abs, e.max_abs,
                e.wrong_sign);
    EXPECT_EQ(e.wrong_sign, 0);
    EXPECT_LT(e.mean_abs, 0.014);
  }
}

// A straight cut across a long strip (1000 × 10 cells, h = 0.05): beyond about 700 h the vector
// heat underflows, and a second stage from the resolved frontier carries X on; d is x − 1 (right
// of the upward cut positive) to rounding on the whole strip.
TEST(SignedDistance, LongStripNeedsASecondStage) {
  intrinsic::TriangleMesh m = intrinsic::grid(1000, 10, 50.0, 0.5);
  CurveCondition c;
  c.vertices = {20, 10 * 1001 + 20};
  const solvers::CurveSurface s = solvers::prepare_curve_surface(test::as_input(m), {c});
  solvers::SignedDistanceReport rep;
  const Eigen::VectorXd d = solvers::signed_distance(s, {}, &rep);
  EXPECT_GE(rep.stages, 2);
  EXPECT_EQ(rep.unresolved_vertices, 0);
  double worst = 0;
  for (Index v = 0; v < d.size(); ++v)
    worst = std::max(worst, std::abs(d[v] - (m.positions(v, 0) - 1)));
  EXPECT_LT(worst, 1e-6);
}

// A loop on spot: FlipOut leaves 5 long curve edges (split into pieces of about h for the
// sources) with large negative cotan weights (constrained, across nearly flat triangle pairs:
// clamped); |d| stays close to the unsigned heat distance to the same curve near it (0.003
// measured; 0.035 with the long edges unsplit).
TEST(SignedDistance, SpotLoopMatchesUnsignedDistanceNearTheCurve) {
  CurveCondition c;
  c.vertices = {1392, 1382, 323};
  c.shape = intrinsic::CurveShape::kLoop;
  const solvers::CurveSurface s = solvers::prepare_curve_surface(
      io::read_surface((test::test_data() / "spot.obj").string()), {c});
  ASSERT_LT(s.signs.min_weight, 0.0);  // the case the clamping is for
  const Eigen::VectorXd d = solvers::signed_distance(s);
  const Eigen::VectorXd u = solvers::curve_distance(s);
  double err = 0;
  int n = 0, neg = 0, pos = 0;
  for (Eigen::Index v = 0; v < d.size(); ++v) {
    ASSERT_TRUE(std::isfinite(d[v]));
    neg += d[v] < 0;
    pos += d[v] > 0;
    if (u[v] < 0.2) {
      err += std::abs(std::abs(d[v]) - u[v]);
      ++n;
    }
  }
  err /= n;
  std::printf("spot loop: mean ||d| - heat distance| %.4f over %d vertices within 0.2\n", err, n);
  EXPECT_LT(err, 0.006);
  EXPECT_GT(neg, 500);
  EXPECT_GT(pos, 500);
}

TEST(SignedDistance, BadInputIsOneClearError) {
  const intrinsic::TriangleMesh m = square(8);
  const solvers::PreparedSurface s = solvers::prepare_surface(test::as_input(m));
  EXPECT_THROW(solvers::signed_distance(s, {}), InvalidInput);
  EXPECT_THROW(solvers::signed_distance(s, {{0, {0, 0, 1}, "p:1"}}), InvalidInput);  // normal ⟂
  EXPECT_THROW(solvers::signed_distance(s, {{999, {1, 0, 0}, "p:1"}}), InvalidInput);
  EXPECT_THROW(solvers::signed_distance(s, {{3, {1, 0, 0}, ""}, {3, {1, 0, 0}, ""}}), InvalidInput);
  solvers::SignedDistanceOptions bad;
  bad.time_factor = -1;
  EXPECT_THROW(solvers::signed_distance(s, {{3, {1, 0, 0}, ""}}, bad), InvalidInput);
  EXPECT_THROW(solvers::signed_level_set_from("zero"), InvalidInput);
  // curves need an orientable surface
  CurveCondition c;
  c.vertices = {0, 5};
  EXPECT_THROW(solvers::prepare_curve_surface(test::as_input(test::moebius(12)), {c}),
               InvalidInput);
}

}  // namespace
}  // namespace ifem
