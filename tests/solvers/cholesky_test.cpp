#include "solvers/cholesky.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>

#include "fem/operators.h"
#include "intrinsic/core/errors.h"
#include "test_util.h"

namespace ifem::solvers {
namespace {

fem::SparseMatrix spd_matrix() {
  const auto tri = test::make_tri(intrinsic::icosphere(4));
  fem::SparseMatrix A = fem::cotan_laplacian(tri);
  const Eigen::VectorXd m = fem::lumped_mass(tri);
  for (Eigen::Index i = 0; i < A.rows(); ++i) A.coeffRef(i, i) += m[i];
  A.makeCompressed();
  return A;
}

TEST(SolversCholesky, SolvesVectorAndMatrixRhs) {
  const fem::SparseMatrix A = spd_matrix();
  const CholeskySolver chol(A);
  EXPECT_EQ(chol.size(), A.rows());
  const Eigen::VectorXd x0 = Eigen::VectorXd::LinSpaced(A.rows(), -1.0, 2.0);
  const Eigen::VectorXd x = chol.solve(Eigen::VectorXd(A * x0));
  EXPECT_LT((x - x0).norm() / x0.norm(), 1e-10);
  Eigen::MatrixXd X0 = Eigen::MatrixXd::Random(A.rows(), 3);
  const Eigen::MatrixXd X = chol.solve(Eigen::MatrixXd(A * X0));
  EXPECT_LT((X - X0).norm() / X0.norm(), 1e-10);
  EXPECT_GT(chol.factor_nonzeros(), A.rows());
}

TEST(SolversCholesky, RefactorSamePatternAndMove) {
  fem::SparseMatrix A = spd_matrix();
  CholeskySolver chol(A);
  A *= 2.0;
  chol.refactor(A);
  const Eigen::VectorXd x0 = Eigen::VectorXd::Ones(A.rows());
  CholeskySolver moved(std::move(chol));
  EXPECT_LT((moved.solve(Eigen::VectorXd(A * x0)) - x0).norm(), 1e-9);
  // a different pattern is refused, and the old factor still works
  fem::SparseMatrix B(A.rows(), A.cols());
  B.setIdentity();
  EXPECT_THROW(moved.refactor(B), InvalidInput);
  EXPECT_LT((moved.solve(Eigen::VectorXd(A * x0)) - x0).norm(), 1e-9);
}

TEST(SolversCholesky, SingularMatrixThrowsSolverError) {
  const auto tri = test::make_tri(intrinsic::icosphere(3));
  const fem::SparseMatrix L = fem::cotan_laplacian(tri);  // L·1 = 0: singular
  try {
    CholeskySolver chol(L);
    FAIL() << "expected SolverError";
  } catch (const SolverError& e) {
    EXPECT_NE(std::string(e.what()).find("not positive definite"), std::string::npos) << e.what();
  }
  fem::SparseMatrix neg = spd_matrix();
  neg *= -1.0;
  EXPECT_THROW(CholeskySolver{neg}, SolverError);
  // refactor with an indefinite matrix keeps the old factor
  fem::SparseMatrix A = spd_matrix();
  CholeskySolver chol(A);
  EXPECT_THROW(chol.refactor(neg), SolverError);
  const Eigen::VectorXd x0 = Eigen::VectorXd::Ones(A.rows());
  EXPECT_LT((chol.solve(Eigen::VectorXd(A * x0)) - x0).norm(), 1e-9);
}

TEST(SolversCholesky, BadInput) {
  fem::SparseMatrix R(3, 4);
  EXPECT_THROW(CholeskySolver{R}, InvalidInput);
  fem::SparseMatrix E(0, 0);
  EXPECT_THROW(CholeskySolver{E}, InvalidInput);
  fem::SparseMatrix A = spd_matrix();
  A.coeffRef(0, 0) = std::nan("");
  EXPECT_THROW(CholeskySolver{A}, InvalidInput);
  const CholeskySolver chol(spd_matrix());
  EXPECT_THROW(chol.solve(Eigen::VectorXd(Eigen::VectorXd::Ones(3))), InvalidInput);
}

TEST(SolversCholesky, RawSolveInPlaceMatchesVectorSolveAndReportsChoice) {
  const fem::SparseMatrix A = spd_matrix();
  // lower triangle only: all CHOLMOD reads
  const fem::SparseMatrix lower = A.triangularView<Eigen::Lower>();
  const CholeskySolver chol(lower);
  EXPECT_STREQ(chol.ordering(), "AMD");
  EXPECT_TRUE(chol.supernodal());
  EXPECT_GT(chol.factor_nonzeros(), 0.0);
  EXPECT_GT(chol.factor_flops(), 0.0);
  const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(A.rows(), -1.0, 2.0);
  const Eigen::VectorXd x = chol.solve(b);
  EXPECT_LT((A * x - b).norm(), 1e-10 * b.norm());
  Eigen::VectorXd y = b;
  chol.solve(y.data(), y.data());  // in place, reused workspace
  chol.solve(y.data(), y.data());  // twice: A⁻²b
  EXPECT_LT((A * (A * y) - b).norm(), 1e-9 * b.norm());
  Eigen::MatrixXd B(A.rows(), 3);
  B << b, 2 * b, -b;
  const Eigen::MatrixXd X = chol.solve(B);  // column count changes: workspace reallocated
  EXPECT_LT((X.col(1) - 2 * x).norm(), 1e-12 * x.norm());
}

TEST(SolversCholesky, BlasThreadScopeRestoresTheSetting) {
  const int before = BlasThreadScope::current();
  {
    const BlasThreadScope outer(1);
    if (before > 0) {
      EXPECT_EQ(BlasThreadScope::current(), 1);
    }
    const BlasThreadScope inner(3);  // nested: the first scope's count stays
    if (before > 0) {
      EXPECT_EQ(BlasThreadScope::current(), 1);
    }
  }
  EXPECT_EQ(BlasThreadScope::current(), before);
}

}  // namespace
}  // namespace ifem::solvers
