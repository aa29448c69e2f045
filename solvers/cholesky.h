// Sparse Cholesky factorization (CHOLMOD supernodal LL', AMD ordering) behind a small class:
// factor once, solve many. CHOLMOD stays private to cholesky.cpp.
#pragma once

#include <memory>

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include "fem/operators.h"

namespace ifem::solvers {

/// Options of CholeskySolver.
struct CholeskyOptions {
  /// Force AMD ordering (CHOLMOD nmethods = 1). METIS, CHOLMOD's default choice on large
  /// matrices, costs more in analysis than it saves here (see DEPENDENCIES.md).
  bool force_amd = true;
  /// Supernodal factorization (fast with an optimized BLAS); false = simplicial.
  bool supernodal = true;
  /// A factor whose reciprocal condition estimate (CHOLMOD's (min diag / max diag)² of L) is
  /// below this is reported as numerically singular (SolverError).
  double min_rcond = 1e-12;
  void validate() const {}
};

/// Cholesky factorization A = LLᵀ of a sparse symmetric positive definite matrix.
///
/// Only the lower triangle of A is read (the matrix is assumed symmetric). The symbolic
/// analysis is kept, so refactor() with a matrix of the same sparsity pattern only redoes the
/// numeric part. Non-copyable, movable. solve() is const and may be called from several
/// threads (calls are serialized internally).
class CholeskySolver {
 public:
  /// Analyzes and factors A (#n×#n).
  /// @throws InvalidInput if A is not square, is empty or has a non-finite entry
  /// @throws SolverError if A is not positive definite (naming the failing column) or CHOLMOD
  ///         fails (out of memory, ...)
  explicit CholeskySolver(const fem::SparseMatrix& A, const CholeskyOptions& options = {});
  ~CholeskySolver();
  CholeskySolver(CholeskySolver&&) noexcept;
  CholeskySolver& operator=(CholeskySolver&&) noexcept;
  CholeskySolver(const CholeskySolver&) = delete;
  CholeskySolver& operator=(const CholeskySolver&) = delete;

  /// Numeric refactorization of a matrix with the same size and sparsity pattern.
  /// On failure the solver keeps its previous factor (strong guarantee).
  /// @throws InvalidInput if the pattern differs; SolverError as the constructor
  void refactor(const fem::SparseMatrix& A);

  /// Solves A x = b. @param b #n  @throws InvalidInput on a size mismatch
  Eigen::VectorXd solve(const Eigen::VectorXd& b) const;
  /// Solves A X = B for every column of B (#n×k) at once.
  Eigen::MatrixXd solve(const Eigen::MatrixXd& B) const;

  /// Size n of the factored matrix.
  Eigen::Index size() const;
  /// Number of nonzeros in the factor L (after supernodal padding).
  double factor_nonzeros() const;

 /// Internal state (CHOLMOD common + factor); defined in cholesky.cpp only.
  struct Impl;

 private:
  std::unique_ptr<Impl> impl_;
};

}  // namespace ifem::solvers
