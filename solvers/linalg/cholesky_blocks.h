// The heat method's block solves on a CholeskySolver's factor, in the solve kernel's own row
// order (internal: for solvers/scalar/poisson.cpp and its heat engine, and the tests of the
// kernel; not part of CholeskySolver's public API).
#pragma once

#include <Eigen/Core>
#include <vector>

namespace ifem::solvers {

class CholeskySolver;

/// Access to a CholeskySolver's supernodal kernel for blocks kept in the kernel's row order
/// across several solves (the heat method's queries: docs/decisions.md D-058). Defined in
/// cholesky.cpp.
struct CholeskyBlocks {
  /// The row order of CholeskySolver::solve_rows()'s blocks of two or more columns where they
  /// run our kernel (its own factor, or the copy over CHOLMOD's simplicial factor, built here if
  /// not yet): row i of a block in this order is unknown (*order)[i]. Null when blocks take
  /// another path. The vector lives until refactor() (the ordering itself never changes: one
  /// analysis).
  static const std::vector<int>* block_order(const CholeskySolver& chol);
  /// solve_rows() on a block W (n × cols, row-major) of `cols` ≥ 2 columns already in
  /// block_order() (non-null): no row copies. source_rows (cols entries, or null): point
  /// sources, column j zero but in row source_rows[j] of the block
  /// (SupernodalSolver::solve_rows_in_factor_order()). shift_rows (n, in block_order()) and
  /// shift_sums (cols): solve for W − shift_rows·shift_sumsᵀ, the rank-one term folded into the
  /// forward pass.
  /// @throws InvalidInput if block_order() is null or cols < 2
  static void solve_in_block_order(const CholeskySolver& chol, double* W, Eigen::Index cols,
                                   const int* source_rows = nullptr,
                                   const double* shift_rows = nullptr,
                                   const double* shift_sums = nullptr);
};

}  // namespace ifem::solvers
