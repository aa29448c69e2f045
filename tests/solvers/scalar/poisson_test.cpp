#include "solvers/scalar/poisson.h"

#include <gtest/gtest.h>

#include <cmath>

#include "fem/operators.h"
#include "intrinsic/core/errors.h"
#include "intrinsic/core/geometry.h"
#include "solvers/test_util.h"

namespace ifem::solvers {
namespace {

using intrinsic::kPi;

// max error of L u = M f on [0,1]² with u = sin(πx) sin(πy) + xy, Dirichlet on the boundary
double square_error(int n) {
  const auto m = intrinsic::grid(n, n);
  const auto tri = test::make_tri(m);
  Eigen::VectorXd f(tri.n_vertices()), exact(tri.n_vertices());
  std::vector<Index> bv;
  std::vector<double> bval;
  for (Index v = 0; v < tri.n_vertices(); ++v) {
    const double x = m.positions(v, 0), y = m.positions(v, 1);
    exact[v] = std::sin(kPi * x) * std::sin(kPi * y) + x * y;
    f[v] = 2 * kPi * kPi * std::sin(kPi * x) * std::sin(kPi * y);
    if (x < 1e-12 || y < 1e-12 || x > 1 - 1e-12 || y > 1 - 1e-12) {
      bv.push_back(v);
      bval.push_back(exact[v]);
    }
  }
  const Eigen::VectorXd u = solve_poisson(
      tri, f, bv, Eigen::Map<Eigen::VectorXd>(bval.data(), Eigen::Index(bval.size())));
  return (u - exact).cwiseAbs().maxCoeff();
}

TEST(SolversPoisson, FlatSquareConvergesAtSecondOrder) {
  const double e1 = square_error(16), e2 = square_error(32), e3 = square_error(64);
  const double p1 = std::log2(e1 / e2), p2 = std::log2(e2 / e3);
  std::printf("Poisson max error: %.3g %.3g %.3g, observed orders %.3f %.3f\n", e1, e2, e3, p1, p2);
  EXPECT_NEAR(p1, 2.0, 0.25);
  EXPECT_NEAR(p2, 2.0, 0.2);
  EXPECT_LT(e3, 1e-3);
}

TEST(SolversPoisson, ClosedSurfaceZeroMeanAndCompatibleRhs) {
  const auto sphere = intrinsic::icosphere(8);
  const auto tri = test::make_tri(sphere);
  const Eigen::VectorXd m = fem::lumped_mass(tri);
  // f = z + 1: incompatible (non-zero mean); the z part is an l = 1 eigenfunction (λ ≈ 2)
  Eigen::VectorXd f(tri.n_vertices());
  for (Index v = 0; v < tri.n_vertices(); ++v) f[v] = sphere.positions(v, 2) + 1.0;
  const Eigen::VectorXd u = solve_poisson(tri, f, {}, Eigen::VectorXd());
  EXPECT_NEAR(m.dot(u), 0.0, 1e-10);
  for (Index v = 0; v < tri.n_vertices(); ++v)
    EXPECT_NEAR(u[v], sphere.positions(v, 2) / 2.0, 5e-3);
  // screened: (L + cM) u = M f has the unique solution z/(2 + c) + 1/c
  PoissonOptions opt;
  opt.screening = 3.0;
  const Eigen::VectorXd us = solve_poisson(tri, f, {}, Eigen::VectorXd(), opt);
  for (Index v = 0; v < tri.n_vertices(); ++v) {
    EXPECT_NEAR(us[v], sphere.positions(v, 2) / 5.0 + 1.0 / 3.0, 5e-3);
  }
}

TEST(SolversPoisson, DisconnectedAndUnreferenced) {
  const auto m = test::two_copies(intrinsic::grid(8, 8), 3.0, 2);
  const auto tri = test::make_tri(m);
  const Index n = Index(intrinsic::grid(8, 8).positions.rows());
  // Dirichlet only on the first copy: u = x there (harmonic); the second copy is pure Neumann
  std::vector<Index> bv;
  Eigen::VectorXd bval(0);
  for (Index v = 0; v < n; ++v) {
    const double x = m.positions(v, 0), y = m.positions(v, 1);
    if (x < 1e-12 || y < 1e-12 || x > 1 - 1e-12 || y > 1 - 1e-12) bv.push_back(v);
  }
  bval.resize(Eigen::Index(bv.size()));
  for (std::size_t i = 0; i < bv.size(); ++i) bval[Eigen::Index(i)] = m.positions(bv[i], 0);
  Eigen::VectorXd f = Eigen::VectorXd::Zero(tri.n_vertices());
  for (Index v = n; v < 2 * n; ++v) f[v] = m.positions(v, 0) - 3.5;  // mean zero already
  const Eigen::VectorXd u = solve_poisson(tri, f, bv, bval);
  for (Index v = 0; v < n; ++v) EXPECT_NEAR(u[v], m.positions(v, 0), 1e-10);
  const Eigen::VectorXd mass = fem::lumped_mass(tri);
  EXPECT_NEAR(mass.segment(n, n).dot(u.segment(n, n)), 0.0, 1e-12);
  EXPECT_GT(u.segment(n, n).cwiseAbs().maxCoeff(), 1e-3);  // non-trivial
  EXPECT_EQ(u[2 * n], 0.0);
  EXPECT_EQ(u[2 * n + 1], 0.0);
  // a Dirichlet value on an unreferenced vertex is returned as given
  const Eigen::VectorXd u2 = solve_poisson(tri, f, {2 * n + 1}, Eigen::VectorXd::Constant(1, 7.0));
  EXPECT_EQ(u2[2 * n + 1], 7.0);
}

TEST(SolversPoisson, ReusesFactorForNewData) {
  const auto m = intrinsic::grid(10, 10);
  const auto tri = test::make_tri(m);
  const PoissonSolver solver(tri, {0, 10});
  const Eigen::VectorXd f = Eigen::VectorXd::Zero(tri.n_vertices());
  Eigen::VectorXd g(2);
  g << 1.0, 1.0;
  const Eigen::VectorXd u = solver.solve(f, g);
  EXPECT_LT((u.array() - 1.0).abs().maxCoeff(), 1e-10);  // constant solution
  g << 0.0, 1.0;
  const Eigen::VectorXd u2 = solver.solve(f, g);
  EXPECT_GT(u2.maxCoeff() - u2.minCoeff(), 0.5);
}

TEST(SolversPoisson, ErrorPaths) {
  const auto tri = test::make_tri(intrinsic::grid(4, 4));
  const Eigen::VectorXd f = Eigen::VectorXd::Zero(tri.n_vertices());
  EXPECT_THROW(solve_poisson(tri, f, {99}, Eigen::VectorXd::Zero(1)), InvalidInput);
  EXPECT_THROW(solve_poisson(tri, f, {1, 1}, Eigen::VectorXd::Zero(2)), InvalidInput);
  EXPECT_THROW(solve_poisson(tri, f, {1}, Eigen::VectorXd::Zero(2)), InvalidInput);
  EXPECT_THROW(solve_poisson(tri, Eigen::VectorXd::Zero(3), {}, Eigen::VectorXd()), InvalidInput);
  PoissonOptions bad;
  bad.screening = -1.0;
  EXPECT_THROW(solve_poisson(tri, f, {}, Eigen::VectorXd(), bad), InvalidInput);
  Eigen::VectorXd nanf = f;
  nanf[0] = std::nan("");
  EXPECT_THROW(solve_poisson(tri, nanf, {}, Eigen::VectorXd()), InvalidInput);
}

}  // namespace
}  // namespace ifem::solvers
