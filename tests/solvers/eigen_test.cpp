#include "solvers/eigen.h"

#include <gtest/gtest.h>

#include <cmath>

#include "fem/operators.h"
#include "intrinsic/core/errors.h"
#include "test_util.h"

namespace ifem::solvers {
namespace {

TEST(SolversEigen, UnitSphereSpectrumWithMultiplicities) {
  const auto tri = test::make_tri(intrinsic::icosphere(16));
  const EigenPairs ep = eigenpairs(tri, 16);
  ASSERT_EQ(ep.values.size(), 16);
  for (int i = 1; i < 16; ++i) EXPECT_LE(ep.values[i - 1], ep.values[i]);
  EXPECT_NEAR(ep.values[0], 0.0, 1e-8);
  // l(l+1) with multiplicity 2l + 1
  int i = 1;
  for (int l = 1; l <= 3; ++l) {
    const double exact = l * (l + 1);
    for (int c = 0; c < 2 * l + 1; ++c, ++i) {
      EXPECT_NEAR(ep.values[i], exact, 0.01 * exact) << "l = " << l << ", copy " << c;
    }
  }
  // residuals and M-orthonormality
  const fem::SparseMatrix L = fem::cotan_laplacian(tri);
  const Eigen::VectorXd m = fem::lumped_mass(tri);
  for (int j = 0; j < 16; ++j) {
    const Eigen::VectorXd r =
        L * ep.vectors.col(j) - ep.values[j] * m.cwiseProduct(ep.vectors.col(j));
    EXPECT_LT(r.norm(), 1e-7 * std::max(1.0, ep.values[j]) * (L * ep.vectors.col(j)).norm() + 1e-9);
  }
  const Eigen::MatrixXd G = ep.vectors.transpose() * m.asDiagonal() * ep.vectors;
  EXPECT_LT((G - Eigen::MatrixXd::Identity(16, 16)).cwiseAbs().maxCoeff(), 1e-8);
}

TEST(SolversEigen, UnreferencedVerticesGetZero) {
  const auto tri = test::make_tri(test::two_copies(intrinsic::icosphere(4), 3.0, 2));
  const EigenPairs ep = eigenpairs(tri, 4);
  EXPECT_NEAR(ep.values[0], 0.0, 1e-8);
  EXPECT_NEAR(ep.values[1], 0.0, 1e-8);  // two components: 0 twice
  EXPECT_GT(ep.values[2], 1.0);
  const Index n = tri.n_vertices();
  EXPECT_EQ(ep.vectors.row(n - 1).norm(), 0.0);
  EXPECT_EQ(ep.vectors.row(n - 2).norm(), 0.0);
}

TEST(SolversEigen, ErrorPaths) {
  const auto tri = test::make_tri(intrinsic::icosphere(2));
  EXPECT_THROW(eigenpairs(tri, 0), InvalidInput);
  EXPECT_THROW(eigenpairs(tri, tri.n_vertices()), InvalidInput);
  EXPECT_THROW(eigenpairs(tri, tri.n_vertices() + 5), InvalidInput);
  EigenOptions o;
  o.max_iterations = 1;
  o.ncv = 0;
  EXPECT_THROW(eigenpairs(test::make_tri(intrinsic::icosphere(12)), 10, o), SolverError);
}

}  // namespace
}  // namespace ifem::solvers
