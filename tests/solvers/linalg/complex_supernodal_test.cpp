// Our complex supernodal kernel (ComplexSupernodalSolver, through ComplexCholeskySolver with
// SolveKernel::kSupernodalDouble): the same solutions as CHOLMOD's own solve on the same factor
// (1e-12 relative) on meshes of several sizes, for point sources, several sources, dense and
// multi-column right-hand sides; small residuals; bitwise the same with one thread and two.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <complex>
#include <random>
#include <vector>

#ifdef _OPENMP
#include <omp.h>
#endif

#include "fem/connection.h"
#include "fem/operators.h"
#include "intrinsic/core/errors.h"
#include "intrinsic/core/geometry.h"
#include "intrinsic/generators/mesh_generators.h"
#include "solvers/linalg/cholesky.h"
#include "solvers/linalg/supernodal_solve.h"
#include "solvers/test_util.h"

namespace ifem::solvers {
namespace {

using Kernel = CholeskyOptions::SolveKernel;
using Complex = std::complex<double>;

// M + t·L∇ (n-direction connection Laplacian, t = h²) of a mesh: the vector heat method's matrix.
ComplexSparseMatrix vector_heat_matrix(const intrinsic::TriangleMesh& m, int symmetry) {
  const auto tri = test::make_tri(m);
  const double h = intrinsic::mean_edge_length(tri);
  ComplexSparseMatrix A =
      h * h * fem::connection_laplacian(tri, fem::tangent_frames(tri), symmetry);
  const Eigen::VectorXd mass = fem::lumped_mass(tri);
  for (Eigen::Index i = 0; i < A.rows(); ++i) A.coeffRef(i, i) += mass[i];
  A.makeCompressed();
  return A;
}

CholeskyOptions complex_kernel_options(Kernel kernel) {
  CholeskyOptions o;
  o.solve_kernel = kernel;
  return o;
}

double complex_rel_diff(const Eigen::MatrixXcd& a, const Eigen::MatrixXcd& b) {
  return (a - b).cwiseAbs().maxCoeff() / b.cwiseAbs().maxCoeff();
}

// Right-hand sides: one point source, three sources, a dense random vector; and all three as the
// columns of one block.
std::vector<Eigen::VectorXcd> right_hand_sides(Eigen::Index n) {
  std::mt19937 rng(7);
  std::normal_distribution<double> g;
  Eigen::VectorXcd one = Eigen::VectorXcd::Zero(n), three = Eigen::VectorXcd::Zero(n);
  one[n / 3] = Complex(0.6, -0.8);
  three[0] = 1.0;
  three[n / 2] = Complex(0.0, 2.0);
  three[n - 1] = Complex(-1.0, 0.5);
  Eigen::VectorXcd dense(n);
  for (Eigen::Index i = 0; i < n; ++i) dense[i] = Complex(g(rng), g(rng));
  return {one, three, dense};
}

void expect_kernel_matches_cholmod(const intrinsic::TriangleMesh& mesh, int symmetry,
                                   bool expect_split) {
  const ComplexSparseMatrix A = vector_heat_matrix(mesh, symmetry);
  const ComplexCholeskySolver cholmod(A, complex_kernel_options(Kernel::kCholmod));
  const ComplexCholeskySolver ours(A, complex_kernel_options(Kernel::kSupernodalDouble));
  const std::vector<Eigen::VectorXcd> rhs = right_hand_sides(A.rows());
  Eigen::MatrixXcd block(A.rows(), Eigen::Index(rhs.size()));
  for (std::size_t j = 0; j < rhs.size(); ++j) {
    const Eigen::VectorXcd x = ours.solve(rhs[j]);
    const Eigen::VectorXcd ref = cholmod.solve(rhs[j]);
    EXPECT_LT(complex_rel_diff(x, ref), 1e-12) << "right-hand side " << j << ", n = " << A.rows();
    const Eigen::VectorXcd r = A.selfadjointView<Eigen::Lower>() * x - rhs[j];
    EXPECT_LT(r.norm() / rhs[j].norm(), 1e-11) << "residual, right-hand side " << j;
    block.col(Eigen::Index(j)) = rhs[j];
  }
  const Eigen::MatrixXcd X = ours.solve(block);
  EXPECT_LT(complex_rel_diff(X, cholmod.solve(block)), 1e-12) << "block of " << block.cols();
  for (Eigen::Index j = 0; j < X.cols(); ++j) {  // a column of a block: the same as alone
    EXPECT_EQ(X.col(j), ours.solve(Eigen::VectorXcd(block.col(j)))) << "column " << j;
  }
  // the large case runs the two bins (ComplexSupernodalSolver: entries ≥ kParallelEntries / 2)
  if (expect_split) {
    EXPECT_GE(ours.factor_nonzeros(), 0.5 * SupernodalSolver::kParallelEntries);
  }
}

TEST(ComplexSupernodal, MatchesCholmodSmallSphere) {
  expect_kernel_matches_cholmod(intrinsic::icosphere(4), 1, false);
}

TEST(ComplexSupernodal, MatchesCholmodGridWithBoundaryFourSymmetry) {
  expect_kernel_matches_cholmod(intrinsic::grid(40, 30), 4, false);
}

TEST(ComplexSupernodal, MatchesCholmodLargeSphereOverTwoBins) {
  // icosphere(50): 25k vertices, about 1.2M complex factor entries, past the two-bin threshold
  expect_kernel_matches_cholmod(intrinsic::icosphere(50), 1, true);
}

TEST(ComplexSupernodal, SameBitsOnOneThreadAndTwo) {
#ifdef _OPENMP
  const ComplexSparseMatrix A = vector_heat_matrix(intrinsic::icosphere(50), 1);
  const ComplexCholeskySolver ours(A, complex_kernel_options(Kernel::kSupernodalDouble));
  const int saved = omp_get_max_threads();
  for (const Eigen::VectorXcd& b : right_hand_sides(A.rows())) {
    omp_set_num_threads(1);
    const Eigen::VectorXcd one = ours.solve(b);
    omp_set_num_threads(2);
    const Eigen::VectorXcd two = ours.solve(b);
    EXPECT_EQ(one, two);
  }
  omp_set_num_threads(saved);
#else
  GTEST_SKIP() << "no OpenMP: one thread only";
#endif
}

TEST(ComplexSupernodal, SinglePrecisionKernelRefused) {
  const ComplexSparseMatrix A = vector_heat_matrix(intrinsic::icosphere(2), 1);
  EXPECT_THROW(ComplexCholeskySolver(A, complex_kernel_options(Kernel::kSupernodalSingle)),
               InvalidInput);
}

}  // namespace
}  // namespace ifem::solvers
