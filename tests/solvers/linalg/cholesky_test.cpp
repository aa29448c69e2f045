#include "solvers/linalg/cholesky.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <complex>
#include <vector>

#include "fem/operators.h"
#include "intrinsic/core/errors.h"
#include "solvers/test_util.h"

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

// A Hermitian positive definite matrix with genuinely complex off-diagonal entries: the SPD
// matrix above with its off-diagonal entries turned by phases e^{i(θ_i − θ_j)} (a gauge
// transform, so it stays positive definite), plus a small non-gauge part that keeps it
// Hermitian: i·c on (i, j) and −i·c on (j, i).
ComplexSparseMatrix hermitian_matrix() {
  const fem::SparseMatrix A = spd_matrix();
  std::vector<Eigen::Triplet<std::complex<double>>> trip;
  for (Eigen::Index j = 0; j < A.outerSize(); ++j) {
    for (fem::SparseMatrix::InnerIterator it(A, j); it; ++it) {
      const Eigen::Index i = it.row();
      std::complex<double> z = it.value();
      if (i != j) {
        z *= std::polar(1.0, 0.3 * double(i) - 0.3 * double(j));
        z += std::complex<double>(0.0, i > j ? 1e-3 : -1e-3) * std::abs(it.value());
      }
      trip.emplace_back(i, j, z);
    }
  }
  ComplexSparseMatrix H(A.rows(), A.cols());
  H.setFromTriplets(trip.begin(), trip.end());
  return H;
}

TEST(SolversCholesky, ComplexHermitianSolvesAndOrderings) {
  const ComplexSparseMatrix H = hermitian_matrix();
  ASSERT_LT((Eigen::MatrixXcd(H) - Eigen::MatrixXcd(H).adjoint()).norm(), 1e-14);
  const Eigen::VectorXcd x0 = Eigen::VectorXcd::Random(H.rows());
  for (const bool metis : {false, true}) {
    CholeskyOptions o;
    o.force_metis = metis;
    // only the lower triangle is read
    const ComplexSparseMatrix lower = H.triangularView<Eigen::Lower>();
    const ComplexCholeskySolver chol(lower, o);
    EXPECT_STREQ(chol.ordering(), metis ? "METIS" : "AMD");
    EXPECT_EQ(chol.size(), H.rows());
    EXPECT_GT(chol.factor_nonzeros(), 0.0);
    const Eigen::VectorXcd x = chol.solve(Eigen::VectorXcd(H * x0));
    EXPECT_LT((x - x0).norm() / x0.norm(), 1e-10);
    Eigen::MatrixXcd X0 = Eigen::MatrixXcd::Random(H.rows(), 3);
    const Eigen::MatrixXcd X = chol.solve(Eigen::MatrixXcd(H * X0));
    EXPECT_LT((X - X0).norm() / X0.norm(), 1e-10);
  }
}

TEST(SolversCholesky, ComplexBadInputAndIndefinite) {
  ComplexSparseMatrix R(3, 4);
  EXPECT_THROW(ComplexCholeskySolver{R}, InvalidInput);
  ComplexSparseMatrix H = hermitian_matrix();
  H.coeffRef(1, 0) = std::complex<double>(0.0, std::nan(""));
  EXPECT_THROW(ComplexCholeskySolver{H}, InvalidInput);
  ComplexSparseMatrix neg = hermitian_matrix();
  neg *= -1.0;
  EXPECT_THROW(ComplexCholeskySolver{neg}, SolverError);
  ComplexCholeskySolver chol(hermitian_matrix());
  EXPECT_THROW(chol.solve(Eigen::VectorXcd(Eigen::VectorXcd::Ones(3))), InvalidInput);
  const ComplexCholeskySolver moved(std::move(chol));
  EXPECT_EQ(moved.size(), hermitian_matrix().rows());
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
