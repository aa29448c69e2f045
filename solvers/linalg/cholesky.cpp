#include "solvers/linalg/cholesky.h"

#include <amd.h>
#include <cholmod.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <mutex>
#include <string>
#include <vector>

#ifdef _OPENMP
#include <omp.h>
#endif

#include "intrinsic/core/errors.h"
#include "solvers/linalg/cholesky_blocks.h"
#include "solvers/linalg/flush_denormals.h"
#include "solvers/linalg/supernodal_solve.h"

namespace ifem::solvers {

void CholeskyOptions::validate() const {
  if (!(min_rcond >= 0.0) || factor_blas_threads < 0 || solve_blas_threads < 0 ||
      !(simplicial_below_flops_per_entry >= 0.0) ||
      !std::isfinite(simplicial_below_flops_per_entry)) {
    throw InvalidInput(
        "CholeskyOptions: need min_rcond ≥ 0, BLAS thread counts ≥ 0 and a finite "
        "simplicial_below_flops_per_entry ≥ 0");
  }
  if (solve_kernel != SolveKernel::kCholmod && !supernodal) {
    throw InvalidInput("CholeskyOptions: the supernodal solve kernel needs supernodal = true");
  }
}

namespace {

// Frees factor values taken over from CHOLMOD, through SuiteSparse's own free (whatever
// allocator SuiteSparse_config holds).
void release_cholmod_values(void* values) { SuiteSparse_free(values); }

}  // namespace

namespace {

// CHOLMOD's parallel loops (clearing and assembling supernodes) ask OpenMP for a fixed team of
// CHOLMOD_OMP_NUM_THREADS = 4 threads whatever the core count, also when two factorizations
// run side by side: on two cores that is 8 spinning threads, and a factorization alone ran
// ~20% slower than with the loops serial (docs/decisions.md, "Cholesky: CHOLMOD's OpenMP loops
// serial"). This scope makes OpenMP regions started by the calling thread serial (the per-thread
// max-active-levels setting, OpenMP ≥ 5.0; CHOLMOD and the library share libgomp); a no-op in a
// build without OpenMP.
class SerialOpenMpScope {
 public:
  SerialOpenMpScope() {
#ifdef _OPENMP
    saved_ = omp_get_max_active_levels();
    if (saved_ != 0) omp_set_max_active_levels(0);
#endif
  }
  ~SerialOpenMpScope() {
#ifdef _OPENMP
    if (saved_ > 0) omp_set_max_active_levels(saved_);
#endif
  }
  SerialOpenMpScope(const SerialOpenMpScope&) = delete;
  SerialOpenMpScope& operator=(const SerialOpenMpScope&) = delete;

 private:
  int saved_ = -1;
};

// The pattern of CHOLMOD's numeric supernodal factor f (32-bit indices), for our kernels.
SupernodalPattern supernodal_pattern(const cholmod_factor* f) {
  const auto* super = static_cast<const int*>(f->super);
  const auto* pi = static_cast<const int*>(f->pi);
  const auto* px = static_cast<const int*>(f->px);
  const auto* perm = static_cast<const int*>(f->Perm);
  const std::size_t ns = f->nsuper;
  SupernodalPattern p;
  p.n = static_cast<Eigen::Index>(f->n);
  p.perm.assign(perm, perm + f->n);
  p.super.assign(super, super + ns + 1);
  p.row_start.assign(pi, pi + ns + 1);
  p.value_start.assign(px, px + ns + 1);
  p.rows.assign(static_cast<const int*>(f->s), static_cast<const int*>(f->s) + pi[ns]);
  return p;
}

}  // namespace

struct CholeskySolver::Impl {
  cholmod_common common;
  cholmod_factor* factor = nullptr;
  bool factored_supernodal = false;  // the numeric factorization ran supernodal
  Eigen::Index n = 0;
  std::vector<int> outer, inner;  // pattern of the analyzed matrix (for refactor checks)
  mutable std::mutex mutex;       // cholmod_common is not thread-safe
  int factor_blas_threads = 1, solve_blas_threads = 1;
  // cholmod_solve2 workspace, kept between solves (guarded by mutex)
  mutable cholmod_dense* X = nullptr;
  mutable cholmod_dense* Y = nullptr;
  mutable cholmod_dense* E = nullptr;
  // our supernodal kernel (CholeskyOptions::solve_kernel), holding the factor's values
  CholeskyOptions::SolveKernel kernel_kind = CholeskyOptions::SolveKernel::kCholmod;
  std::unique_ptr<SupernodalSolver> kernel;
  // a complex factor's kernel (SolveKernel::kSupernodalDouble): it reads CHOLMOD's values in
  // place, so the factor keeps them
  std::unique_ptr<ComplexSupernodalSolver> complex_kernel;
  // Without it: our kernel over CHOLMOD's simplicial factor for solve_rows() with several
  // columns, built on the first such call (rows_kernel_for_blocks()), dropped by refactor().
  mutable std::mutex rows_kernel_mutex;
  mutable bool rows_kernel_built = false;
  mutable std::unique_ptr<SupernodalSolver> rows_kernel;

  Impl() {
    cholmod_start(&common);
    common.print = 0;  // report through exceptions, never print
    common.error_handler = nullptr;
  }
  ~Impl() {
    if (X) cholmod_free_dense(&X, &common);
    if (Y) cholmod_free_dense(&Y, &common);
    if (E) cholmod_free_dense(&E, &common);
    if (factor) cholmod_free_factor(&factor, &common);
    cholmod_finish(&common);
  }

  int xtype = CHOLMOD_REAL;  // CHOLMOD_COMPLEX for ComplexCholeskySolver

  // A view of A's lower triangle as a cholmod_sparse (no copy): real, or complex with Eigen's
  // interleaved (re, im) storage, which is CHOLMOD_COMPLEX's.
  template <class Matrix>
  static cholmod_sparse view(const Matrix& A, int xtype) {
    cholmod_sparse s;
    std::memset(&s, 0, sizeof(s));
    s.nrow = static_cast<size_t>(A.rows());
    s.ncol = static_cast<size_t>(A.cols());
    s.nzmax = static_cast<size_t>(A.nonZeros());
    s.p = const_cast<int*>(A.outerIndexPtr());
    s.i = const_cast<int*>(A.innerIndexPtr());
    s.nz = const_cast<int*>(A.innerNonZeroPtr());
    s.x = const_cast<void*>(static_cast<const void*>(A.valuePtr()));
    s.stype = -1;  // symmetric (Hermitian), lower triangle used
    s.itype = CHOLMOD_INT;
    s.xtype = xtype;
    s.dtype = CHOLMOD_DOUBLE;
    s.sorted = 1;
    s.packed = A.isCompressed() ? 1 : 0;
    return s;
  }

  std::string status_text() const {
    switch (common.status) {
      case CHOLMOD_OUT_OF_MEMORY:
        return "out of memory";
      case CHOLMOD_TOO_LARGE:
        return "problem too large";
      case CHOLMOD_INVALID:
        return "invalid input";
      case CHOLMOD_GPU_PROBLEM:
        return "GPU problem";
      case CHOLMOD_NOT_POSDEF:
        return "not positive definite";
      case CHOLMOD_DSMALL:
        return "diagonal entry tiny";
      default:
        return "status " + std::to_string(common.status);
    }
  }

  double min_rcond = 0.0;

  // Numeric factorization into `f`; throws SolverError with the reason.
  void factorize(cholmod_sparse s, cholmod_factor* f, const char* who) {
    const BlasThreadScope threads(factor_blas_threads);
    const FlushDenormalsScope no_subnormals;
    const SerialOpenMpScope serial_loops;
    const int ok = cholmod_factorize(&s, f, &common);
    if (!ok || common.status < CHOLMOD_OK) {
      throw SolverError(std::string(who) + ": CHOLMOD factorization failed: " + status_text());
    }
    if (common.status == CHOLMOD_NOT_POSDEF || f->minor < f->n) {
      throw SolverError(std::string(who) + ": matrix is not positive definite (Cholesky pivot " +
                        std::to_string(f->minor) + " of " + std::to_string(f->n) +
                        " is not positive); a Laplacian needs Dirichlet data, screening or a "
                        "pinned vertex on every connected component");
    }
    // a singular PSD matrix often factors with a round-off-sized last pivot: catch it
    const double rcond = cholmod_rcond(f, &common);
    if (!(rcond >= min_rcond)) {
      throw SolverError(std::string(who) +
                        ": matrix is not positive definite (numerically "
                        "singular: reciprocal condition estimate " +
                        std::to_string(rcond) +
                        "); a Laplacian needs Dirichlet data, screening or a pinned vertex on "
                        "every connected component");
    }
  }

  // With our supernodal kernel: hand it the numeric supernodal factor f (double: its values
  // taken over; single: rounded into a copy), then drop f's values (CHOLMOD keeps the symbolic
  // factor, for refactor()).
  void hand_factor_to_kernel(cholmod_factor* f, const char* who) {
    if (kernel_kind == CholeskyOptions::SolveKernel::kCholmod || xtype != CHOLMOD_REAL) return;
    if (!f->is_super) throw SolverError(std::string(who) + ": factor is not supernodal");
    SupernodalPattern p = supernodal_pattern(f);
    const FactorPrecision precision = kernel_kind == CholeskyOptions::SolveKernel::kSupernodalSingle
                                          ? FactorPrecision::kSingle
                                          : FactorPrecision::kDouble;
    if (precision == FactorPrecision::kDouble) {
      // our kernel takes CHOLMOD's values over (no second copy of the factor while it is
      // handed over: the heat method's peak memory, docs/decisions.md D-112); CHOLMOD's
      // allocator frees them
      kernel = std::make_unique<SupernodalSolver>(SupernodalSolver::adopt(
          std::move(p), static_cast<double*>(f->x), &release_cholmod_values));
      // what cholmod_change_factor(CHOLMOD_PATTERN, ...) makes of a supernodal factor, without
      // freeing the values (it refuses a numeric factor without them)
      f->x = nullptr;
      f->xtype = CHOLMOD_PATTERN;
      f->minor = f->n;
      f->is_ll = 1;
      return;
    }
    kernel = std::make_unique<SupernodalSolver>(std::move(p), static_cast<const double*>(f->x),
                                                precision);
    // to_xtype = pattern: frees the values, keeps the supernodal symbolic factor
    if (!cholmod_change_factor(CHOLMOD_PATTERN, 1, 1, 1, 1, f, &common) || f->x) {
      throw SolverError(std::string(who) + ": dropping CHOLMOD's factor values failed");
    }
  }
};

namespace {

// ComplexCholeskySolver with our kernel: a view of CHOLMOD's numeric supernodal factor (the
// pattern copied, the values read in place).
std::unique_ptr<ComplexSupernodalSolver> complex_kernel_of(const cholmod_factor* f,
                                                           const char* who) {
  if (!f->is_super || f->xtype != CHOLMOD_COMPLEX || f->itype != CHOLMOD_INT || !f->x) {
    throw SolverError(std::string(who) + ": the complex factor is not supernodal");
  }
  SupernodalPattern p = supernodal_pattern(f);
  return std::make_unique<ComplexSupernodalSolver>(std::move(p),
                                                   static_cast<const std::complex<double>*>(f->x));
}

bool finite_value(double x) { return std::isfinite(x); }
bool finite_value(const std::complex<double>& z) {
  return std::isfinite(z.real()) && std::isfinite(z.imag());
}

template <class Matrix>
void check_matrix(const Matrix& A, const char* who) {
  if (A.rows() != A.cols()) {
    throw InvalidInput(std::string(who) + ": matrix is " + std::to_string(A.rows()) + "×" +
                       std::to_string(A.cols()) + ", expected square");
  }
  if (A.rows() == 0) throw InvalidInput(std::string(who) + ": empty matrix");
  const auto* v = A.valuePtr();
  for (Eigen::Index k = 0; k < A.nonZeros(); ++k) {
    if (!finite_value(v[k])) {
      throw InvalidInput(std::string(who) + ": matrix has a non-finite entry");
    }
  }
}

// A itself when compressed (CHOLMOD reads the CSC arrays directly), else a compressed copy
// kept in `storage`.
template <class Matrix>
const Matrix* compressed(const Matrix& A, Matrix& storage) {
  if (A.isCompressed()) return &A;
  storage = A;
  storage.makeCompressed();
  return &storage;
}

}  // namespace

namespace {

// The analysis settings of `options` in c: supernodal or not, LL', the forced ordering.
void configure_analysis(cholmod_common& c, const CholeskyOptions& options) {
  c.supernodal = options.supernodal ? CHOLMOD_SUPERNODAL : CHOLMOD_SIMPLICIAL;
  if (options.supernodal && options.simplicial_below_flops_per_entry > 0.0 &&
      options.solve_kernel == CholeskyOptions::SolveKernel::kCholmod) {
    c.supernodal = CHOLMOD_AUTO;  // simplicial when flops / nnz(L) < supernodal_switch
    c.supernodal_switch = options.simplicial_below_flops_per_entry;
  }
  c.final_ll = 1;
  if (!options.ordering.empty() || options.force_metis || options.force_amd) {
    c.nmethods = 1;
    c.method[0].ordering = !options.ordering.empty() ? CHOLMOD_GIVEN
                           : options.force_metis     ? CHOLMOD_METIS
                                                     : CHOLMOD_AMD;
    c.postorder = 1;
  }
}

// The symbolic factor of the pattern `s` views (c configured by configure_analysis), with the
// options' given ordering if any. nullptr if CHOLMOD fails.
cholmod_factor* analyze_pattern(cholmod_sparse& s, const CholeskyOptions& options,
                                cholmod_common& c, const char* who) {
  if (options.ordering.empty()) return cholmod_analyze(&s, &c);
  const std::size_t n = s.nrow;
  std::vector<char> seen(n, 0);
  bool permutation = options.ordering.size() == n;
  for (std::size_t k = 0; permutation && k < n; ++k) {
    const int j = options.ordering[k];
    permutation = j >= 0 && static_cast<std::size_t>(j) < n && !seen[j];
    if (permutation) seen[j] = 1;
  }
  if (!permutation) {
    throw InvalidInput(std::string(who) + ": CholeskyOptions::ordering has " +
                       std::to_string(options.ordering.size()) +
                       " entries and is not a permutation of 0.." + std::to_string(n) + "−1");
  }
  std::vector<int> perm = options.ordering;  // CHOLMOD's argument is not const
  return cholmod_analyze_p(&s, perm.data(), nullptr, 0, &c);
}

// The numeric settings of `options` in im.
void configure_numeric(CholeskySolver::Impl& im, Eigen::Index n, const CholeskyOptions& options) {
  im.n = n;
  im.min_rcond = options.min_rcond;
  im.factor_blas_threads = options.factor_blas_threads;
  im.solve_blas_threads = options.solve_blas_threads;
}

// Numeric factorization of im.factor (analyzed) and, optionally, the conversion to a
// simplicial factor for the solves.
void factor_and_convert(CholeskySolver::Impl& im, cholmod_sparse s, const CholeskyOptions& options,
                        const char* who) {
  cholmod_common& c = im.common;
  im.kernel_kind = options.solve_kernel;
  im.factorize(s, im.factor, who);
  im.factored_supernodal = im.factor->is_super;
  im.hand_factor_to_kernel(im.factor, who);
  if (im.xtype == CHOLMOD_COMPLEX &&
      options.solve_kernel == CholeskyOptions::SolveKernel::kSupernodalDouble) {
    im.complex_kernel = complex_kernel_of(im.factor, who);
  }
  // a complex factor stays supernodal: its supernodal solves are faster (simplicial_solves)
  if (!im.kernel && im.factor->is_super && options.simplicial_solves && im.xtype == CHOLMOD_REAL) {
    // to_ll = 1, to_super = 0, to_packed = 1, to_monotonic = 1
    if (!cholmod_change_factor(im.xtype, 1, 0, 1, 1, im.factor, &c) || c.status < CHOLMOD_OK) {
      throw SolverError(std::string(who) + ": converting the factor failed: " + im.status_text());
    }
  }
}

// Analysis, numeric factorization and (optionally) the conversion to a simplicial factor, for
// either solver; `s` views the matrix, im.xtype says real or complex.
void analyze_and_factor(CholeskySolver::Impl& im, cholmod_sparse s, const CholeskyOptions& options,
                        const char* who) {
  configure_numeric(im, static_cast<Eigen::Index>(s.nrow), options);
  configure_analysis(im.common, options);
  im.factor = analyze_pattern(s, options, im.common, who);
  if (!im.factor || im.common.status < CHOLMOD_OK) {
    throw SolverError(std::string(who) + ": CHOLMOD analysis failed: " + im.status_text());
  }
  factor_and_convert(im, s, options, who);
}

}  // namespace

CholeskySolver::CholeskySolver(const SparseMatrix& A_in, const CholeskyOptions& options)
    : impl_(std::make_unique<Impl>()) {
  options.validate();
  check_matrix(A_in, "CholeskySolver");
  SparseMatrix storage;
  const SparseMatrix* A = compressed(A_in, storage);
  Impl& im = *impl_;
  analyze_and_factor(im, Impl::view(*A, CHOLMOD_REAL), options, "CholeskySolver");
  im.outer.assign(A->outerIndexPtr(), A->outerIndexPtr() + A->cols() + 1);
  im.inner.assign(A->innerIndexPtr(), A->innerIndexPtr() + A->nonZeros());
}

// --- AMD ordering ----------------------------------------------------------------------------

std::vector<int> amd_ordering(int n, const std::vector<int>& start, const std::vector<int>& index) {
  if (n < 0 || start.size() != static_cast<std::size_t>(n) + 1 || start[0] != 0 ||
      static_cast<std::size_t>(start[n]) != index.size() ||
      !std::is_sorted(start.begin(), start.end()) ||
      std::any_of(index.begin(), index.end(), [n](int i) { return i < 0 || i >= n; })) {
    throw InvalidInput("amd_ordering: malformed adjacency lists for " + std::to_string(n) +
                       " nodes");
  }
  std::vector<int> perm(n);
  if (n == 0) return perm;
  if (2 * index.size() + index.size() / 2 + static_cast<std::size_t>(n) + 1 >
      static_cast<std::size_t>(std::numeric_limits<int>::max())) {
    throw InvalidInput("amd_ordering: the graph is too large for 32-bit indices");
  }
  // amd_2 (AMD's core) on the graph as it needs it: both directions of every edge, without
  // self-loops and repeats, contiguous lists and a fifth of elbow room (amd_order would check,
  // sort, transpose and symmetrize in separate passes)
  std::vector<int> pe(n + 1, 0), len(n, 0), mark(n, -1);
  for (int j = 0; j < n; ++j) {
    for (int p = start[j]; p < start[j + 1]; ++p) {
      if (index[p] == j) continue;
      ++pe[index[p] + 1];
      ++pe[j + 1];
    }
  }
  for (int j = 0; j < n; ++j) pe[j + 1] += pe[j];
  const std::size_t nz = static_cast<std::size_t>(pe[n]);
  const std::size_t iwlen = nz + nz / 5 + static_cast<std::size_t>(n) + 1;
  std::vector<int> iw(iwlen);
  for (int j = 0; j < n; ++j) {
    for (int p = start[j]; p < start[j + 1]; ++p) {
      const int i = index[p];
      if (i == j) continue;
      iw[pe[i] + len[i]++] = j;
      iw[pe[j] + len[j]++] = i;
    }
  }
  int pfree = 0;  // drop repeats, closing the gaps
  for (int j = 0; j < n; ++j) {
    const int begin = pe[j], end = pe[j] + len[j];
    pe[j] = pfree;
    for (int p = begin; p < end; ++p) {
      if (mark[iw[p]] == j) continue;
      mark[iw[p]] = j;
      iw[pfree++] = iw[p];
    }
    len[j] = pfree - pe[j];
  }
  pe.pop_back();
  std::vector<int> nv(n), inverse(n), head(n), elen(n), degree(n), w(n);
  double control[AMD_CONTROL], info[AMD_INFO];
  amd_defaults(control);
  amd_2(n, pe.data(), iw.data(), len.data(), static_cast<int>(iwlen), pfree, nv.data(),
        inverse.data(), perm.data(), head.data(), elen.data(), degree.data(), w.data(), control,
        info);
  return perm;
}

// --- CholeskyAnalysis ------------------------------------------------------------------------

struct CholeskyAnalysis::Impl {
  cholmod_common common;
  cholmod_factor* symbolic = nullptr;
  Eigen::Index n = 0;
  std::vector<int> outer, inner;  // the analyzed pattern

  Impl() {
    cholmod_start(&common);
    common.print = 0;
    common.error_handler = nullptr;
  }
  ~Impl() {
    if (symbolic) cholmod_free_factor(&symbolic, &common);
    cholmod_finish(&common);
  }
  Impl(const Impl&) = delete;
  Impl& operator=(const Impl&) = delete;

  bool same_pattern(const SparseMatrix& A) const {
    return A.rows() == n && A.cols() == n &&
           static_cast<std::size_t>(A.nonZeros()) == inner.size() &&
           std::equal(outer.begin(), outer.end(), A.outerIndexPtr()) &&
           std::equal(inner.begin(), inner.end(), A.innerIndexPtr());
  }
};

CholeskyAnalysis::CholeskyAnalysis(const SparseMatrix& A_in, const CholeskyOptions& options)
    : impl_(std::make_unique<Impl>()) {
  options.validate();
  if (A_in.rows() != A_in.cols() || A_in.rows() == 0) {
    throw InvalidInput("CholeskyAnalysis: matrix is " + std::to_string(A_in.rows()) + "×" +
                       std::to_string(A_in.cols()) + ", expected square and not empty");
  }
  SparseMatrix storage;
  const SparseMatrix* A = compressed(A_in, storage);
  Impl& im = *impl_;
  im.n = A->rows();
  configure_analysis(im.common, options);
  cholmod_sparse s = CholeskySolver::Impl::view(*A, CHOLMOD_REAL);
  im.symbolic = analyze_pattern(s, options, im.common, "CholeskyAnalysis");
  if (!im.symbolic || im.common.status < CHOLMOD_OK) {
    throw SolverError("CholeskyAnalysis: CHOLMOD analysis failed (status " +
                      std::to_string(im.common.status) + ")");
  }
  im.outer.assign(A->outerIndexPtr(), A->outerIndexPtr() + A->cols() + 1);
  im.inner.assign(A->innerIndexPtr(), A->innerIndexPtr() + A->nonZeros());
}

CholeskyAnalysis::~CholeskyAnalysis() = default;
CholeskyAnalysis::CholeskyAnalysis(CholeskyAnalysis&&) noexcept = default;
CholeskyAnalysis& CholeskyAnalysis::operator=(CholeskyAnalysis&&) noexcept = default;
Eigen::Index CholeskyAnalysis::size() const { return impl_->n; }

CholeskySolver::CholeskySolver(const SparseMatrix& A_in, const CholeskyAnalysis& analysis,
                               const CholeskyOptions& options)
    : impl_(std::make_unique<Impl>()) {
  options.validate();
  check_matrix(A_in, "CholeskySolver");
  SparseMatrix storage;
  const SparseMatrix* A = compressed(A_in, storage);
  const CholeskyAnalysis::Impl& an = *analysis.impl_;
  if (!an.same_pattern(*A)) {
    throw InvalidInput("CholeskySolver: the matrix's sparsity pattern is not the analyzed one");
  }
  Impl& im = *impl_;
  configure_numeric(im, A->rows(), options);
  configure_analysis(im.common, options);  // final_ll: a simplicial factor ends LL' as its own does
  // what the analysis chose, for ordering(), factor_nonzeros() and factor_flops()
  im.common.nmethods = an.common.nmethods;
  std::copy(std::begin(an.common.method), std::end(an.common.method), std::begin(im.common.method));
  im.common.selected = an.common.selected;
  im.common.lnz = an.common.lnz;
  im.common.fl = an.common.fl;
  im.factor = cholmod_copy_factor(an.symbolic, &im.common);  // reads the shared factor only
  if (!im.factor) throw SolverError("CholeskySolver: out of memory copying the analysis");
  factor_and_convert(im, Impl::view(*A, CHOLMOD_REAL), options, "CholeskySolver");
  im.outer = an.outer;
  im.inner = an.inner;
}

CholeskySolver::~CholeskySolver() = default;
CholeskySolver::CholeskySolver(CholeskySolver&&) noexcept = default;
CholeskySolver& CholeskySolver::operator=(CholeskySolver&&) noexcept = default;

void CholeskySolver::refactor(const SparseMatrix& A_in) {
  check_matrix(A_in, "CholeskySolver::refactor");
  SparseMatrix storage;
  const SparseMatrix* A = compressed(A_in, storage);
  Impl& im = *impl_;
  const bool same = A->rows() == im.n &&
                    static_cast<std::size_t>(A->nonZeros()) == im.inner.size() &&
                    std::equal(im.outer.begin(), im.outer.end(), A->outerIndexPtr()) &&
                    std::equal(im.inner.begin(), im.inner.end(), A->innerIndexPtr());
  if (!same) {
    throw InvalidInput(
        "CholeskySolver::refactor: the sparsity pattern differs from the "
        "analyzed matrix; construct a new solver");
  }
  std::lock_guard<std::mutex> lock(im.mutex);
  // factor into a copy so a failure keeps the previous factor usable
  cholmod_factor* f = cholmod_copy_factor(im.factor, &im.common);
  if (!f) throw SolverError("CholeskySolver::refactor: out of memory");
  try {
    im.factorize(Impl::view(*A, CHOLMOD_REAL), f, "CholeskySolver::refactor");
    im.hand_factor_to_kernel(f, "CholeskySolver::refactor");
  } catch (...) {
    cholmod_free_factor(&f, &im.common);
    throw;
  }
  cholmod_free_factor(&im.factor, &im.common);
  im.factor = f;
  const std::lock_guard<std::mutex> rows_lock(im.rows_kernel_mutex);
  im.rows_kernel.reset();
  im.rows_kernel_built = false;
}

namespace {

// Our supernodal kernel over a simplicial LL' factor (the same values, no factorization):
// consecutive columns whose patterns nest (column j + 1's rows are column j's without j) become
// one dense supernode, zeros above its diagonal, at most kMaxWidth columns wide (the chunk
// kernels' range). nullptr unless the factor is real, double, int-indexed, simplicial LL' with
// its diagonal first and sorted rows in every column.
std::unique_ptr<SupernodalSolver> kernel_from_simplicial(const cholmod_factor* f) {
  constexpr int kMaxWidth = 64;
  if (!f || f->is_super || !f->is_ll || f->xtype != CHOLMOD_REAL || f->itype != CHOLMOD_INT ||
      f->dtype != CHOLMOD_DOUBLE || f->n == 0 || !f->x) {
    return nullptr;
  }
  const int n = static_cast<int>(f->n);
  const auto* Lp = static_cast<const int*>(f->p);
  const auto* Li = static_cast<const int*>(f->i);
  const auto* Lnz = static_cast<const int*>(f->nz);
  const auto* Lx = static_cast<const double*>(f->x);
  const auto* perm = static_cast<const int*>(f->Perm);
  SupernodalPattern p;
  p.n = n;
  p.perm.assign(perm, perm + n);
  p.super = {0};
  p.row_start = {0};
  p.value_start = {0};
  std::vector<double> values;
  for (int j0 = 0; j0 < n;) {
    const int* r0 = Li + Lp[j0];
    const int nz0 = Lnz[j0];
    if (nz0 < 1 || r0[0] != j0 || !std::is_sorted(r0, r0 + nz0)) return nullptr;
    int j1 = j0 + 1;
    while (j1 < n && j1 - j0 < kMaxWidth && Lnz[j1] == nz0 - (j1 - j0) &&
           std::equal(r0 + (j1 - j0), r0 + nz0, Li + Lp[j1])) {
      ++j1;
    }
    const std::size_t base = values.size();
    values.resize(base + std::size_t(nz0) * std::size_t(j1 - j0), 0.0);
    for (int c = 0; c < j1 - j0; ++c) {
      std::copy_n(Lx + Lp[j0 + c], Lnz[j0 + c], values.data() + base + std::size_t(c) * nz0 + c);
    }
    p.rows.insert(p.rows.end(), r0, r0 + nz0);
    p.super.push_back(j1);
    p.row_start.push_back(static_cast<std::int64_t>(p.rows.size()));
    p.value_start.push_back(static_cast<std::int64_t>(values.size()));
    j0 = j1;
  }
  return std::make_unique<SupernodalSolver>(std::move(p), values.data(), FactorPrecision::kDouble);
}

// Our kernel for solve_rows() with several columns when CHOLMOD holds the factor (built once).
const SupernodalSolver* rows_kernel_for_blocks(const CholeskySolver::Impl& im) {
  const std::lock_guard<std::mutex> lock(im.rows_kernel_mutex);
  if (!im.rows_kernel_built) {
    im.rows_kernel = kernel_from_simplicial(im.factor);
    im.rows_kernel_built = true;
  }
  return im.rows_kernel.get();
}

// Solves A X = B for B given as raw column-major data (rows = n, cols columns; complex entries
// as interleaved (re, im) pairs when im.xtype is CHOLMOD_COMPLEX); X may alias B.
void solve_raw(const CholeskySolver::Impl& im, const double* B, Eigen::Index cols, double* X) {
  if (cols == 0) return;
  if (im.complex_kernel) {
    im.complex_kernel->solve(reinterpret_cast<const std::complex<double>*>(B),
                             reinterpret_cast<std::complex<double>*>(X), cols);
    return;
  }
  if (im.kernel) {
    // one BLAS thread: OpenBLAS's threaded kernels round differently (results must not depend
    // on its thread count), and our kernel runs its own two bins
    const BlasThreadScope threads(im.solve_blas_threads);
    im.kernel->solve(B, X, cols);
    return;
  }
  cholmod_dense b;
  std::memset(&b, 0, sizeof(b));
  b.nrow = static_cast<size_t>(im.n);
  b.ncol = static_cast<size_t>(cols);
  b.nzmax = b.nrow * b.ncol;
  b.d = b.nrow;
  b.x = const_cast<double*>(B);
  b.xtype = im.xtype;
  b.dtype = CHOLMOD_DOUBLE;
  std::lock_guard<std::mutex> lock(im.mutex);
  const BlasThreadScope threads(im.solve_blas_threads);
  const FlushDenormalsScope no_subnormals;
  auto& c = const_cast<cholmod_common&>(im.common);
  // cholmod_solve2 reuses X, Y, E when their sizes fit: no allocation per solve
  const int ok =
      cholmod_solve2(CHOLMOD_A, im.factor, &b, nullptr, &im.X, nullptr, &im.Y, &im.E, &c);
  if (!ok || !im.X || c.status < CHOLMOD_OK) {
    throw SolverError("CholeskySolver::solve: CHOLMOD solve failed: " + im.status_text());
  }
  const size_t doubles_per_entry = im.xtype == CHOLMOD_COMPLEX ? 2 : 1;
  std::memcpy(X, im.X->x, sizeof(double) * doubles_per_entry * b.nzmax);
}

void check_rhs(Eigen::Index rows, Eigen::Index n) {
  if (rows != n) {
    throw InvalidInput("CholeskySolver::solve: right-hand side has " + std::to_string(rows) +
                       " rows, expected " + std::to_string(n));
  }
}

}  // namespace

Eigen::MatrixXd CholeskySolver::solve(const Eigen::MatrixXd& B) const {
  check_rhs(B.rows(), impl_->n);
  Eigen::MatrixXd X(B.rows(), B.cols());
  solve_raw(*impl_, B.data(), B.cols(), X.data());
  return X;
}

Eigen::VectorXd CholeskySolver::solve(const Eigen::VectorXd& b) const {
  check_rhs(b.rows(), impl_->n);
  Eigen::VectorXd x(b.rows());
  solve_raw(*impl_, b.data(), 1, x.data());
  return x;
}

void CholeskySolver::solve(const double* b, double* x, Eigen::Index cols) const {
  if (cols < 0) throw InvalidInput("CholeskySolver::solve: negative column count");
  solve_raw(*impl_, b, cols, x);
}

namespace {
// The kernel that solve_rows() runs for blocks of several columns, or null.
const SupernodalSolver* block_kernel(const CholeskySolver::Impl& im) {
  if (im.xtype != CHOLMOD_REAL) return nullptr;
  return im.kernel ? im.kernel.get() : rows_kernel_for_blocks(im);
}
}  // namespace

const std::vector<int>* CholeskyBlocks::block_order(const CholeskySolver& chol) {
  const SupernodalSolver* k = block_kernel(*chol.impl_);
  return k ? &k->permutation() : nullptr;
}

void CholeskyBlocks::solve_in_block_order(const CholeskySolver& chol, double* W, Eigen::Index cols,
                                          const int* source_rows, const double* shift_rows,
                                          const double* shift_sums) {
  const SupernodalSolver* k = block_kernel(*chol.impl_);
  if (!k || cols < 2) {
    throw InvalidInput("CholeskyBlocks::solve_in_block_order: " +
                       std::string(k ? "needs two or more columns" : "no block order here"));
  }
  const BlasThreadScope threads(chol.impl_->solve_blas_threads);
  k->solve_rows_in_factor_order(W, cols, source_rows, shift_rows, shift_sums);
}

void CholeskySolver::solve_rows(double* X, Eigen::Index cols) const {
  if (cols < 0) throw InvalidInput("CholeskySolver::solve_rows: negative column count");
  const Impl& im = *impl_;
  if (im.xtype != CHOLMOD_REAL) {
    throw InvalidInput("CholeskySolver::solve_rows: a complex factor (use solve())");
  }
  if (cols == 0) return;
  if (im.kernel) {
    const BlasThreadScope threads(im.solve_blas_threads);
    im.kernel->solve_rows(X, cols);
    return;
  }
  if (cols == 1) {
    solve_raw(im, X, 1, X);  // one column: rows are columns
    return;
  }
  // CHOLMOD's simplicial solve takes k columns four at a time and column-major: our kernel over
  // its factor instead (docs/decisions.md, "Our kernel over CHOLMOD's simplicial factor")
  if (const SupernodalSolver* k = rows_kernel_for_blocks(im)) {
    const BlasThreadScope threads(im.solve_blas_threads);
    k->solve_rows(X, cols);
    return;
  }
  // CHOLMOD solves column-major blocks: through a transposed copy
  Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>> rows(X, im.n,
                                                                                          cols);
  Eigen::MatrixXd B = rows;
  solve_raw(im, B.data(), cols, B.data());
  rows = B;
}

Eigen::Index CholeskySolver::size() const { return impl_->n; }

double CholeskySolver::factor_flops() const { return impl_->common.fl; }

namespace {

const char* ordering_name(const cholmod_common& c) {
  if (c.selected < 0 || c.selected >= CHOLMOD_MAXMETHODS) return "unknown";
  switch (c.method[c.selected].ordering) {
    case CHOLMOD_NATURAL:
      return "natural";
    case CHOLMOD_GIVEN:
      return "given";
    case CHOLMOD_AMD:
      return "AMD";
    case CHOLMOD_METIS:
      return "METIS";
    case CHOLMOD_NESDIS:
      return "NESDIS";
    case CHOLMOD_COLAMD:
      return "COLAMD";
    default:
      return "other";
  }
}

}  // namespace

const char* CholeskySolver::ordering() const { return ordering_name(impl_->common); }

bool CholeskySolver::supernodal() const { return impl_->factor && impl_->factored_supernodal; }

double CholeskySolver::factor_nonzeros() const { return impl_->common.lnz; }

double CholeskySolver::solve_bytes() const {
  const Impl& im = *impl_;
  if (im.kernel) return 2.0 * double(im.kernel->bytes_per_pass());
  const cholmod_factor* f = im.factor;
  if (f->is_super) return 2.0 * (8.0 * double(f->xsize) + 4.0 * double(f->ssize));
  return 2.0 * 12.0 * double(im.common.lnz);  // simplicial: a value and a row index per entry
}

// --- ComplexCholeskySolver -------------------------------------------------------------------

ComplexCholeskySolver::ComplexCholeskySolver(const ComplexSparseMatrix& A_in,
                                             const CholeskyOptions& options)
    : impl_(std::make_unique<CholeskySolver::Impl>()) {
  options.validate();
  if (options.solve_kernel == CholeskyOptions::SolveKernel::kSupernodalSingle) {
    throw InvalidInput(
        "ComplexCholeskySolver: no single-precision solve kernel for complex factors");
  }
  check_matrix(A_in, "ComplexCholeskySolver");
  ComplexSparseMatrix storage;
  const ComplexSparseMatrix* A = compressed(A_in, storage);
  impl_->xtype = CHOLMOD_COMPLEX;
  analyze_and_factor(*impl_, CholeskySolver::Impl::view(*A, CHOLMOD_COMPLEX), options,
                     "ComplexCholeskySolver");
}

ComplexCholeskySolver::~ComplexCholeskySolver() = default;
ComplexCholeskySolver::ComplexCholeskySolver(ComplexCholeskySolver&&) noexcept = default;
ComplexCholeskySolver& ComplexCholeskySolver::operator=(ComplexCholeskySolver&&) noexcept = default;

Eigen::VectorXcd ComplexCholeskySolver::solve(const Eigen::VectorXcd& b) const {
  check_rhs(b.rows(), impl_->n);
  Eigen::VectorXcd x(b.rows());
  solve_raw(*impl_, reinterpret_cast<const double*>(b.data()), 1,
            reinterpret_cast<double*>(x.data()));
  return x;
}

Eigen::MatrixXcd ComplexCholeskySolver::solve(const Eigen::MatrixXcd& B) const {
  check_rhs(B.rows(), impl_->n);
  Eigen::MatrixXcd X(B.rows(), B.cols());
  solve_raw(*impl_, reinterpret_cast<const double*>(B.data()), B.cols(),
            reinterpret_cast<double*>(X.data()));
  return X;
}

Eigen::Index ComplexCholeskySolver::size() const { return impl_->n; }
double ComplexCholeskySolver::factor_nonzeros() const { return impl_->common.lnz; }
const char* ComplexCholeskySolver::ordering() const { return ordering_name(impl_->common); }

}  // namespace ifem::solvers
