// Triangular solves with a supernodal Cholesky factor held in our own arrays, in double or single
// precision, over two independent halves of the elimination tree on two threads (internal to
// solvers/; CholeskySolver uses it when CholeskyOptions::solve_kernel asks for it).
#pragma once

#include <Eigen/Core>
#include <complex>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

namespace ifem::solvers {

/// The sparsity of a supernodal factor L with P A Pᵀ = L Lᵀ, in CHOLMOD's layout: supernode s
/// holds columns [super[s], super[s+1]) as one dense column-major block of
/// (row_start[s+1] − row_start[s]) rows × (super[s+1] − super[s]) columns, starting at
/// value_start[s] in the values; its row indices, ascending and its own columns first, are
/// rows[row_start[s] ..]. Supernodes are numbered in a postorder of the elimination tree (as
/// CHOLMOD's analysis with postordering leaves them), so every subtree is a contiguous range.
struct SupernodalPattern {
  Eigen::Index n = 0;                     ///< matrix size
  std::vector<int> perm;                  ///< n: row k of P A Pᵀ is row perm[k] of A
  std::vector<int> super;                 ///< #supernodes + 1
  std::vector<std::int64_t> row_start;    ///< #supernodes + 1, into rows
  std::vector<std::int64_t> value_start;  ///< #supernodes + 1, into the values
  std::vector<int> rows;                  ///< row indices of every supernode
};

/// Precision of the factor values the solves read (the right-hand sides, the solution and every
/// sum stay in double).
enum class FactorPrecision {
  kDouble,  ///< 8 bytes per factor entry
  kSingle,  ///< 4 bytes per entry: a float copy (half the memory traffic; relative rounding
            ///< 6e-8 in each entry, see CholeskyOptions::solve_kernel)
};

/// Forward and backward substitution with a supernodal factor. The elimination tree is split
/// once, at construction, into a top and two bins of disjoint subtrees of nearly equal
/// work; a solve of k columns runs the bins when the work is large (entries × k ≥
/// kParallelEntries), on two threads unless the caller is itself one of run_parallel()'s jobs,
/// else in one pass in column order; the top, after the bins, runs two halves of the columns
/// side by side when its own work is that large too. The choices depend on the factor and k
/// only, so results are bitwise the same with one thread or two (but a column may round
/// differently alone than in a block: the bins sum the top's updates in another order).
/// solve() is const and may run concurrently from several threads.
class SupernodalSolver {
 public:
  /// Solves with entries × columns at least this large run the two bins (smaller ones are
  /// solved in one pass in column order: a thread start costs more than the work there).
  static constexpr std::int64_t kParallelEntries = 2'000'000;

  /// Copies the factor values (value_start.back() doubles at `values`) in the given precision.
  /// @throws InvalidInput if the pattern is inconsistent (sizes, ranges, not postordered)
  SupernodalSolver(SupernodalPattern pattern, const double* values, FactorPrecision precision);
  /// In double precision on the values at `values` themselves (value_start.back() doubles),
  /// taking them over instead of copying (no second copy of the factor while it is handed
  /// over): the solver frees them with release(values) when it is destroyed. On a throw the
  /// values are not taken (the caller still owns them).
  /// @throws InvalidInput as above, or if values or release is null
  static SupernodalSolver adopt(SupernodalPattern pattern, double* values, void (*release)(void*));
  ~SupernodalSolver();
  SupernodalSolver(SupernodalSolver&&) noexcept;
  SupernodalSolver& operator=(SupernodalSolver&&) noexcept;

  /// Solves A X = B for `cols` columns stored column-major at b (n × cols) into x (may alias b).
  void solve(const double* b, double* x, Eigen::Index cols) const;
  /// Solves A X = B in place for `cols` columns stored row-major at X (n × cols: row i, the
  /// cols values of unknown i, is contiguous): the kernel's own layout, so only the rows'
  /// permutation is copied (solve() also transposes). The same bits as solve() for cols > 1.
  void solve_rows(double* X, Eigen::Index cols) const;
  /// The factor's row order: row i of P A Pᵀ is row permutation()[i] of A (n entries).
  const std::vector<int>& permutation() const;
  /// solve_rows() on a block already in the factor's row order (row i of W, cols values, is
  /// unknown permutation()[i]): no row copies in or out, for a caller that keeps its block in
  /// that order across several solves. source_rows (cols entries, or null): point sources,
  /// column j of W zero but in row source_rows[j]; the forward pass then runs each supernode on
  /// the columns whose source lies in its subtree only (the same values), which saves most when
  /// the columns are in the order of their rows (a subtree's sources are then adjacent).
  /// shift_rows (n values in the factor's order) and shift_sums (cols values), both or neither:
  /// solves for W − shift_rows·shift_sumsᵀ instead of W, the rank-one term subtracted from each
  /// row as the forward pass reaches it (no sweep of the block of its own); source_rows is then
  /// ignored (every row is nonzero).
  void solve_rows_in_factor_order(double* W, Eigen::Index cols, const int* source_rows = nullptr,
                                  const double* shift_rows = nullptr,
                                  const double* shift_sums = nullptr) const;

  /// Bytes one pass over the factor reads (values and row indices): a solve makes two passes.
  std::size_t bytes_per_pass() const;
  /// Number of stored factor entries (with CHOLMOD's supernodal padding).
  std::int64_t entries() const;
  /// True when a solve of `cols` columns runs the two bins (entries × cols ≥ kParallelEntries,
  /// and a postordered tree).
  bool split(Eigen::Index cols = 1) const;
  /// Share of the factor's entries in the serial top of the tree (0 without a split).
  double top_share() const;

  struct Impl;

 private:
  SupernodalSolver() = default;
  void init(SupernodalPattern pattern, const double* values, FactorPrecision precision,
            double* owned, void (*release)(void*));
  std::unique_ptr<Impl> impl_;
};

/// Forward and backward substitution with a complex supernodal factor, P A Pᵀ = L Lᴴ (A Hermitian
/// positive definite), in the layout of SupernodalPattern with complex values (CHOLMOD's complex
/// supernodal factor: interleaved (re, im) pairs, a real positive diagonal). The values are read
/// where they are, not copied: the caller keeps them alive and unchanged while the solver lives.
/// The elimination tree is split as SupernodalSolver's; a solve whose factor is large (entries ≥
/// SupernodalSolver::kParallelEntries / 2, postordered) runs the backward pass, and a dense
/// forward pass, over the two bins on two threads (unless the caller is itself one of
/// run_parallel()'s jobs); a right-hand side whose nonzero rows reach less than half of the
/// factor (point sources) runs its forward pass on those rows' supernodes and their ancestors
/// only. The choices depend on the factor and the right-hand side's nonzero rows only, so
/// results are bitwise the same with one thread or two. solve() is const and may run
/// concurrently from several threads.
class ComplexSupernodalSolver {
 public:
  /// @param values value_start.back() complex entries, viewed (not copied)
  /// @throws InvalidInput if the pattern is inconsistent (sizes, ranges, a parent before its
  ///         child)
  ComplexSupernodalSolver(SupernodalPattern pattern, const std::complex<double>* values);
  ~ComplexSupernodalSolver();
  ComplexSupernodalSolver(ComplexSupernodalSolver&&) noexcept;
  ComplexSupernodalSolver& operator=(ComplexSupernodalSolver&&) noexcept;

  /// Solves A X = B for `cols` columns stored column-major at b (n × cols) into x (may alias b),
  /// one column after the other.
  void solve(const std::complex<double>* b, std::complex<double>* x, Eigen::Index cols) const;
  /// Bytes one pass over the factor reads (values and row indices): a solve makes two passes.
  std::size_t bytes_per_pass() const;
  /// True when a solve runs its backward pass over the two bins.
  bool split() const;

  struct Impl;

 private:
  std::unique_ptr<Impl> impl_;
};

}  // namespace ifem::solvers
