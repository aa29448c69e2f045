// The Vector Heat Method (solvers/vector/vector_heat.h) against known answers: parallel fields on a
// flat domain are constant, the log map of a flat domain is the identity, on the unit sphere the
// log map's radius is the great-circle distance and transport along a great circle keeps the angle
// to the arc; plus the closest-point extension, linearity, the 3D bases and bad input.
#include "solvers/vector/vector_heat.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdio>
#include <functional>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "intrinsic/core/errors.h"
#include "solvers/tangent_test_util.h"
#include "solvers/test_util.h"

namespace ifem::solvers {
namespace {

using Complex = std::complex<double>;
using intrinsic::kPi;

// A flat n×n grid on the unit square, interior vertices jittered in the plane by up to
// `jitter`·(1/n) in x and y (the boundary stays straight, so boundary vertices have angle sum
// π except the corners). Vertex (i, j) is j·(n + 1) + i.
intrinsic::TriangleMesh flat_grid(int n, double jitter = 0.25, unsigned seed = 3) {
  intrinsic::TriangleMesh m = intrinsic::grid(n, n);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-jitter / n, jitter / n);
  for (int j = 1; j < n; ++j) {
    for (int i = 1; i < n; ++i) {
      const Index v = j * (n + 1) + i;
      m.positions(v, 0) += u(rng);
      m.positions(v, 1) += u(rng);
    }
  }
  return m;
}

Index grid_id(int n, int i, int j) { return j * (n + 1) + i; }

bool on_grid_boundary(int n, Index v) {
  const Index i = v % (n + 1), j = v / (n + 1);
  return i == 0 || j == 0 || i == n || j == n;
}

// --- flat domain --------------------------------------------------------------------------------

// Angle error of transport on the flat grid: the transported field in 3D against the source's
// vector, over interior vertices (FlatDomainsWithCornersTransportExactly covers every vertex).
test::ErrorStats flat_transport_error(int n) {
  const intrinsic::TriangleMesh m = flat_grid(n);
  const auto tri = test::make_tri(m, false);
  const VectorHeatSolver solver(tri);
  const Index src = grid_id(n, n / 2, n / 2);
  const Complex z(std::cos(0.7), std::sin(0.7));
  VectorHeatReport rep;
  const Eigen::VectorXcd x = solver.transport({{src, 2.0 * z}}, &rep);
  EXPECT_EQ(rep.unreached_vertices, 0);
  EXPECT_EQ(rep.unresolved_vertices, 0);
  EXPECT_NEAR(std::abs(x[src] - 2.0 * z), 0.0, 1e-12);
  const TangentBasis3d basis =
      tangent_basis_3d(m.positions, m.faces, {}, solver.triangulation(), solver.frames());
  const Eigen::MatrixX3d x3 = to_3d(x, basis);
  const Eigen::Vector3d ref = x3.row(src).transpose();
  test::ErrorStats s;
  for (Index v = 0; v < tri.n_vertices(); ++v) {
    EXPECT_NEAR(std::abs(x[v]), 2.0, 1e-12);  // one source: its length everywhere
    if (on_grid_boundary(n, v)) continue;
    s.add(std::abs(test::signed_angle(ref, x3.row(v).transpose(), Eigen::Vector3d::UnitZ())));
  }
  s.finish();
  std::printf("flat transport n=%d: angle error mean %.3g max %.3g rad\n", n, s.mean, s.max);
  return s;
}

// The connection of a flat domain is trivial (fem/connection.h), so the transported field is
// the constant one up to round-off at every resolution (no discretization error to converge).
TEST(SolversVectorHeat, FlatTransportIsConstant) {
  for (const int n : {16, 32}) EXPECT_LT(flat_transport_error(n).max, 1e-12) << n;
}

// Flat domains with corners (the jittered square: corners π/2; the L: five corners π/2, one
// 3π/2; boundary vertices slid along their straight sides): the connection is flat (boundary
// vertices keep their true angles), so in a parallel gauge p (r_h = p_j / p_i) the connection
// Laplacian is P L P* and the vector heat of z at s is p_v φ_v z / p_s, φ the scalar heat (> 0):
// the transported direction is the source's at EVERY vertex, corners included, up to the
// round-off of the fans' angle sums and of the solve (measured ≤ 6e-15 rad up to n = 24; the
// bound 1e-12 leaves room for longer sums, and is 1e10 times below the 0.5° the issue asks
// for). Returns the largest angle (rad) between the 3D vector at a vertex and the source's.
double flat_domain_transport_max_angle(const intrinsic::TriangleMesh& m, Index src, double alpha,
                                       Index* worst_vertex = nullptr) {
  const auto tri = test::make_tri(m, false);
  const VectorHeatSolver solver(tri);
  const Complex z = std::polar(1.5, alpha);
  VectorHeatReport rep;
  const Eigen::VectorXcd x = solver.transport({{src, z}}, &rep);
  EXPECT_EQ(rep.unreached_vertices, 0);
  EXPECT_EQ(rep.unresolved_vertices, 0);
  const TangentBasis3d basis =
      tangent_basis_3d(m.positions, m.faces, {}, solver.triangulation(), solver.frames());
  EXPECT_EQ(basis.fallback_vertices, 0);
  const Eigen::MatrixX3d x3 = to_3d(x, basis);
  const Eigen::Vector3d ref = x3.row(src).transpose();
  double worst = 0.0;
  for (Index v = 0; v < tri.n_vertices(); ++v) {
    EXPECT_NEAR(std::abs(x[v]), 1.5, 1e-12);
    const double e =
        std::abs(test::signed_angle(ref, x3.row(v).transpose(), Eigen::Vector3d::UnitZ()));
    if (e >= worst && worst_vertex) *worst_vertex = v;
    worst = std::max(worst, e);
  }
  return worst;
}

// The vertex of m nearest to (x, y).
Index nearest_vertex(const intrinsic::TriangleMesh& m, double x, double y) {
  Index best = 0;
  for (Index v = 0; v < m.positions.rows(); ++v) {
    if (std::hypot(m.positions(v, 0) - x, m.positions(v, 1) - y) <
        std::hypot(m.positions(best, 0) - x, m.positions(best, 1) - y)) {
      best = v;
    }
  }
  return best;
}

TEST(SolversVectorHeat, FlatDomainsWithCornersTransportExactly) {
  double overall = 0.0;
  for (const bool l_shape : {false, true}) {
    for (const int n : {8, 24}) {
      const intrinsic::TriangleMesh m =
          l_shape ? test::flat_l_shape(n, 0.3, 7) : test::flat_square(n, 0.3, 9);
      // sources: the centre of the square / the L's arm, next to the reflex corner, next to a
      // convex corner, and a corner itself; directions in every quadrant
      const Index sources[4] = {nearest_vertex(m, 0.27, 0.31), nearest_vertex(m, 0.47, 0.45),
                                nearest_vertex(m, 0.9, 0.08), nearest_vertex(m, 0.0, 1.0)};
      for (int k = 0; k < 4; ++k) {
        const double alpha = -2.9 + 1.7 * k;
        Index at = 0;
        const double worst = flat_domain_transport_max_angle(m, sources[k], alpha, &at);
        std::printf("flat %s n=%d source %d angle %.2f: max angle error %.3g rad at vertex %d\n",
                    l_shape ? "L" : "square", n, int(sources[k]), alpha, worst, int(at));
        EXPECT_LT(worst, 1e-12) << (l_shape ? "L" : "square") << " n " << n << " source "
                                << sources[k] << " worst at " << at;
        overall = std::max(overall, worst);
      }
    }
  }
  std::printf("flat domains with corners: max transport angle error %.3g rad\n", overall);
}

TEST(SolversVectorHeat, ExtensionTakesTheNearestSourcesValue) {
  for (const int n : {16, 32}) {
    const intrinsic::TriangleMesh m = flat_grid(n);
    const auto tri = test::make_tri(m, false);
    const VectorHeatSolver solver(tri);
    const Index a = grid_id(n, n / 4, n / 2), b = grid_id(n, 3 * n / 4, n / 2);
    const Eigen::VectorXd ext = solver.extend_scalar({{a, 1.0}, {b, 5.0}});
    EXPECT_NEAR(ext[a], 1.0, 1e-3);
    EXPECT_NEAR(ext[b], 5.0, 1e-3);
    // away from the bisector (6h: the heat kernels' ratio there is about e^{-6}), the nearest
    // source's value
    double worst = 0.0;
    int counted = 0;
    for (Index v = 0; v < tri.n_vertices(); ++v) {
      const double da = (m.positions.row(v) - m.positions.row(a)).norm();
      const double db = (m.positions.row(v) - m.positions.row(b)).norm();
      EXPECT_GE(ext[v], 1.0 - 1e-9);
      EXPECT_LE(ext[v], 5.0 + 1e-9);
      if (std::abs(da - db) < 6.0 / n) continue;
      worst = std::max(worst, std::abs(ext[v] - (da < db ? 1.0 : 5.0)));
      ++counted;
    }
    std::printf("extension n=%d: max error %.3g over %d vertices\n", n, worst, counted);
    EXPECT_GT(counted, tri.n_vertices() / 5);
    EXPECT_LT(worst, 0.04);  // 1% of the values' spread
  }
}

// Log map on the flat grid against the identity map in the source's frame: relative position
// error over vertices at least 3h from the source (corners included: boundary vertices keep
// their true angles), and the angle of the reference halfedge's head.
test::ErrorStats flat_log_map_error(int n) {
  const intrinsic::TriangleMesh m = flat_grid(n);
  const auto tri = test::make_tri(m, false);
  const VectorHeatSolver solver(tri);
  const Index src = grid_id(n, n / 2, n / 2);
  const Eigen::VectorXcd z = solver.log_map(src);
  EXPECT_EQ(z[src], Complex(0.0));
  const TangentBasis3d basis =
      tangent_basis_3d(m.positions, m.faces, {}, solver.triangulation(), solver.frames());
  const Eigen::Vector3d e1 = basis.e1.row(src).transpose(), e2 = basis.e2.row(src).transpose();
  test::ErrorStats s;
  for (Index v = 0; v < tri.n_vertices(); ++v) {
    const Eigen::Vector3d d = (m.positions.row(v) - m.positions.row(src)).transpose();
    const Complex exact(d.dot(e1), d.dot(e2));
    if (std::abs(exact) < 3.0 / n) continue;
    s.add(std::abs(z[v] - exact) / std::abs(exact));
  }
  s.finish();
  const Index head = solver.triangulation().head(solver.triangulation().vertex_halfedge(src));
  const double angle0 = std::arg(z[head]);
  std::printf(
      "flat log map n=%d: relative error mean %.3g max %.3g; angle of the reference "
      "head %.3g rad\n",
      n, s.mean, s.max, angle0);
  EXPECT_LT(std::abs(angle0), 0.1);
  return s;
}

TEST(SolversVectorHeat, FlatLogMapIsTheIdentity) {
  const test::ErrorStats coarse = flat_log_map_error(16);
  const test::ErrorStats fine = flat_log_map_error(32);
  EXPECT_LT(fine.mean, 0.03);
  EXPECT_LT(fine.mean, coarse.mean);
}

// --- unit sphere --------------------------------------------------------------------------------

// Log map about vertex 0 of the unit icosphere: the radius against the great-circle distance
// (relative), and the angle against the great circle's direction at the source, read in the
// source's 3D basis (absolute, rad), over vertices from 3h to π − 0.3 (the antipode is the cut
// locus).
test::ErrorStats sphere_log_map_error(int n, test::ErrorStats* angle) {
  const intrinsic::TriangleMesh m = intrinsic::icosphere(n);
  const auto tri = test::make_tri(m, false);
  const VectorHeatSolver solver(tri);
  const Index src = 0;
  const Eigen::VectorXcd z = solver.log_map(src);
  const TangentBasis3d basis =
      tangent_basis_3d(m.positions, m.faces, {}, solver.triangulation(), solver.frames());
  const Eigen::Vector3d s = m.positions.row(src).transpose();
  const Eigen::Vector3d e1 = basis.e1.row(src).transpose(), e2 = basis.e2.row(src).transpose();
  const double h = intrinsic::mean_edge_length(tri);
  test::ErrorStats radius;
  for (Index v = 0; v < tri.n_vertices(); ++v) {
    const Eigen::Vector3d p = m.positions.row(v).transpose();
    const double exact = test::great_circle(s, p);
    if (exact < 3.0 * h || exact > kPi - 0.3) continue;
    radius.add(std::abs(std::abs(z[v]) - exact) / exact);
    const Eigen::Vector3d leave = p - p.dot(s) * s;
    angle->add(
        std::abs(test::wrap_angle(std::arg(z[v]) - std::atan2(leave.dot(e2), leave.dot(e1)))));
  }
  radius.finish();
  angle->finish();
  std::printf(
      "sphere log map n=%d: radius relative error mean %.3g max %.3g; angle error mean "
      "%.3g max %.3g rad\n",
      n, radius.mean, radius.max, angle->mean, angle->max);
  return radius;
}

TEST(SolversVectorHeat, SphereLogMapIsTheGreatCircleMap) {
  test::ErrorStats angle_coarse, angle_fine;
  const test::ErrorStats coarse = sphere_log_map_error(8, &angle_coarse);
  const test::ErrorStats fine = sphere_log_map_error(16, &angle_fine);
  EXPECT_LT(fine.mean, 0.03);
  EXPECT_LT(fine.mean, coarse.mean);
  EXPECT_LT(angle_fine.mean, 0.02);
  EXPECT_LT(angle_fine.max, 0.1);
}

// Transport of e^{iα} from a vertex s to the vertices x near s's equator (great-circle distance
// π/2 ± 0.05): the angle from the arc's direction to the vector must be the same at both ends.
test::ErrorStats sphere_transport_error(int n, double alpha) {
  const intrinsic::TriangleMesh m = intrinsic::icosphere(n);
  const auto tri = test::make_tri(m, false);
  const VectorHeatSolver solver(tri);
  const Index src = 0;
  const Eigen::VectorXcd x = solver.transport({{src, std::polar(1.0, alpha)}});
  const TangentBasis3d basis =
      tangent_basis_3d(m.positions, m.faces, {}, solver.triangulation(), solver.frames());
  const Eigen::MatrixX3d x3 = to_3d(x, basis);
  char label[64];
  std::snprintf(label, sizeof(label), "sphere transport n=%d alpha=%.2f", n, alpha);
  return test::great_circle_transport_error(m.positions, x3, src, label);
}

TEST(SolversVectorHeat, SphereTransportAlongGreatCircles) {
  for (const double alpha : {0.0, 1.3}) {
    const test::ErrorStats coarse = sphere_transport_error(8, alpha);
    const test::ErrorStats fine = sphere_transport_error(16, alpha);
    EXPECT_GT(fine.n, 20);
    EXPECT_LT(coarse.max, 0.01);
    EXPECT_LT(fine.max, 0.01);
  }
}

// Transport is linear in the sources' vectors: turning them all by e^{iα} turns the result.
// (On a flat grid: on a symmetric sphere the antipode of a vertex source is a vertex where the
// transported vectors cancel to round-off and the direction is noise.)
TEST(SolversVectorHeat, TransportIsLinearInTheSourceVectors) {
  const int n = 16;
  const auto tri = test::make_tri(flat_grid(n), false);
  const VectorHeatSolver solver(tri);
  const Complex rot = std::polar(1.0, 2.1);
  const Index a = grid_id(n, 3, 3), b = grid_id(n, 12, 10);
  const Eigen::VectorXcd one = solver.transport({{a, 1.0}});
  const Eigen::VectorXcd turned = solver.transport({{a, rot}});
  EXPECT_LT((turned - rot * one).cwiseAbs().maxCoeff(), 1e-12);
  // two sources of different lengths: turning both turns the result
  const std::vector<VectorSource> two = {{a, Complex(1.0, 2.0)}, {b, Complex(-0.5, 0.1)}};
  const std::vector<VectorSource> two_turned = {{a, rot * two[0].vector}, {b, rot * two[1].vector}};
  const Eigen::VectorXcd x = solver.transport(two), y = solver.transport(two_turned);
  EXPECT_LT((y - rot * x).cwiseAbs().maxCoeff(), 1e-12 * x.cwiseAbs().maxCoeff());
  // each source keeps its own vector, and lengths blend between the two
  EXPECT_LT(std::abs(x[a] - two[0].vector), 1e-3);
  EXPECT_LT(std::abs(x[b] - two[1].vector), 1e-3);
  EXPECT_LE(x.cwiseAbs().maxCoeff(), std::abs(two[0].vector) + 1e-9);
  EXPECT_GE(x.cwiseAbs().minCoeff(), std::abs(two[1].vector) - 1e-9);
}

// Lengths scaled by 2^10: transport and extension unchanged (the solver works in units of a
// power of two near h), the log map's radius and the time step scaled.
TEST(SolversVectorHeat, ResultsFollowTheLengthScale) {
  const intrinsic::TriangleMesh m = flat_grid(12);
  intrinsic::TriangleMesh big = m;
  big.positions *= 1024.0;
  const VectorHeatSolver a(test::make_tri(m, false)), b(test::make_tri(big, false));
  EXPECT_NEAR(b.time_step(), 1024.0 * 1024.0 * a.time_step(), 1e-9 * b.time_step());
  const std::vector<VectorSource> src = {{20, Complex(0.3, -1.0)}, {100, Complex(2.0, 0.0)}};
  EXPECT_LT((a.transport(src) - b.transport(src)).cwiseAbs().maxCoeff(), 1e-9);
  const Eigen::VectorXd ea = a.extend_scalar({{20, 1.0}, {100, -1.0}});
  const Eigen::VectorXd eb = b.extend_scalar({{20, 1.0}, {100, -1.0}});
  EXPECT_LT((ea - eb).cwiseAbs().maxCoeff(), 1e-9);
  const Eigen::VectorXcd la = a.log_map(60), lb = b.log_map(60);
  EXPECT_LT((1024.0 * la - lb).cwiseAbs().maxCoeff(), 1e-9 * lb.cwiseAbs().maxCoeff());
  EXPECT_GT(la.cwiseAbs().maxCoeff(), 0.5);  // in the input's unit (the square is 1 wide)
  const Eigen::VectorXcd aa = a.log_map(60, LogMapMethod::kAffine);
  const Eigen::VectorXcd ab = b.log_map(60, LogMapMethod::kAffine);
  EXPECT_LT((1024.0 * aa - ab).cwiseAbs().maxCoeff(), 1e-9 * ab.cwiseAbs().maxCoeff());
  EXPECT_GT(aa.cwiseAbs().maxCoeff(), 0.5);
}

// --- components, bad input ----------------------------------------------------------------------

TEST(SolversVectorHeat, UnreachedComponentsAndUnreferencedVertices) {
  const intrinsic::TriangleMesh m = test::two_copies(flat_grid(8), 2.0, 3);
  const auto tri = test::make_tri(m, false);
  const VectorHeatSolver solver(tri);
  const Index per_copy = 81;
  VectorHeatReport rep;
  const Eigen::VectorXcd x = solver.transport({{40, Complex(0.0, 1.0)}}, &rep);
  EXPECT_EQ(rep.unreached_vertices, per_copy + 3);
  EXPECT_EQ(rep.unresolved_vertices, 0);
  EXPECT_EQ(x[per_copy + 40], Complex(0.0));
  EXPECT_NEAR(std::abs(x[0]), 1.0, 1e-12);
  const Eigen::VectorXd e = solver.extend_scalar({{40, 3.0}});
  EXPECT_TRUE(std::isnan(e[per_copy + 40]));
  EXPECT_TRUE(std::isnan(e[2 * per_copy]));
  EXPECT_NEAR(e[0], 3.0, 1e-12);
  const Eigen::VectorXcd z = solver.log_map(per_copy + 40, &rep);
  EXPECT_EQ(rep.unreached_vertices, per_copy + 3);
  EXPECT_TRUE(std::isnan(z[0].real()) && std::isnan(z[0].imag()));
  EXPECT_GT(std::abs(z[per_copy]), 0.5);
}

void expect_invalid(const std::function<void()>& f, const std::string& mention) {
  try {
    f();
    ADD_FAILURE() << "accepted input that should mention " << mention;
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find(mention), std::string::npos) << e.what();
  }
}

TEST(SolversVectorHeat, BadInputNamesTheArgument) {
  const auto tri = test::make_tri(intrinsic::icosphere(3), false);
  const VectorHeatSolver solver(tri);
  const Index nv = tri.n_vertices();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  expect_invalid([&] { solver.transport({}); }, "empty");
  expect_invalid([&] { solver.transport({{1, 1.0}, {nv, 1.0}}); }, "sources[1].vertex");
  expect_invalid([&] { solver.transport({{-1, 1.0}}); }, "sources[0].vertex");
  expect_invalid([&] { solver.transport({{1, 1.0}, {1, 2.0}}); }, "repeats");
  expect_invalid([&] { solver.transport({{1, 0.0}}); }, "sources[0].vector is zero");
  expect_invalid([&] { solver.transport({{1, Complex(nan, 0.0)}}); }, "sources[0].vector");
  expect_invalid([&] { solver.extend_scalar({}); }, "empty");
  expect_invalid([&] { solver.extend_scalar({{2, nan}}); }, "sources[0].value");
  expect_invalid([&] { solver.extend_scalar({{nv + 5, 1.0}}); }, "sources[0].vertex");
  expect_invalid([&] { solver.log_map(nv); }, "source");
  expect_invalid([&] { solver.log_map(-3); }, "source");
  test::expect_each_rejected(&VectorHeatOptions::time_factor, {0.0, -1.0, nan}, "time_factor");
  test::expect_each_rejected(&VectorHeatOptions::mean_edge_length, {-1.0, nan}, "mean_edge_length");
  VectorHeatOptions too_long;
  too_long.boundary_vertices.assign(static_cast<std::size_t>(nv) + 1, 0);
  expect_invalid([&] { VectorHeatSolver{tri, too_long}; }, "boundary_vertices");
  const auto unreferenced = test::make_tri(test::two_copies(intrinsic::icosphere(2), 3.0, 1));
  const VectorHeatSolver s2(unreferenced);
  expect_invalid([&] { s2.transport({{unreferenced.n_vertices() - 1, 1.0}}); }, "not referenced");
}

// --- 3D bases -----------------------------------------------------------------------------------

// On a flat grid every interior vertex has angle sum 2π and its intrinsic edges are chords, so
// to_3d of the unit vector at a halfedge's angle is the halfedge's direction: for both face
// orientations, and as a point cloud (no triangles: principal-axis normals).
TEST(SolversVectorHeat, TangentBasisMapsHalfedgeAnglesToTheirChords) {
  const int n = 10;
  intrinsic::TriangleMesh m = flat_grid(n);
  m.positions.col(2) = 0.3 * m.positions.col(0);  // a tilted plane
  for (const int variant : {0, 1, 2}) {
    intrinsic::TriangleMesh mv = m;
    if (variant == 1) {
      for (auto& f : mv.faces) std::swap(f[1], f[2]);
    }
    const auto tri = test::make_tri(mv, true);  // flipped edges are still chords here
    const fem::TangentFrames frames = fem::tangent_frames(tri);
    const std::vector<Triangle> none;
    const TangentBasis3d b =
        tangent_basis_3d(mv.positions, variant == 2 ? none : mv.faces, {}, tri, frames);
    EXPECT_EQ(b.fallback_vertices, 0);
    const Eigen::Vector3d up = Eigen::Vector3d(-0.3, 0.0, 1.0).normalized();
    double worst = 0.0;
    for (Index h = 0; h < tri.n_halfedges(); ++h) {
      const Index v = tri.tail(h);
      if (on_grid_boundary(n, v)) continue;
      Eigen::VectorXcd z = Eigen::VectorXcd::Zero(tri.n_vertices());
      z[v] = std::polar(1.0, frames.halfedge_angle[h]);
      const Eigen::Vector3d got = to_3d(z, b).row(v).transpose();
      const Eigen::Vector3d want =
          (mv.positions.row(tri.head(h)) - mv.positions.row(v)).transpose().normalized();
      worst = std::max(worst, (got - want).norm());
      EXPECT_NEAR(std::abs(b.normal.row(v).dot(up)), 1.0, 1e-9);
    }
    std::printf("basis variant %d: worst |to_3d − chord| %.3g\n", variant, worst);
    EXPECT_LT(worst, 1e-9);
  }
  const auto tri = test::make_tri(m);
  const TangentBasis3d b =
      tangent_basis_3d(m.positions, m.faces, {}, tri, fem::tangent_frames(tri));
  EXPECT_THROW(to_3d(Eigen::VectorXcd::Zero(3), b), InvalidInput);
  const Eigen::MatrixX3d wrong_normals = Eigen::MatrixX3d::Zero(5, 3);
  EXPECT_THROW(tangent_basis_3d(m.positions, {}, wrong_normals, tri, fem::tangent_frames(tri)),
               InvalidInput);
}

}  // namespace
}  // namespace ifem::solvers
