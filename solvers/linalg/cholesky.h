// Sparse Cholesky factorization (CHOLMOD supernodal LL', AMD ordering) behind a small class:
// factor once, solve many; real symmetric (CholeskySolver) and complex Hermitian
// (ComplexCholeskySolver). CHOLMOD stays private to cholesky.cpp.
#pragma once

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <complex>
#include <memory>
#include <vector>

#include "solvers/linalg/blas_threads.h"

namespace ifem::solvers {

/// Real sparse matrix, column-major with 32-bit indices (the same type as SparseMatrix).
using SparseMatrix = Eigen::SparseMatrix<double, Eigen::ColMajor, int>;

/// Options of CholeskySolver.
struct CholeskyOptions {
  /// Force AMD ordering (CHOLMOD nmethods = 1) instead of CHOLMOD's default choice (METIS on
  /// large matrices). Why: docs/DEPENDENCIES.md, "Sparse Cholesky".
  bool force_amd = true;
  /// Force METIS nested dissection instead (takes precedence over force_amd). Its analysis costs
  /// ~2 s at 1M faces, more than its smaller fill saves on a real factor and on a complex one at
  /// one BLAS thread; it beats AMD only for a complex factor at two BLAS threads (measurements:
  /// docs/decisions.md, "Vector heat: complex Cholesky").
  bool force_metis = false;
  /// A fill-reducing ordering to use instead of computing one (takes precedence over both
  /// flags above): ordering[k] is the column eliminated k-th, a permutation of 0..n−1
  /// (CHOLMOD's given ordering; its elimination tree is still postordered). Why: the heat
  /// method runs AMD on L's pattern straight from the triangulation's edges, beside the assembly
  /// of L (PoissonSolver::analyze(tri); docs/decisions.md, "Small meshes: the analysis beside the
  /// assembly"). Empty (the default): order as the flags say.
  std::vector<int> ordering;
  /// Supernodal factorization (fast with an optimized BLAS); false = simplicial.
  bool supernodal = true;
  /// With supernodal = true and CHOLMOD's own solves: factor simplicially instead when the
  /// analysis predicts fewer than this many flops per factor entry (CHOLMOD's
  /// supernodal_switch), i.e. a factor with little fill, whose supernodes are too small for BLAS
  /// to pay. 0 = always supernodal (the default). Measured, analysis + factorization: spot
  /// (38 flops per entry) 2.6 ms simplicial / 3.7 ms supernodal, rocketship (48) 29 / 38 ms,
  /// icosphere(23) (91) 7.7 / 6.5 ms, icosphere(62) (226) 164 / 55 ms (docs/decisions.md, "Small
  /// meshes: simplicial factors below 64 flops per entry"). ≥ 0.
  double simplicial_below_flops_per_entry = 0.0;
  /// After a supernodal factorization of a real matrix, convert the factor to simplicial form
  /// for the solves (a supernodal solve calls BLAS once per, mostly small, supernode;
  /// measurements: docs/decisions.md, "Cholesky: simplicial solves, one BLAS thread").
  /// refactor() then runs a simplicial numeric factorization (slower; documented there).
  /// ComplexCholeskySolver ignores it: a complex factor stays supernodal, whose solves measured
  /// faster than simplicial ones and which skips the conversion's copy (docs/decisions.md,
  /// "Vector heat: complex Cholesky").
  bool simplicial_solves = true;
  /// Who runs the solves (of a complex factor: kCholmod, or kSupernodalDouble for
  /// ComplexSupernodalSolver reading CHOLMOD's supernodal factor in place, no copy):
  enum class SolveKernel {
    kCholmod,  ///< CHOLMOD's own, simplicial or supernodal as simplicial_solves says
    /// Our supernodal kernel (solvers/linalg/supernodal_solve.h) over the supernodal factor:
    /// in double precision CHOLMOD's values themselves, taken over (no copy), or a copy as
    /// floats (half the bytes per solve; each factor entry rounded to 6e-8 relative, so a solve's
    /// relative error grows to ~6e-8 × the condition number; what that means for the heat method:
    /// docs/decisions.md, "Heat queries: our supernodal solve kernel"). Large factors are solved
    /// over two halves of the elimination tree on two threads. CHOLMOD keeps only the symbolic
    /// factor. Needs supernodal = true.
    kSupernodalDouble,
    kSupernodalSingle,
  };
  SolveKernel solve_kernel = SolveKernel::kCholmod;
  /// A factor whose reciprocal condition estimate (CHOLMOD's (min diag / max diag)² of L,
  /// dimensionless) is below this is reported as numerically singular (SolverError). ≥ 0.
  double min_rcond = 1e-12;
  /// BLAS threads during the numeric factorization (OpenBLAS only, see BlasThreadScope):
  /// 0 = leave the process setting. Default 1: OpenBLAS's threaded kernels round differently
  /// from its one-thread ones (eigenvectors moved by 3e-12 between the CLI, which runs BLAS on
  /// one thread, and the Python module on two), surface factorizations are mostly small dense
  /// blocks where BLAS threads gain little (igea eigenpairs: the same time with 1 and 2), and
  /// factorizations side by side must not fight over the cores (docs/decisions.md, "Small
  /// meshes: one analysis, no threads below their size"). ≥ 0.
  int factor_blas_threads = 1;
  /// BLAS threads during solves: one right-hand side is a chain of small triangular solves and
  /// matrix–vector products, memory bound, where OpenBLAS's threads only add synchronization
  /// (docs/decisions.md, "Cholesky: simplicial solves, one BLAS thread"). 0 = leave the
  /// process setting. ≥ 0.
  int solve_blas_threads = 1;
  /// @throws InvalidInput if min_rcond is negative or NaN, a thread count is negative, or our
  ///         supernodal kernel is asked for without a supernodal factorization
  void validate() const;
};

/// AMD's fill-reducing ordering of the graph on nodes 0..n−1 with an edge {i, j} for every i in
/// index[start[j] .. start[j+1]) (each edge listed once or twice, in either list; self-loops and
/// repeats ignored; start has n + 1 entries, start[0] = 0): returns the permutation p with p[k]
/// = the node eliminated k-th, for CholeskyOptions::ordering. AMD's default controls (dense rows
/// above 10√n, aggressive absorption), as CHOLMOD's own AMD.
/// @throws InvalidInput if the lists are malformed (an index outside 0..n−1, start not
///         non-decreasing) or too long for 32-bit indices
std::vector<int> amd_ordering(int n, const std::vector<int>& start, const std::vector<int>& index);

/// The symbolic analysis of a sparse symmetric pattern (the fill-reducing ordering and the
/// factor's structure, CHOLMOD's cholmod_analyze), to share between CholeskySolvers of several
/// matrices with that pattern: the heat method factors M + tL and L, whose stored entries agree,
/// and the ordering (AMD) is a tenth of a small mesh's precompute (docs/decisions.md, "Small
/// meshes: one analysis, no threads below their size"). Immutable once built: several solvers
/// may be constructed from it at once, from different threads. Movable, not copyable.
class CholeskyAnalysis {
 public:
  /// Analyzes the pattern of A's lower triangle (the values are not read). Options as for
  /// CholeskySolver (ordering, supernodal); the solvers built from it take theirs from it.
  /// @throws InvalidInput if A is not square or is empty; SolverError if CHOLMOD fails
  explicit CholeskyAnalysis(const SparseMatrix& A, const CholeskyOptions& options = {});
  ~CholeskyAnalysis();
  CholeskyAnalysis(CholeskyAnalysis&&) noexcept;
  CholeskyAnalysis& operator=(CholeskyAnalysis&&) noexcept;
  CholeskyAnalysis(const CholeskyAnalysis&) = delete;
  CholeskyAnalysis& operator=(const CholeskyAnalysis&) = delete;

  /// Size n of the analyzed matrix.
  Eigen::Index size() const;

  /// Internal state (CHOLMOD common + symbolic factor + pattern); defined in cholesky.cpp only.
  struct Impl;

 private:
  std::unique_ptr<Impl> impl_;
  friend class CholeskySolver;
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
  /// @throws InvalidInput if A is not square, is empty or has a non-finite entry, or on bad
  ///         options (CholeskyOptions::validate())
  /// @throws SolverError if A is not positive definite (naming the failing column) or CHOLMOD
  ///         fails (out of memory, ...)
  explicit CholeskySolver(const SparseMatrix& A, const CholeskyOptions& options = {});
  /// Factors A with a shared symbolic analysis instead of analyzing it again: the ordering and
  /// the supernodal structure are the analysis's (its options' force_amd, force_metis and
  /// supernodal; the others are these options'). A factor equals the one of
  /// CholeskySolver(A, options) with that analysis options (same ordering, same operations).
  /// @throws InvalidInput if A's pattern (lower triangle, as stored) is not the analyzed one;
  ///         otherwise as the constructor above
  CholeskySolver(const SparseMatrix& A, const CholeskyAnalysis& analysis,
                 const CholeskyOptions& options = {});
  ~CholeskySolver();
  CholeskySolver(CholeskySolver&&) noexcept;
  CholeskySolver& operator=(CholeskySolver&&) noexcept;
  CholeskySolver(const CholeskySolver&) = delete;
  CholeskySolver& operator=(const CholeskySolver&) = delete;

  /// Numeric refactorization of a matrix with the same size and sparsity pattern (simplicial
  /// when the factor was converted for solves: simplicial_solves).
  /// On failure the solver keeps its previous factor (strong guarantee).
  /// @throws InvalidInput if the pattern differs; SolverError as the constructor
  void refactor(const SparseMatrix& A);

  /// Solves A x = b. @param b #n  @throws InvalidInput on a size mismatch
  Eigen::VectorXd solve(const Eigen::VectorXd& b) const;
  /// Solves A X = B for every column of B (#n×k) at once.
  Eigen::MatrixXd solve(const Eigen::MatrixXd& B) const;
  /// Solves A X = B for `cols` columns stored column-major at b (n×cols) into x (may alias b).
  /// No allocation after the first call with a given column count (CHOLMOD's workspace is kept).
  void solve(const double* b, double* x, Eigen::Index cols = 1) const;
  /// Solves A X = B in place for `cols` columns stored row-major at X (n×cols: the cols values
  /// of unknown i contiguous), the layout our supernodal kernel works in (no transposes). Where
  /// CHOLMOD holds the factor (SolveKernel::kCholmod): one column by CHOLMOD's solve; several by
  /// our kernel over CHOLMOD's simplicial LL' factor (consecutive columns with nested patterns as
  /// dense supernodes; a copy of the values built on the first such call under a lock, rebuilt
  /// after refactor()), or through a column-major copy for any other factor. Real factors only.
  /// @throws InvalidInput on a negative column count or a complex factor
  void solve_rows(double* X, Eigen::Index cols) const;

  /// Size n of the factored matrix.
  Eigen::Index size() const;
  /// Number of nonzeros in the factor L (after supernodal padding).
  double factor_nonzeros() const;
  /// Floating-point operations of the numeric factorization (CHOLMOD's estimate).
  double factor_flops() const;
  /// The fill-reducing ordering CHOLMOD used: "AMD", "METIS", "given" (CholeskyOptions::ordering,
  /// e.g. AMD run by PoissonSolver::analyze(tri)), "natural", ...
  const char* ordering() const;
  /// Bytes of factor data one solve with one right-hand side reads (values and row indices,
  /// forward and backward pass), for bandwidth figures (BENCHMARKS.md, "Heat queries").
  double solve_bytes() const;
  /// True when the numeric factorization ran supernodal (the stored factor may have been
  /// converted to simplicial form for faster solves, see simplicial_solves).
  bool supernodal() const;

  /// Internal state (CHOLMOD common + factor); defined in cholesky.cpp only.
  struct Impl;

 private:
  std::unique_ptr<Impl> impl_;
  friend struct CholeskyBlocks;  // the heat method's block solves (cholesky_blocks.h)
};

/// Complex sparse matrix (same type as fem::ComplexSparseMatrix).
using ComplexSparseMatrix = Eigen::SparseMatrix<std::complex<double>, Eigen::ColMajor, int>;

/// Cholesky factorization A = LLᴴ of a sparse Hermitian positive definite complex matrix (CHOLMOD
/// complex xtype: Eigen's interleaved (re, im) storage is passed through without a copy). Same
/// options and conventions as CholeskySolver: only the lower triangle of A is read (A is assumed
/// Hermitian), solve() is const (serialized internally with CHOLMOD's solves, concurrent with our
/// kernel's); the factor stays supernodal (simplicial_solves applies to real factors only).
/// solve_kernel: kCholmod or kSupernodalDouble (ComplexSupernodalSolver on the factor in place).
/// Why complex and not the real 2n×2n form [Re −Im; Im Re]: docs/decisions.md, "Vector heat:
/// complex Cholesky" (less than half the factor time and half the factor size).
class ComplexCholeskySolver {
 public:
  /// Analyzes and factors A (#n×#n).
  /// @throws InvalidInput if A is not square, is empty or has a non-finite entry, or on bad
  ///         options (also kSupernodalSingle: no float kernel for complex factors);
  ///         SolverError if A is not positive definite or CHOLMOD fails
  explicit ComplexCholeskySolver(const ComplexSparseMatrix& A, const CholeskyOptions& options = {});
  ~ComplexCholeskySolver();
  ComplexCholeskySolver(ComplexCholeskySolver&&) noexcept;
  ComplexCholeskySolver& operator=(ComplexCholeskySolver&&) noexcept;
  ComplexCholeskySolver(const ComplexCholeskySolver&) = delete;
  ComplexCholeskySolver& operator=(const ComplexCholeskySolver&) = delete;

  /// Solves A x = b. @param b #n  @throws InvalidInput on a size mismatch
  Eigen::VectorXcd solve(const Eigen::VectorXcd& b) const;
  /// Solves A X = B for every column of B (#n×k) at once.
  Eigen::MatrixXcd solve(const Eigen::MatrixXcd& B) const;

  /// Size n of the factored matrix.
  Eigen::Index size() const;
  /// Number of nonzeros in the factor L (complex entries, after supernodal padding).
  double factor_nonzeros() const;
  /// The fill-reducing ordering CHOLMOD used: "AMD", "METIS", ...
  const char* ordering() const;

 private:
  std::unique_ptr<CholeskySolver::Impl> impl_;
};

}  // namespace ifem::solvers
