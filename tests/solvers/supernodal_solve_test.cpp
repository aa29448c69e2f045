// Our supernodal solve kernel (solvers/linalg/supernodal_solve.h) through CholeskySolver: the same
// solutions as CHOLMOD's solve, single precision within its rounding, a point source's sparse
// forward pass equal to the full one, and results bitwise independent of the thread count.
#include "solvers/linalg/supernodal_solve.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <string>
#include <vector>

#ifdef _OPENMP
#include <omp.h>
#endif

#include "fem/operators.h"
#include "intrinsic/core/errors.h"
#include "solvers/linalg/cholesky.h"
#include "solvers/linalg/cholesky_blocks.h"
#include "test_util.h"

namespace ifem::solvers {
namespace {

using Kernel = CholeskyOptions::SolveKernel;

// M + L of an icosphere with `n` subdivisions (positive definite; n = 50: 2.4M factor entries,
// enough for the two-bin split).
fem::SparseMatrix mass_plus_laplacian(int n) {
  const auto tri = test::make_tri(intrinsic::icosphere(n));
  fem::SparseMatrix A = fem::cotan_laplacian(tri);
  const Eigen::VectorXd m = fem::lumped_mass(tri);
  for (Eigen::Index i = 0; i < A.rows(); ++i) A.coeffRef(i, i) += m[i];
  A.makeCompressed();
  return A;
}

CholeskyOptions kernel_options(Kernel kernel) {
  CholeskyOptions o;
  o.solve_kernel = kernel;
  return o;
}

// Sets OpenMP's thread count (the library's only threads): n, or the default for n = 0.
void set_threads(int n) {
#ifdef _OPENMP
  static const int default_threads = omp_get_max_threads();
  omp_set_num_threads(n > 0 ? n : default_threads);
#else
  (void)n;
#endif
}

// Relative max-norm difference.
double rel_diff(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  return (a - b).cwiseAbs().maxCoeff() / b.cwiseAbs().maxCoeff();
}

// Solves with 1 and with 2 threads; both must agree bit for bit.
Eigen::MatrixXd solve_with_threads(const CholeskySolver& chol, const Eigen::MatrixXd& B,
                                   int threads) {
  set_threads(threads);
  Eigen::MatrixXd X = chol.solve(B);
  set_threads(0);
  return X;
}

void expect_same_as_cholmod(int subdivisions) {
  const fem::SparseMatrix A = mass_plus_laplacian(subdivisions);
  const CholeskySolver reference(A);
  const Eigen::MatrixXd X0 = Eigen::MatrixXd::Random(A.rows(), 5);
  const Eigen::MatrixXd B = A * X0;
  const Eigen::MatrixXd Xr = reference.solve(B);
  for (const Kernel kernel : {Kernel::kSupernodalDouble, Kernel::kSupernodalSingle}) {
    const CholeskySolver chol(A, kernel_options(kernel));
    const bool single = kernel == Kernel::kSupernodalSingle;
    const Eigen::MatrixXd X1 = solve_with_threads(chol, B, 1);
    const Eigen::MatrixXd X2 = solve_with_threads(chol, B, 2);
    EXPECT_TRUE(X1 == X2) << "thread count changed the result";  // bitwise
    EXPECT_LT(rel_diff(X1, Xr), single ? 1e-5 : 1e-12);
    // column by column (one right-hand side at a time) gives the same numbers
    const Eigen::VectorXd x3 = chol.solve(Eigen::VectorXd(B.col(3)));
    EXPECT_LT(rel_diff(x3, Xr.col(3)), single ? 1e-5 : 1e-12);
    // single precision halves the value bytes: a solve reads less than 2/3 of the double one
    EXPECT_LT(chol.solve_bytes(),
              (single ? 0.67 : 1.01) *
                  CholeskySolver(A, kernel_options(Kernel::kSupernodalDouble)).solve_bytes());
  }
}

TEST(SupernodalSolve, SmallFactorMatchesCholmod) { expect_same_as_cholmod(6); }

TEST(SupernodalSolve, SplitFactorMatchesCholmodAndIsThreadIndependent) {
  expect_same_as_cholmod(50);
}

// chol.solve_rows() of B (column-major here) on one thread and on two: expects the same bits,
// returns the solution.
Eigen::MatrixXd solve_rows_on_one_and_two_threads(const CholeskySolver& chol,
                                                  const Eigen::MatrixXd& B) {
  using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  RowMajor X[2] = {B, B};
  for (const int threads : {1, 2}) {
    set_threads(threads);
    chol.solve_rows(X[threads - 1].data(), B.cols());
  }
  set_threads(0);
  EXPECT_TRUE(X[0] == X[1]) << "thread count changed the result, k = " << B.cols();
  return X[0];
}

// solve_rows(), the kernel's own layout, for every chunk width of its small-supernode loops
// (8, 4, 2, 1 columns) on a factor with the two-bin split: CHOLMOD's solution, the same bits as
// the column-major solve (which goes through it) and the same bits on one thread or two; and
// CHOLMOD's own solve through solve_rows()'s transposed copy.
TEST(SupernodalSolve, RowsLayoutEveryChunkWidth) {
  using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  const fem::SparseMatrix A = mass_plus_laplacian(50);
  const CholeskySolver reference(A);
  for (const Kernel kernel : {Kernel::kSupernodalDouble, Kernel::kSupernodalSingle}) {
    const CholeskySolver chol(A, kernel_options(kernel));
    const bool single = kernel == Kernel::kSupernodalSingle;
    for (const int k : {2, 3, 7, 8, 15, 16, 24, 32, 33}) {
      std::srand(unsigned(k));
      const Eigen::MatrixXd B = A * Eigen::MatrixXd::Random(A.rows(), k);
      const Eigen::MatrixXd Xr = reference.solve(B);
      const Eigen::MatrixXd X0 = solve_rows_on_one_and_two_threads(chol, B);
      EXPECT_LT(rel_diff(X0, Xr), single ? 1e-5 : 1e-12) << "k = " << k;
      EXPECT_TRUE(X0 == chol.solve(B)) << "k = " << k;
    }
  }
  // CHOLMOD's factor: our kernel over it for several columns (RowsOverCholmodSimplicialFactor),
  // CHOLMOD's own solve for one
  const Eigen::MatrixXd B = Eigen::MatrixXd::Random(A.rows(), 3);
  RowMajor X = B;
  reference.solve_rows(X.data(), 3);
  EXPECT_LT(rel_diff(Eigen::MatrixXd(X), reference.solve(B)), 1e-12);
  Eigen::VectorXd x = B.col(0);
  reference.solve_rows(x.data(), 1);
  EXPECT_TRUE(x == reference.solve(Eigen::VectorXd(B.col(0))));
  EXPECT_THROW(reference.solve_rows(X.data(), -1), InvalidInput);
}

// A column's bits do not depend on which chunk kernel solves it: the kernels for 32 and 16
// columns at once (AVX-512 hosts) and the chunks of 8 run the same operations per column. In one
// solve (one split of the tree, one order of the bins' sums) of a block whose later columns
// repeat its first ones, the repeats go through other kernels and must come out bitwise equal:
// k = 48 puts columns 0–15 again at 32–47 (16 at once), k = 40 puts 8–15 again at 32–39 (a chunk
// of 8). (Narrower chunks are not compared: without AVX-512, supernodes over 64 columns go
// through BLAS, whose rounding may depend on the number of columns.)
TEST(SupernodalSolve, ColumnBitsDoNotDependOnTheKernel) {
  const fem::SparseMatrix A = mass_plus_laplacian(50);
  for (const Kernel kernel : {Kernel::kSupernodalDouble, Kernel::kSupernodalSingle}) {
    const CholeskySolver chol(A, kernel_options(kernel));
    std::srand(7u);
    const Eigen::MatrixXd R = A * Eigen::MatrixXd::Random(A.rows(), 32);
    Eigen::MatrixXd B48(A.rows(), 48), B40(A.rows(), 40);
    B48 << R, R.leftCols(16);
    B40 << R, R.middleCols(8, 8);
    const Eigen::MatrixXd X48 = solve_rows_on_one_and_two_threads(chol, B48);
    EXPECT_TRUE(X48.rightCols(16) == X48.leftCols(16)) << "16 at once against 32";
    const Eigen::MatrixXd X40 = solve_rows_on_one_and_two_threads(chol, B40);
    EXPECT_TRUE(X40.rightCols(8) == X40.middleCols(8, 8)) << "a chunk of 8 against 32";
    EXPECT_TRUE(X40.leftCols(32) == X48.leftCols(32)) << "the same 32 columns, other blocks";
    // and the block is solved: A X = B
    EXPECT_LT((A * X48 - B48).norm() / B48.norm(),
              kernel == Kernel::kSupernodalSingle ? 1e-5 : 1e-12);
  }
}

// Where CHOLMOD holds a simplicial factor, solve_rows() with several columns runs our kernel over
// it (consecutive columns with nested patterns as dense supernodes, built on the first call):
// equal to CHOLMOD's column solve, the same bits on 1 and 2 threads, and rebuilt by refactor().
TEST(SupernodalSolve, RowsOverCholmodSimplicialFactor) {
  using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  const fem::SparseMatrix A = mass_plus_laplacian(50);
  CholeskyOptions from_start;  // a simplicial numeric factorization (else: converted to one)
  from_start.simplicial_below_flops_per_entry = 1e9;
  for (const CholeskyOptions& o : {CholeskyOptions{}, from_start}) {
    CholeskySolver chol(A, o);
    for (const int k : {2, 3, 8, 33}) {
      std::srand(unsigned(k));
      const Eigen::MatrixXd B = A * Eigen::MatrixXd::Random(A.rows(), k);
      const Eigen::MatrixXd Xc = chol.solve(B);
      const Eigen::MatrixXd X0 = solve_rows_on_one_and_two_threads(chol, B);
      EXPECT_LT(rel_diff(X0, Xc), 1e-12) << "k = " << k;
    }
    // new values, the same pattern: the block kernel must follow (2A: half the solution)
    chol.refactor(2.0 * A);
    const Eigen::MatrixXd B = A * Eigen::MatrixXd::Random(A.rows(), 5);
    RowMajor X = B;
    chol.solve_rows(X.data(), 5);
    EXPECT_LT(rel_diff(Eigen::MatrixXd(X), 0.5 * CholeskySolver(A).solve(B)), 1e-12);
  }
}

// A block already in the kernel's row order (block_order()) solves without row copies to the
// same bits as solve_rows(), on our own factor and on the copy over CHOLMOD's. Given point
// sources (source_rows), the forward pass runs each supernode on the columns whose source lies
// below it: the same values, for sources in row order (narrow ranges) and in any order, on a
// factor solved in one pass and on one split into two bins; and a rank-one term subtracted from
// the right-hand sides by the forward pass gives the solution for the subtracted ones.
TEST(SupernodalSolve, RowsInBlockOrder) {
  using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  for (const int subdivisions : {12, 50}) {
    const fem::SparseMatrix A = mass_plus_laplacian(subdivisions);
    const Index n = Index(A.rows());
    for (const Kernel kernel : {Kernel::kSupernodalDouble, Kernel::kCholmod}) {
      const CholeskySolver chol(A, kernel_options(kernel));
      const std::vector<int>* order = CholeskyBlocks::block_order(chol);
      ASSERT_NE(order, nullptr);
      std::vector<int> position(static_cast<std::size_t>(n));
      for (Index i = 0; i < n; ++i) position[std::size_t((*order)[std::size_t(i)])] = int(i);
      for (const int sources : {0, 1, 2}) {  // dense; point sources in any order; in row order
        const int k = 13;
        RowMajor B = RowMajor::Zero(n, k);
        std::vector<int> source_row(static_cast<std::size_t>(k));
        if (sources == 0) {
          std::srand(7u);
          B = Eigen::MatrixXd::Random(n, k);
        }
        for (int j = 0; sources > 0 && j < k; ++j) {
          const Index v =
              sources == 1 ? Index((j * 7919 + 5) % n) : (*order)[std::size_t(j * n / k)];
          B(v, j) = 1.0;
          source_row[std::size_t(j)] = position[std::size_t(v)];
        }
        RowMajor expected = B;
        chol.solve_rows(expected.data(), k);
        RowMajor W(n, k);
        for (Index i = 0; i < n; ++i) W.row(i) = B.row((*order)[std::size_t(i)]);
        CholeskyBlocks::solve_in_block_order(chol, W.data(), k,
                                             sources ? source_row.data() : nullptr);
        RowMajor X(n, k);
        for (Index i = 0; i < n; ++i) X.row((*order)[std::size_t(i)]) = W.row(i);
        const std::string what =
            "n = " + std::to_string(n) + ", sources " + std::to_string(sources);
        if (sources == 0) {
          EXPECT_TRUE(X == expected) << what;
        } else {
          EXPECT_LT(rel_diff(X, expected), 1e-13) << what;
        }
      }
      // a rank-one term folded into the forward pass: the solution for W − rows·sumsᵀ
      const int k = 9;
      std::srand(11u);
      const RowMajor B = Eigen::MatrixXd::Random(n, k);
      const Eigen::VectorXd rows = Eigen::VectorXd::Random(n);
      const Eigen::RowVectorXd sums = Eigen::RowVectorXd::Random(k);
      RowMajor expected = B - rows * sums;
      chol.solve_rows(expected.data(), k);
      RowMajor W(n, k);
      for (Index i = 0; i < n; ++i) W.row(i) = B.row((*order)[std::size_t(i)]);
      Eigen::VectorXd rows_in_order(n);
      for (Index i = 0; i < n; ++i) rows_in_order[i] = rows[(*order)[std::size_t(i)]];
      CholeskyBlocks::solve_in_block_order(chol, W.data(), k, nullptr, rows_in_order.data(),
                                           sums.data());
      RowMajor X(n, k);
      for (Index i = 0; i < n; ++i) X.row((*order)[std::size_t(i)]) = W.row(i);
      EXPECT_LT(rel_diff(X, expected), 1e-12) << "rank-one term, n = " << n;
      double x = 0.0;
      EXPECT_THROW(CholeskyBlocks::solve_in_block_order(chol, &x, 1), InvalidInput);
    }
  }
}

// A factor built by hand: two dense w-column supernodes (leaves) under a one-column root, so
// that the split puts one leaf in each bin and only the root in the serial top.
struct TwoLeafFactor {
  SupernodalPattern pattern;
  std::vector<double> values;
  Eigen::MatrixXd dense;  // the same L, dense (identity permutation)
};

TwoLeafFactor two_leaf_factor(int w = 1000) {
  const int n = 2 * w + 1;
  TwoLeafFactor f;
  SupernodalPattern& p = f.pattern;
  p.n = n;
  p.perm.resize(n);
  for (int i = 0; i < n; ++i) p.perm[i] = i;
  p.super = {0, w, 2 * w, n};
  p.row_start = {0, w + 1, 2 * (w + 1), 2 * (w + 1) + 1};
  p.value_start = {0, Eigen::Index(w + 1) * w, 2 * Eigen::Index(w + 1) * w,
                   2 * Eigen::Index(w + 1) * w + 1};
  for (int leaf = 0; leaf < 2; ++leaf) {
    for (int r = 0; r < w; ++r) p.rows.push_back(leaf * w + r);
    p.rows.push_back(n - 1);
  }
  p.rows.push_back(n - 1);
  f.dense = Eigen::MatrixXd::Zero(n, n);
  for (int leaf = 0; leaf < 2; ++leaf) {
    for (int c = 0; c < w; ++c) {
      for (int r = 0; r <= w; ++r) {
        const int row = r < w ? leaf * w + r : n - 1;
        const double v = r < c ? 0.0 : r == c ? 2.0 : 0.3 * std::sin(1.0 + r + 7.0 * c);
        f.values.push_back(v);
        f.dense(row, leaf * w + c) = v;
      }
    }
  }
  f.values.push_back(3.0);
  f.dense(n - 1, n - 1) = 3.0;
  return f;
}

TEST(SupernodalSolve, TwoBinSplitOfAHandBuiltTree) {
  const TwoLeafFactor f = two_leaf_factor();
  const Eigen::MatrixXd X0 = Eigen::MatrixXd::Random(f.dense.rows(), 3);
  // B = L Lᵀ X0 as two products with L (n² work each; forming L Lᵀ is n³)
  const Eigen::MatrixXd B = f.dense * (f.dense.transpose() * X0);
  for (const FactorPrecision precision : {FactorPrecision::kDouble, FactorPrecision::kSingle}) {
    const SupernodalSolver solver(f.pattern, f.values.data(), precision);
    ASSERT_TRUE(solver.split());
    EXPECT_LT(solver.top_share(), 1e-5);  // the root's one entry
    Eigen::MatrixXd X1(B.rows(), B.cols()), X2(B.rows(), B.cols());
    set_threads(1);
    solver.solve(B.data(), X1.data(), B.cols());
    set_threads(2);
    solver.solve(B.data(), X2.data(), B.cols());
    set_threads(0);
    EXPECT_TRUE(X1 == X2);
    EXPECT_LT(rel_diff(X1, X0), precision == FactorPrecision::kSingle ? 1e-4 : 1e-10);
  }
  SupernodalPattern bad = f.pattern;
  bad.super.back() = 7;
  EXPECT_THROW(SupernodalSolver(bad, f.values.data(), FactorPrecision::kDouble), InvalidInput);
}

// A factor below the split's size for one column (80,401 entries) runs the bins for a block of
// columns (entries × columns ≥ kParallelEntries): from 25 columns on here. A block split so
// solves correctly, with the same bits on one thread or two.
TEST(SupernodalSolve, BlocksOfColumnsRunTheBinsOfASmallFactor) {
  const TwoLeafFactor f = two_leaf_factor(200);
  const SupernodalSolver solver(f.pattern, f.values.data(), FactorPrecision::kDouble);
  ASSERT_EQ(solver.entries(), 80'401);
  for (const Eigen::Index k : {1, 24, 25, 32}) {
    EXPECT_EQ(solver.split(k), k >= 25) << "k = " << k;
  }
  const Eigen::MatrixXd X0 = Eigen::MatrixXd::Random(f.dense.rows(), 32);
  const Eigen::MatrixXd B = f.dense * (f.dense.transpose() * X0);
  Eigen::MatrixXd X[2];
  for (const int threads : {1, 2}) {
    using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
    RowMajor R = B;
    set_threads(threads);
    solver.solve_rows(R.data(), 32);
    X[threads - 1] = R;
  }
  set_threads(0);
  EXPECT_TRUE(X[0] == X[1]);
  EXPECT_LT(rel_diff(X[0], X0), 1e-10);
}

TEST(SupernodalSolve, PointSourceForwardPassEqualsTheFullOne) {
  const fem::SparseMatrix A = mass_plus_laplacian(50);
  const CholeskySolver reference(A);
  const CholeskySolver chol(A, kernel_options(Kernel::kSupernodalDouble));
  for (const Eigen::Index v : {Eigen::Index(0), A.rows() / 2, A.rows() - 1}) {
    const Eigen::VectorXd e = Eigen::VectorXd::Unit(A.rows(), v);
    const Eigen::VectorXd x = chol.solve(e);
    EXPECT_LT(rel_diff(x, reference.solve(e)), 1e-12) << "source " << v;
    // a dense right-hand side that differs from e only far below its size takes the full pass
    Eigen::VectorXd dense = e;
    dense.array() += 1e-300;
    EXPECT_LT(rel_diff(chol.solve(dense), x), 1e-12);
  }
}

TEST(SupernodalSolve, SplitShareAndRefactor) {
  fem::SparseMatrix A = mass_plus_laplacian(50);
  CholeskySolver chol(A, kernel_options(Kernel::kSupernodalSingle));
  // refactor() hands the new values to the kernel too
  for (Eigen::Index k = 0; k < A.nonZeros(); ++k) A.valuePtr()[k] *= 2.0;
  chol.refactor(A);
  const Eigen::VectorXd x0 = Eigen::VectorXd::LinSpaced(A.rows(), -1.0, 1.0);
  EXPECT_LT(rel_diff(chol.solve(Eigen::VectorXd(A * x0)), x0), 1e-5);
}

TEST(SupernodalSolve, RejectsASimplicialFactorization) {
  CholeskyOptions o = kernel_options(Kernel::kSupernodalDouble);
  o.supernodal = false;
  EXPECT_THROW(o.validate(), InvalidInput);
}

}  // namespace
}  // namespace ifem::solvers
