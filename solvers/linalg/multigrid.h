// Algebraic multigrid on a given hierarchy: Galerkin coarse operators PᵀAP from caller-supplied
// prolongations, V-cycles (symmetric Gauss–Seidel or damped Jacobi smoothing, a Cholesky solve on
// the coarsest level) as the preconditioner of conjugate gradients. Matrices only: where the
// prolongations come from (intrinsic simplification, nested meshes) is the caller's business.
#pragma once

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <memory>
#include <vector>

#include "solvers/linalg/cholesky.h"

namespace ifem::solvers {

/// P (#n×m) with row i moved to row new_row[i] (#n entries; −1: row dropped) of a rows×m
/// matrix, column by column (no triplets). new_row must increase over the rows it keeps (the
/// rows then stay sorted in each column), and each kept target must be < rows.
SparseMatrix renumber_rows(const SparseMatrix& P, const std::vector<int>& new_row,
                           Eigen::Index rows);

/// Options of MultigridSolver.
struct MultigridOptions {
  /// The smoother of every level but the coarsest (pre- and post-smoothing, arranged so that a
  /// V-cycle is a symmetric operator, as conjugate gradients needs).
  enum class Smoother {
    /// Forward Gauss–Seidel sweeps before the coarse correction, backward sweeps after.
    kSymmetricGaussSeidel,
    /// Damped Jacobi sweeps x ← x + ω D⁻¹ r (ω = jacobi_weight), the same number before and after.
    kJacobi,
  };
  Smoother smoother = Smoother::kSymmetricGaussSeidel;
  /// Sweeps before and after the coarse correction on each level. ≥ 1.
  int smoothing_steps = 1;
  /// ω of kJacobi, in (0, 1].
  double jacobi_weight = 2.0 / 3.0;
  /// Conjugate gradients stop when ‖b − Ax‖₂ ≤ tolerance · ‖b‖₂ (relative residual). In (0, 1).
  double tolerance = 1e-10;
  /// Largest number of PCG iterations per right-hand side. ≥ 1.
  int max_iterations = 200;
  /// A right-hand side that does not reach the tolerance within max_iterations throws
  /// SolverError when true; when false its last iterate is returned and the report says so.
  bool throw_if_not_converged = true;
  /// Options of the coarsest level's Cholesky factorization.
  CholeskyOptions coarsest;
  /// @throws InvalidInput naming the field
  void validate() const;
};

/// What one PCG solve (one right-hand side) did.
struct MultigridReport {
  int iterations = 0;                ///< PCG iterations (one V-cycle each)
  double relative_residual = 0.0;    ///< ‖b − Ax‖₂ / ‖b‖₂ at the end (0 for b = 0)
  double reduction_per_cycle = 0.0;  ///< geometric mean of the residual reduction per iteration
  bool converged = false;            ///< relative_residual ≤ tolerance
};

/// Multigrid-preconditioned conjugate gradients for A x = b, A (#n×#n) symmetric positive
/// definite, on the hierarchy given by prolongations P₀ (#n×n₁), P₁ (n₁×n₂), …, P_{k−1}: level
/// l+1's operator is A_{l+1} = P_lᵀ A_l P_l (Galerkin), the coarsest one is factored (Cholesky).
/// A is given with both triangles or as its lower triangle (Stored); every level is kept as its
/// lower triangle (docs/decisions.md D-335). Columns of a P_l with no entry (e.g. coarse vertices
/// whose fine neighbours are all eliminated Dirichlet rows) are dropped, so that each coarse
/// operator stays definite.
///
/// Null space: A must be definite. A pure-Neumann Laplacian (constants in its kernel) is refused
/// where the coarsest factorization finds it singular (SolverError); pin a vertex or add mass
/// first (PoissonSolver pins one vertex per pure-Neumann component).
///
/// Thread safety: solve() and cycle() are const and allocate their own work vectors; several
/// threads may call them at once. Non-copyable, movable.
class MultigridSolver {
 public:
  /// What the constructor's A holds.
  enum class Stored {
    kBothTriangles,  ///< the whole symmetric matrix
    kLowerTriangle,  ///< its lower triangle only (what CHOLMOD reads), rows increasing per column
  };

  /// Builds the hierarchy and factors the coarsest level.
  /// @param A #n×#n, symmetric positive definite, stored as `stored` says
  /// @param prolongations P₀ … P_{k−1}, P_l with as many rows as level l has unknowns; k = 0
  ///        gives a one-level "multigrid", i.e. a Cholesky factorization of A
  /// @throws InvalidInput on bad options, a non-square or empty A, a non-finite entry, a lower
  ///         triangle with rows out of order, or a prolongation whose rows do not match its level
  /// @throws SolverError if a level's diagonal is not positive or the coarsest operator is not
  ///         positive definite
  MultigridSolver(const SparseMatrix& A, std::vector<SparseMatrix> prolongations,
                  const MultigridOptions& options = {}, Stored stored = Stored::kBothTriangles);
  /// As above, taking A's storage (A is left empty: Eigen 3.4's SparseMatrix has no move
  /// constructor, so this overload swaps instead of copying). Pass the prolongations as an
  /// rvalue too to hand them over.
  MultigridSolver(SparseMatrix&& A, std::vector<SparseMatrix> prolongations,
                  const MultigridOptions& options = {}, Stored stored = Stored::kBothTriangles);
  /// As above, with prolongations shared with the caller (e.g. one hierarchy behind several
  /// solvers): a P_l used as given is referenced, not copied; one whose rows or columns must
  /// change (columns dropped, or rows of the previous level's dropped columns) is copied first.
  /// fine_pattern: null, or another solver's fine_pattern() (e.g. M + tL and L of one
  /// triangulation): when A's lower triangle has exactly its pattern (size, column starts, rows)
  /// and there is at least one prolongation, this solver keeps A's values only and references
  /// that pattern (12 → 8 bytes an entry; docs/decisions.md D-365); else it is ignored.
  /// @throws InvalidInput also on a null prolongation
  MultigridSolver(SparseMatrix&& A, std::vector<std::shared_ptr<const SparseMatrix>> prolongations,
                  const MultigridOptions& options = {}, Stored stored = Stored::kBothTriangles,
                  std::shared_ptr<const SparseMatrix> fine_pattern = nullptr);
  /// A given as its lower triangle's values on another solver's fine_pattern() (so that A's
  /// index arrays are never allocated; docs/decisions.md D-365).
  /// @param values fine_pattern->nonZeros() values in its storage order (diagonal first)
  /// @throws InvalidInput on a null, non-square, empty or uncompressed pattern, a values count
  ///         that differs from its entries, a non-finite value, no prolongation, or as above
  /// @throws SolverError as above
  MultigridSolver(std::shared_ptr<const SparseMatrix> fine_pattern, std::vector<double>&& values,
                  std::vector<std::shared_ptr<const SparseMatrix>> prolongations,
                  const MultigridOptions& options = {});
  ~MultigridSolver();
  MultigridSolver(MultigridSolver&&) noexcept;
  MultigridSolver& operator=(MultigridSolver&&) noexcept;
  MultigridSolver(const MultigridSolver&) = delete;
  MultigridSolver& operator=(const MultigridSolver&) = delete;

  /// Solves A x = b by PCG from x = 0. @param b #n  @param[out] report optional
  /// @throws InvalidInput on a size mismatch; SolverError if not converged (see
  ///         MultigridOptions::throw_if_not_converged)
  Eigen::VectorXd solve(const Eigen::VectorXd& b, MultigridReport* report = nullptr) const;
  /// Solves A X = B column by column (#n×k), each column to the tolerance on its own.
  /// @param[out] reports optional, one per column
  Eigen::MatrixXd solve(const Eigen::MatrixXd& B,
                        std::vector<MultigridReport>* reports = nullptr) const;
  /// solve() for `cols` columns stored column-major at b (n×cols) into x (may alias b).
  void solve(const double* b, double* x, Eigen::Index cols = 1) const;

  /// One V-cycle from a zero initial guess: the preconditioner z = B r (B symmetric positive
  /// definite, B ≈ A⁻¹). As a stationary iteration x ← x + B(b − Ax) its residual reduction per
  /// cycle is the hierarchy's quality measure. @param r #n
  Eigen::VectorXd cycle(const Eigen::VectorXd& r) const;

  /// Size n of A.
  Eigen::Index size() const;
  /// Number of levels (prolongations + 1).
  int n_levels() const;
  /// Unknowns of level l (0 = A's), l in [0, n_levels()).
  Eigen::Index level_size(int level) const;
  /// The fine level's operator as stored (lower triangle, diagonal first), for its pattern: pass
  /// it as another solver's fine_pattern. Its values are this solver's unless this solver itself
  /// shares a pattern (then they are the owner's). Never null.
  std::shared_ptr<const SparseMatrix> fine_pattern() const;
  /// Bytes held: the operators (lower triangles) and prolongations of every level (values and
  /// indices; a prolongation shared with the caller counted in full) and the coarsest factor's
  /// entries (12 bytes each: value and row index); a fine level sharing another solver's pattern
  /// counts its values only.
  double memory_bytes() const;

  struct Impl;

 private:
  std::unique_ptr<Impl> impl_;
};

}  // namespace ifem::solvers
