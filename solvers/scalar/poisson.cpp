#include "solvers/scalar/poisson.h"

#include <algorithm>
#include <cmath>
#include <mutex>
#include <optional>
#include <string>

#include "intrinsic/core/errors.h"
#include "solvers/linalg/cholesky_blocks.h"
#include "solvers/linalg/parallel.h"
#include "solvers/scalar/heat_engine.h"

namespace ifem::solvers {

namespace {
// A row-major block of at least this many values is shifted by two threads (as the heat
// method's blocks, kParallelBlockValues in heat_distance.cpp).
constexpr std::int64_t kParallelRowValues = 1 << 16;
}  // namespace

void PoissonOptions::validate() const {
  if (!(screening >= 0.0) || !std::isfinite(screening)) {
    throw InvalidInput("PoissonOptions: screening must be finite and ≥ 0, got " +
                       std::to_string(screening));
  }
  cholesky.validate();
  solver.validate();
}

struct PoissonSolver::Impl {
  Index n = 0;
  std::vector<Index> dirichlet;  // caller's order
  std::vector<Index> unknown;    // vertex → unknown id, or -1
  std::vector<Index> unknown_vertex;
  Components comps;
  std::vector<char> floating;     // per component: pure Neumann (pinned, zero mean)
  std::vector<double> comp_mass;  // per component: Σ m
  // When every vertex lies in one pure-Neumann component (the common case), the compatibility
  // shift and the zero mean of solve_many() are vector operations: 1 on the component's vertices
  // (0 elsewhere), and m_v / Σ m.
  bool one_floating = false;
  Eigen::VectorXd floating_one, floating_weight;
  Eigen::VectorXd mass;
  fem::SparseMatrix A_ud;  // unknowns × Dirichlet columns (coupling)
  // With a shared analysis: per vertex, Dirichlet or pinned (kept in the system as a decoupled
  // row), and those rows; both empty otherwise.
  std::vector<char> fixed;
  std::vector<Index> fixed_rows;
  // the fine operator's values on PoissonOptions::multigrid_pattern, when setup() assembled
  // them there (D-365): factor() then builds the multigrid solver from them, A is empty
  std::vector<double> pattern_values;
  std::optional<CholeskySolver> chol;
  std::optional<MultigridSolver> mg;  // instead of chol (PoissonOptions::solver)

  // Solves the factored (or multigrid) system for k columns, column-major, in place.
  void solve_columns(double* X, Eigen::Index k) const {
    if (mg) {
      mg->solve(X, X, k);
    } else {
      chol->solve(X, X, k);
    }
  }

  // Whether row-major blocks are solved in place: every vertex an unknown (unknown id = vertex),
  // and the pure-Neumann part one component or none.
  bool rows_direct() const {
    return Index(unknown_vertex.size()) == n && (floating.empty() || one_floating);
  }
  // Where the fixed rows are in the block order `order`, and the compatibility shift's weights
  // b in that order, 0 on the fixed rows (computed on first use).
  mutable std::once_flag fixed_positions_once;
  mutable std::vector<Index> fixed_positions;
  mutable std::vector<double> weight_in_order;
  // The row-major solve (rows_direct()): as solve_many_identity(), row by row: Σ_v a_v X(v, :)
  // then X(v, :) −= b_v Σ (k values per vertex: one vector operation each); each sweep in two
  // halves of the rows (on two threads for a large block), the sum as half 0's plus half 1's.
  // With `order`, row i of X is vertex (*order)[i] (the factor's own order: no row copies).
  // With `order`, the compatibility shift's subtraction is folded into the solve's forward pass
  // (no sweep of its own), and compat_sums, when given, are its sums aᵀX (the caller's sweep).
  void solve_rows(double* X, Eigen::Index k, bool zero_mean, const std::vector<int>* order,
                  const int* source_rows, const double* compat_sums = nullptr) const {
    const bool two_threads = std::int64_t(n) * k >= kParallelRowValues;
    auto vertex = [order](Index i) { return order ? Index((*order)[std::size_t(i)]) : i; };
    std::vector<double> half_sum[2];
    auto sums = [&](const Eigen::VectorXd& a) {
      run_halves(two_threads, [&](int half) {
        half_sum[half].assign(std::size_t(k), 0.0);
        double* sum = half_sum[half].data();
        for (Index i = n * half / 2; i < n * (half + 1) / 2; ++i) {
          const double ai = a[vertex(i)], *x = X + i * k;
          for (Eigen::Index j = 0; j < k; ++j) sum[j] += ai * x[j];
        }
      });
      for (std::size_t j = 0; j < std::size_t(k); ++j) half_sum[0][j] += half_sum[1][j];
      return half_sum[0].data();
    };
    auto shift = [&](const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
      const double* sum = sums(a);
      run_halves(two_threads, [&](int half) {
        for (Index i = n * half / 2; i < n * (half + 1) / 2; ++i) {
          const double bi = b[vertex(i)];
          double* x = X + i * k;
          for (Eigen::Index j = 0; j < k; ++j) x[j] -= bi * sum[j];
        }
      });
    };
    const std::vector<Index>* fixed_at = &fixed_rows;
    if (order) {
      std::call_once(fixed_positions_once, [&] {
        std::vector<Index> position(static_cast<std::size_t>(n));
        for (Index i = 0; i < n; ++i) position[std::size_t((*order)[std::size_t(i)])] = i;
        for (const Index r : fixed_rows) fixed_positions.push_back(position[std::size_t(r)]);
        if (one_floating) {
          weight_in_order.resize(std::size_t(n));
          for (Index i = 0; i < n; ++i)
            weight_in_order[std::size_t(i)] = floating_weight[vertex(i)];
          for (const Index r : fixed_positions) weight_in_order[std::size_t(r)] = 0.0;
        }
      });
      fixed_at = &fixed_positions;
    }
    auto zero_fixed = [&] {
      for (const Index r : *fixed_at) std::fill(X + r * k, X + (r + 1) * k, 0.0);
    };
    if (one_floating && !order) shift(floating_one, floating_weight);  // compatible
    // in the order: X − b·(aᵀX)ᵀ, the sums taken before the fixed rows are zeroed and the
    // subtraction made by the forward pass
    const double* sum =
        one_floating && order ? (compat_sums ? compat_sums : sums(floating_one)) : nullptr;
    zero_fixed();
    if (n > 0 && mg) {  // column-major through a copy (no block order: block_order() is null)
      using RowBlock =
          Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>;
      RowBlock rows(X, n, k);
      Eigen::MatrixXd B = rows;
      mg->solve(B.data(), B.data(), k);
      rows = B;
    } else if (n > 0 && sum) {
      CholeskyBlocks::solve_in_block_order(*chol, X, k, nullptr, weight_in_order.data(), sum);
    } else if (n > 0 && order) {
      CholeskyBlocks::solve_in_block_order(*chol, X, k, source_rows);
    } else if (n > 0) {
      chol->solve_rows(X, k);
    }
    zero_fixed();
    if (one_floating && zero_mean) shift(floating_weight, floating_one);
  }

  // Makes the pure-Neumann components' right-hand sides compatible (zero sum), every column.
  void make_compatible(Eigen::Ref<Eigen::MatrixXd> B) const {
    const Eigen::Index k = B.cols();
    if (one_floating) {
      for (Eigen::Index j = 0; j < k; ++j) {
        B.col(j) -= floating_one.dot(B.col(j)) * floating_weight;
      }
    } else if (!floating.empty()) {
      for (Eigen::Index j = 0; j < k; ++j) {
        std::vector<double> sum(comps.count, 0.0);
        for (Index v = 0; v < n; ++v) {
          const Index c = comps.label[v];
          if (c != kInvalidIndex && floating[c]) sum[c] += B(v, j);
        }
        for (Index v = 0; v < n; ++v) {
          const Index c = comps.label[v];
          if (c != kInvalidIndex && floating[c] && comp_mass[c] > 0) {
            B(v, j) -= sum[c] / comp_mass[c] * mass[v];
          }
        }
      }
    }
  }

  // Shifts every column's solution on each pure-Neumann component to zero mean.
  void remove_floating_means(Eigen::Ref<Eigen::MatrixXd> X) const {
    const Eigen::Index k = X.cols();
    if (one_floating) {
      for (Eigen::Index j = 0; j < k; ++j) {
        X.col(j) -= floating_weight.dot(X.col(j)) * floating_one;
      }
    } else if (!floating.empty()) {
      for (Eigen::Index j = 0; j < k; ++j) {
        std::vector<double> mean(comps.count, 0.0);
        for (Index v = 0; v < n; ++v) {
          const Index c = comps.label[v];
          if (c != kInvalidIndex && floating[c]) mean[c] += mass[v] * X(v, j);
        }
        for (Index v = 0; v < n; ++v) {
          const Index c = comps.label[v];
          if (c != kInvalidIndex && floating[c] && comp_mass[c] > 0) {
            X(v, j) -= mean[c] / comp_mass[c];
          }
        }
      }
    }
  }

  // One right-hand side: the work of solve_many() without the #V×1 matrix copies.
  Eigen::VectorXd solve_one(const Eigen::VectorXd& b, const Eigen::VectorXd& g) const {
    const Index nu = static_cast<Index>(unknown_vertex.size());
    Eigen::VectorXd compatible;
    const Eigen::VectorXd* src = &b;
    if (!floating.empty()) {  // pure-Neumann components: a compatible copy of b
      compatible = b;
      make_compatible(Eigen::Map<Eigen::MatrixXd>(compatible.data(), n, 1));
      src = &compatible;
    }
    Eigen::VectorXd rhs(nu);
    for (Index i = 0; i < nu; ++i) rhs[i] = (*src)[unknown_vertex[i]];
    if (A_ud.cols() > 0) rhs.noalias() -= A_ud * g;
    for (const Index r : fixed_rows) rhs[r] = 0.0;  // decoupled: solved to 0
    if (nu > 0) solve_columns(rhs.data(), 1);
    Eigen::VectorXd x = Eigen::VectorXd::Zero(n);
    for (Index i = 0; i < nu; ++i) x[unknown_vertex[i]] = rhs[i];
    for (const Index r : fixed_rows) x[unknown_vertex[r]] = 0.0;  // pinned: 0 (not −0)
    for (std::size_t d = 0; d < dirichlet.size(); ++d) x[dirichlet[d]] = g[Eigen::Index(d)];
    remove_floating_means(Eigen::Map<Eigen::MatrixXd>(x.data(), n, 1));
    return x;
  }

  Eigen::MatrixXd solve_many(Eigen::MatrixXd B, const Eigen::MatrixXd* g) const {
    const Index nu = static_cast<Index>(unknown_vertex.size());
    const Eigen::Index k = B.cols();
    make_compatible(B);  // pure-Neumann components
    // gathers and scatters column by column: a row of a column-major #V × k matrix spans k pages,
    // and copying row by row missed the TLB on every entry (a third of a 32-source batch's time)
    Eigen::MatrixXd rhs(nu, k);
    for (Eigen::Index j = 0; j < k; ++j) {
      for (Index i = 0; i < nu; ++i) rhs(i, j) = B(unknown_vertex[i], j);
    }
    if (g && A_ud.cols() > 0) rhs -= A_ud * (*g);
    for (const Index r : fixed_rows) rhs.row(r).setZero();  // decoupled: solved to 0
    Eigen::MatrixXd X = Eigen::MatrixXd::Zero(n, k);
    if (nu > 0) {
      solve_columns(rhs.data(), k);
      for (Eigen::Index j = 0; j < k; ++j) {
        for (Index i = 0; i < nu; ++i) X(unknown_vertex[i], j) = rhs(i, j);
      }
      for (const Index r : fixed_rows) X.row(unknown_vertex[r]).setZero();
    }
    if (g) {
      for (std::size_t d = 0; d < dirichlet.size(); ++d) X.row(dirichlet[d]) = g->row(d);
    }
    remove_floating_means(X);
    return X;
  }

  // solve_many() with zero Dirichlet values when unknown i is vertex i (every vertex in the
  // system, fixed ones as decoupled rows), over B's own storage.
  void solve_many_identity(Eigen::Ref<Eigen::MatrixXd> B) const {
    make_compatible(B);
    for (const Index r : fixed_rows) B.row(r).setZero();  // decoupled: solved to 0
    if (n > 0) solve_columns(B.data(), B.cols());
    for (const Index r : fixed_rows) B.row(r).setZero();  // pinned and Dirichlet: 0 (not −0)
    remove_floating_means(B);
  }

  // Checks the Dirichlet vertices (in range, each once) and marks them, and the components
  // that hold one.
  void mark_dirichlet(const std::vector<Index>& given, std::vector<char>& is_dirichlet,
                      std::vector<char>& comp_has_dirichlet) const {
    is_dirichlet.assign(n, 0);
    comp_has_dirichlet.assign(comps.count, 0);
    for (const Index v : given) {
      if (v < 0 || v >= n) {
        throw InvalidInput("PoissonSolver: Dirichlet vertex " + std::to_string(v) +
                           " out of range [0, " + std::to_string(n) + ")");
      }
      if (is_dirichlet[v]) {
        throw InvalidInput("PoissonSolver: Dirichlet vertex " + std::to_string(v) + " given twice");
      }
      is_dirichlet[v] = 1;
      if (comps.label[v] != kInvalidIndex) comp_has_dirichlet[comps.label[v]] = 1;
    }
  }

  // Pure-Neumann components (unscreened, no Dirichlet vertex): pins their lowest vertex to 0
  // (shifted to zero mean after each solve) in pinned; sets floating and comp_mass.
  void pin_floating_components(const std::vector<char>& comp_has_dirichlet,
                               std::vector<char>& pinned) {
    floating.assign(comps.count, 0);
    comp_mass.assign(comps.count, 0.0);
    bool any = false;
    std::vector<char> done(comps.count, 0);
    for (Index v = 0; v < n; ++v) {
      const Index c = comps.label[v];
      if (c == kInvalidIndex) continue;
      comp_mass[c] += mass[v];
      if (comp_has_dirichlet[c] || done[c]) continue;
      done[c] = 1;
      pinned[v] = 1;
      floating[c] = 1;
      any = true;
    }
    if (!any) floating.clear();
    one_floating = comps.count == 1 && any && comp_mass[0] > 0.0;
    if (one_floating) {
      floating_one = Eigen::VectorXd::Zero(n);
      floating_weight = Eigen::VectorXd::Zero(n);
      for (Index v = 0; v < n; ++v) {
        if (comps.label[v] == kInvalidIndex) continue;
        floating_one[v] = 1.0;
        floating_weight[v] = mass[v] / comp_mass[0];
      }
    }
  }

  // Numbers the unknowns: vertices in a component, in vertex order; Dirichlet and pinned ones
  // only when `keep_fixed` (a shared analysis: marked in fixed and fixed_rows).
  void number_unknowns(const std::vector<char>& is_dirichlet, const std::vector<char>& pinned,
                       bool keep_fixed) {
    unknown.assign(n, kInvalidIndex);
    if (keep_fixed) fixed.assign(n, 0);
    for (Index v = 0; v < n; ++v) {
      if (comps.label[v] == kInvalidIndex) continue;
      const bool is_fixed = is_dirichlet[v] || pinned[v];
      if (is_fixed && !keep_fixed) continue;
      unknown[v] = static_cast<Index>(unknown_vertex.size());
      if (is_fixed) {
        fixed[v] = 1;
        fixed_rows.push_back(unknown[v]);
      }
      unknown_vertex.push_back(v);
    }
  }
  bool is_fixed(Index v) const { return !fixed.empty() && fixed[v]; }

  // Lower triangle of A_uu = (L + c M) restricted to the unknowns (all CHOLMOD reads), column by
  // column from L's columns. Unknown ids increase with vertex ids, so rows stay sorted; the
  // diagonal comes first in each column and always exists (+ c·m). A fixed row (shared analysis)
  // keeps its entries, as zeros but its positive diagonal: decoupled, with L's pattern.
  fem::SparseMatrix assemble_unknown_block(const fem::SparseMatrix& L, double c) const {
    const Index nu = static_cast<Index>(unknown_vertex.size());
    // one named result, returned from both paths (copy elision: Eigen 3.4's SparseMatrix has
    // no move constructor, so any other return copies it)
    fem::SparseMatrix A;
    if (nu == n && lower_triangle(L, c, A)) {
      decouple_fixed(A);
      return A;
    }
    A.resize(nu, nu);
    int* outer = A.outerIndexPtr();
    outer[0] = 0;
    for (Index u = 0; u < nu; ++u) {
      const Index j = unknown_vertex[u];
      int count = 1;  // the diagonal
      for (fem::SparseMatrix::InnerIterator it(L, j); it; ++it) {
        if (it.row() > j && unknown[it.row()] != kInvalidIndex) ++count;
      }
      outer[u + 1] = outer[u] + count;
    }
    A.resizeNonZeros(outer[nu]);
    int* inner = A.innerIndexPtr();
    double* value = A.valuePtr();
    // serial (one pass over L's entries): the heat method assembles its matrices inside
    // side-by-side factorization jobs, where both cores are busy and an OpenMP team per job only
    // added threads that spin
    for (Index u = 0; u < nu; ++u) {
      const Index j = unknown_vertex[u];
      int k = outer[u];
      inner[k] = u;
      value[k] = c * mass[j];
      const int diag = k++;
      for (fem::SparseMatrix::InnerIterator it(L, j); it; ++it) {
        const Index i = it.row();
        if (i == j) {
          value[diag] += it.value();
        } else if (i > j && unknown[i] != kInvalidIndex) {
          inner[k] = unknown[i];
          value[k++] = it.value();
        }
      }
    }
    decouple_fixed(A);
    return A;
  }

  // lower_triangle()'s values (L + c·M, fixed rows decoupled) written on `pattern`'s storage into
  // pattern_values, without index arrays of their own. False (nothing written) unless every
  // vertex is an unknown and L's lower triangle has exactly that pattern.
  bool values_on_pattern(const fem::SparseMatrix& L, double c, const SparseMatrix& pattern) {
    if (Index(unknown_vertex.size()) != n || !L.isCompressed() || !pattern.isCompressed() ||
        pattern.rows() != n || pattern.cols() != n) {
      return false;
    }
    const int* l_outer = L.outerIndexPtr();
    const int* l_inner = L.innerIndexPtr();
    const double* l_value = L.valuePtr();
    const int* outer = pattern.outerIndexPtr();
    const int* inner = pattern.innerIndexPtr();
    std::vector<double> value(std::size_t(pattern.nonZeros()));
    for (Index j = 0; j < n; ++j) {
      const int* d = std::lower_bound(l_inner + l_outer[j], l_inner + l_outer[j + 1], int(j));
      const int count = int(l_inner + l_outer[j + 1] - d);
      if (count == 0 || *d != j || count != outer[j + 1] - outer[j] ||
          !std::equal(d, d + count, inner + outer[j])) {
        return false;
      }
      std::copy_n(l_value + (d - l_inner), count, value.data() + outer[j]);
      value[std::size_t(outer[j])] += c * mass[j];
    }
    decouple_fixed(outer, inner, value.data(), n);
    pattern_values.swap(value);
    return true;
  }

  void decouple_fixed(fem::SparseMatrix& A) const {
    decouple_fixed(A.outerIndexPtr(), A.innerIndexPtr(), A.valuePtr(), A.cols());
  }
  // Decouples the fixed rows and columns of a block (diagonal first in each column): their
  // off-diagonal entries become zeros, their diagonal any positive value.
  void decouple_fixed(const int* outer, const int* inner, double* value, Index cols) const {
    if (fixed_rows.empty()) return;
    for (Index u = 0; u < cols; ++u) {
      const bool fixed_u = is_fixed(unknown_vertex[u]);
      for (int k = outer[u] + 1; k < outer[u + 1]; ++k) {
        if (fixed_u || is_fixed(unknown_vertex[inner[k]])) value[k] = 0.0;
      }
      if (fixed_u && !(value[outer[u]] > 0.0)) value[outer[u]] = 1.0;
    }
  }

  // assemble_unknown_block() when every vertex is an unknown (the heat method's matrices): each
  // column's lower part is a contiguous tail of L's sorted column, copied whole into A (fixed
  // rows not yet decoupled). False when L is not compressed or lacks a stored diagonal entry
  // (the general loop inserts it).
  bool lower_triangle(const fem::SparseMatrix& L, double c, fem::SparseMatrix& A) const {
    if (!L.isCompressed()) return false;
    const int* l_outer = L.outerIndexPtr();
    const int* l_inner = L.innerIndexPtr();
    const double* l_value = L.valuePtr();
    A.resize(n, n);
    int* outer = A.outerIndexPtr();
    std::vector<int> diag(n);
    outer[0] = 0;
    for (Index j = 0; j < n; ++j) {
      const int* d = std::lower_bound(l_inner + l_outer[j], l_inner + l_outer[j + 1], int(j));
      if (d == l_inner + l_outer[j + 1] || *d != j) return false;
      diag[j] = static_cast<int>(d - l_inner);
      outer[j + 1] = outer[j] + (l_outer[j + 1] - diag[j]);
    }
    A.resizeNonZeros(outer[n]);
    int* inner = A.innerIndexPtr();
    double* value = A.valuePtr();
    for (Index j = 0; j < n; ++j) {
      const int count = l_outer[j + 1] - diag[j];
      std::copy_n(l_inner + diag[j], count, inner + outer[j]);
      std::copy_n(l_value + diag[j], count, value + outer[j]);
      value[outer[j]] += c * mass[j];
    }
    return true;
  }

  // The coupling A_ud (unknown rows × Dirichlet columns) from L's Dirichlet columns.
  void assemble_coupling(const fem::SparseMatrix& L) {
    const Index nu = static_cast<Index>(unknown_vertex.size());
    const Index nd = static_cast<Index>(dirichlet.size());
    A_ud.resize(nu, nd);
    int* outer = A_ud.outerIndexPtr();
    outer[0] = 0;
    for (Index d = 0; d < nd; ++d) {
      int count = 0;
      for (fem::SparseMatrix::InnerIterator it(L, dirichlet[d]); it; ++it) {
        if (unknown[it.row()] != kInvalidIndex && !is_fixed(it.row())) ++count;
      }
      outer[d + 1] = outer[d] + count;
    }
    A_ud.resizeNonZeros(outer[nd]);
    int* inner = A_ud.innerIndexPtr();
    double* value = A_ud.valuePtr();
    for (Index d = 0; d < nd; ++d) {
      int k = outer[d];
      for (fem::SparseMatrix::InnerIterator it(L, dirichlet[d]); it; ++it) {
        const Index ui = unknown[it.row()];
        if (ui == kInvalidIndex || is_fixed(it.row())) continue;
        inner[k] = ui;
        value[k++] = it.value();
      }
    }
  }
};

PoissonSolver::PoissonSolver(const intrinsic::IntrinsicTriangulation& tri,
                             std::vector<Index> dirichlet_vertices, const PoissonOptions& options)
    : PoissonSolver(fem::cotan_laplacian(tri), fem::lumped_mass(tri), connected_components(tri),
                    std::move(dirichlet_vertices), with_hierarchy(tri, options)) {}

PoissonOptions PoissonSolver::with_hierarchy(const intrinsic::IntrinsicTriangulation& tri,
                                             const PoissonOptions& options) {
  options.validate();
  PoissonOptions o = options;
  if (!o.prolongations && o.solver.use_multigrid(tri.n_vertices())) {
    o.prolongations = std::make_shared<const std::vector<SparseMatrix>>(o.solver.provider()(tri));
  }
  return o;
}

namespace {

// Whether a system of n vertices runs multigrid (PoissonOptions::solver): kMultigrid, or kAuto
// from its size on with a hierarchy; an empty chain (a triangulation at most the coarsest
// level's size) is one level, i.e. the factor.
// @throws InvalidInput for multigrid without a hierarchy
bool multigrid_for(const PoissonOptions& options, Index n) {
  const SolverChoice& c = options.solver;
  const bool multigrid = c.kind == LinearSolverKind::kMultigrid ||
                         (c.kind == LinearSolverKind::kAuto && options.prolongations &&
                          n >= c.auto_multigrid_vertices);
  if (!multigrid || (options.prolongations && options.prolongations->empty())) return false;
  if (!options.prolongations) {
    throw InvalidInput(
        "PoissonSolver: multigrid needs a hierarchy (PoissonOptions::prolongations, or the "
        "triangulation constructor with a hierarchy provider)");
  }
  return true;
}

}  // namespace

void PoissonSolver::factor(fem::SparseMatrix&& A, const PoissonOptions& options,
                           const CholeskyAnalysis* analysis) {
  Impl& im = *impl_;
  if (im.unknown_vertex.empty()) return;
  const SolverChoice& c = options.solver;
  if (!multigrid_for(options, im.n)) {
    if (analysis) {
      im.chol.emplace(A, *analysis, options.cholesky);
    } else {
      im.chol.emplace(A, options.cholesky);
    }
    return;
  }
  const std::vector<SparseMatrix>& given = *options.prolongations;
  if (given.front().rows() != im.n) {
    throw InvalidInput("PoissonSolver: the first prolongation has " +
                       std::to_string(given.front().rows()) + " rows for " + std::to_string(im.n) +
                       " vertices");
  }
  // the hierarchy is shared with the caller (and with the other solvers built from the same
  // options): only P₀ is copied, and only when some vertex is not an unknown or is a Dirichlet
  // vertex. A pinned vertex (a decoupled row, u = 0) keeps its row of P₀: the coarse operators
  // then hold its diagonal as a penalty at its coarse vertices, and the heat and Poisson solvers
  // of one triangulation share every P (docs/decisions.md D-335).
  const std::shared_ptr<const std::vector<SparseMatrix>>& shared_chain = options.prolongations;
  std::vector<std::shared_ptr<const SparseMatrix>> chain;
  chain.reserve(given.size());
  for (const SparseMatrix& P : given) chain.emplace_back(shared_chain, &P);  // aliases
  if (Index(im.unknown_vertex.size()) != im.n || !im.dirichlet.empty()) {
    // P₀'s rows of the unknowns (zero rows for fixed ones kept as decoupled rows), column by
    // column: unknown ids increase with vertex ids, so the rows stay sorted (no triplets)
    std::vector<char> fixed_row(im.unknown_vertex.size(), 0);
    for (const Index r : im.fixed_rows) fixed_row[std::size_t(r)] = 1;
    const SparseMatrix& P0 = given.front();
    std::vector<int> new_row(std::size_t(P0.rows()));
    for (Eigen::Index fine = 0; fine < P0.rows(); ++fine) {
      const Index u = im.unknown[fine];
      new_row[std::size_t(fine)] = u != kInvalidIndex && !fixed_row[std::size_t(u)] ? int(u) : -1;
    }
    chain.front() = std::make_shared<SparseMatrix>(
        renumber_rows(P0, new_row, Eigen::Index(im.unknown_vertex.size())));
  }
  if (!im.pattern_values.empty()) {  // setup() wrote the values on the shared pattern
    im.mg.emplace(options.multigrid_pattern, std::move(im.pattern_values), std::move(chain),
                  c.multigrid);
    im.pattern_values = std::vector<double>();
    return;
  }
  // A holds its lower triangle (diagonal first): the multigrid levels keep that form
  im.mg.emplace(std::move(A), std::move(chain), c.multigrid,
                MultigridSolver::Stored::kLowerTriangle, options.multigrid_pattern);
}

namespace {

void check_sizes(const fem::SparseMatrix& L, Eigen::Index mass_size, const Components& comps) {
  const Eigen::Index n = L.rows();
  if (L.cols() != n || mass_size != n || static_cast<Eigen::Index>(comps.label.size()) != n) {
    throw InvalidInput("PoissonSolver: L, mass and components sizes disagree");
  }
}

}  // namespace

// Everything but the factorization: marks, numbering, the coupling; returns the matrix to factor.
fem::SparseMatrix PoissonSolver::setup(const fem::SparseMatrix& L, const Eigen::VectorXd& mass,
                                       const Components& comps, std::vector<Index> dirichlet,
                                       const PoissonOptions& options, bool keep_fixed,
                                       bool on_shared_pattern) {
  options.validate();
  check_sizes(L, mass.size(), comps);
  Impl& im = *impl_;
  im.n = static_cast<Index>(L.rows());
  im.comps = comps;
  im.mass = mass;
  std::vector<char> is_dirichlet;
  std::vector<char> comp_has_dirichlet;
  im.mark_dirichlet(dirichlet, is_dirichlet, comp_has_dirichlet);
  im.dirichlet = std::move(dirichlet);
  // pure-Neumann components: pin their lowest vertex to 0, shift to zero mean afterwards
  std::vector<char> pinned(im.n, 0);
  if (options.screening == 0.0) im.pin_floating_components(comp_has_dirichlet, pinned);
  im.number_unknowns(is_dirichlet, pinned, keep_fixed);
  im.assemble_coupling(L);
  // multigrid on a shared pattern: the values only (factor() takes them from im)
  if (on_shared_pattern && im.values_on_pattern(L, options.screening, *options.multigrid_pattern)) {
    return fem::SparseMatrix();
  }
  // Direct CSC assembly, no triplets (sorting triplets cost more than half a
  // factorization at 100k faces).
  return im.assemble_unknown_block(L, options.screening);
}

PoissonSolver::PoissonSolver(const fem::SparseMatrix& L, const Eigen::VectorXd& mass,
                             const Components& comps, std::vector<Index> dirichlet,
                             const PoissonOptions& options)
    : impl_(std::make_unique<Impl>()) {
  // multigrid without Dirichlet vertices keeps the pinned vertices in the system as decoupled
  // rows: every vertex an unknown, so P₀ is used as given (factor())
  const bool keep_pins = dirichlet.empty() && multigrid_for(options, L.rows());
  const bool on_shared_pattern = keep_pins && options.multigrid_pattern != nullptr;
  factor(setup(L, mass, comps, std::move(dirichlet), options, keep_pins, on_shared_pattern),
         options, nullptr);
}

PoissonSolver::PoissonSolver(const fem::SparseMatrix& L, const Eigen::VectorXd& mass,
                             const Components& comps, std::vector<Index> dirichlet,
                             const CholeskyAnalysis& analysis, const PoissonOptions& options)
    : impl_(std::make_unique<Impl>()) {
  fem::SparseMatrix A = setup(L, mass, comps, std::move(dirichlet), options, true, false);
  if (A.rows() != analysis.size()) {
    throw InvalidInput("PoissonSolver: the analysis is of another Laplacian or components");
  }
  factor(std::move(A), options, &analysis);
}

CholeskyAnalysis PoissonSolver::analyze(const fem::SparseMatrix& L, const Components& comps,
                                        const CholeskyOptions& options) {
  check_sizes(L, L.rows(), comps);
  Impl im;  // every vertex of a component free: L's own pattern there
  im.n = static_cast<Index>(L.rows());
  im.comps = comps;
  im.mass = Eigen::VectorXd::Zero(L.rows());
  const std::vector<char> none(im.n, 0);
  im.number_unknowns(none, none, false);
  if (im.unknown_vertex.empty()) {
    throw InvalidInput("PoissonSolver::analyze: no vertex is in a component");
  }
  return CholeskyAnalysis(im.assemble_unknown_block(L, 0.0), options);
}

CholeskyAnalysis PoissonSolver::analyze(const intrinsic::IntrinsicTriangulation& tri,
                                        const CholeskyOptions& options) {
  // the referenced vertices, numbered in vertex order (the unknowns of analyze(L, components))
  const Index nv = tri.n_vertices();
  const auto& tails = tri.tails();
  std::vector<int> id(nv, -1);
  for (Index h = 0; h < tri.n_halfedges(); ++h) id[tails[h]] = 0;
  int n = 0;
  for (Index v = 0; v < nv; ++v) {
    if (id[v] == 0) id[v] = n++;
  }
  if (n == 0) throw InvalidInput("PoissonSolver::analyze: the triangulation has no faces");
  // each edge once, from its first halfedge (in memory order: no edge → halfedge lookups), as
  // (lower end, upper end)
  const auto& twins = tri.twins();
  std::vector<std::pair<int, int>> ends;
  ends.reserve(tri.n_edges());
  for (Index h = 0; h < tri.n_halfedges(); ++h) {
    if (twins[h] != kInvalidIndex && twins[h] < h) continue;
    const int a = id[tails[h]], b = id[tails[intrinsic::IntrinsicTriangulation::next(h)]];
    if (a != b) ends.emplace_back(std::min(a, b), std::max(a, b));  // a self-edge: nothing in L
  }
  // L's lower triangle: the diagonal, then each edge in its lower end's column, sorted,
  // parallel edges merged
  fem::SparseMatrix P(n, n);
  int* outer = P.outerIndexPtr();
  std::fill(outer, outer + n + 1, 0);
  for (const auto& [j, i] : ends) ++outer[j + 1];
  for (int j = 0; j < n; ++j) outer[j + 1] += outer[j] + 1;
  P.resizeNonZeros(outer[n]);
  int* inner = P.innerIndexPtr();
  std::vector<int> fill(outer, outer + n);
  for (int j = 0; j < n; ++j) inner[fill[j]++] = j;
  for (const auto& [j, i] : ends) inner[fill[j]++] = i;
  int nz = 0;
  for (int j = 0; j < n; ++j) {
    const int begin = outer[j], end = outer[j + 1];
    for (int k = begin + 2; k < end; ++k) {  // insertion sort: a column holds a few edges
      const int r = inner[k];
      int m = k;
      for (; m > begin + 1 && inner[m - 1] > r; --m) inner[m] = inner[m - 1];
      inner[m] = r;
    }
    outer[j] = nz;
    for (int k = begin; k < end; ++k) {
      if (k == begin || inner[k] != inner[k - 1]) inner[nz++] = inner[k];
    }
  }
  outer[n] = nz;
  P.data().resize(nz);
  std::fill(P.valuePtr(), P.valuePtr() + nz, 0.0);
  if (!options.ordering.empty() || !options.force_amd || options.force_metis) {
    return CholeskyAnalysis(P, options);
  }
  // AMD on these lists (each edge once; the diagonal is a self-loop, which it drops)
  CholeskyOptions given = options;
  given.ordering =
      amd_ordering(n, std::vector<int>(outer, outer + n + 1), std::vector<int>(inner, inner + nz));
  return CholeskyAnalysis(P, given);
}

PoissonSolver::~PoissonSolver() = default;
PoissonSolver::PoissonSolver(PoissonSolver&&) noexcept = default;
PoissonSolver& PoissonSolver::operator=(PoissonSolver&&) noexcept = default;

Eigen::VectorXd PoissonSolver::solve_weak(const Eigen::VectorXd& b,
                                          const Eigen::VectorXd& g) const {
  const Impl& im = *impl_;
  if (b.size() != im.n) {
    throw InvalidInput("PoissonSolver::solve: right-hand side has " + std::to_string(b.size()) +
                       " values, expected #V = " + std::to_string(im.n));
  }
  if (g.size() != static_cast<Eigen::Index>(im.dirichlet.size())) {
    throw InvalidInput("PoissonSolver::solve: " + std::to_string(g.size()) +
                       " Dirichlet values for " + std::to_string(im.dirichlet.size()) +
                       " Dirichlet vertices");
  }
  if (!b.allFinite() || !g.allFinite()) {
    throw InvalidInput("PoissonSolver::solve: non-finite right-hand side or Dirichlet value");
  }
  return im.solve_one(b, g);
}

Eigen::VectorXd PoissonSolver::solve(const Eigen::VectorXd& f, const Eigen::VectorXd& g) const {
  if (f.size() != impl_->n) {
    throw InvalidInput("PoissonSolver::solve: f has " + std::to_string(f.size()) +
                       " values, expected #V = " + std::to_string(impl_->n));
  }
  return solve_weak(impl_->mass.cwiseProduct(f), g);
}

Eigen::MatrixXd PoissonSolver::solve_weak_homogeneous(const Eigen::MatrixXd& B) const {
  const Impl& im = *impl_;
  if (B.rows() != im.n) throw InvalidInput("PoissonSolver::solve_weak_homogeneous: wrong rows");
  const Eigen::MatrixXd G = Eigen::MatrixXd::Zero(Eigen::Index(im.dirichlet.size()), B.cols());
  return im.solve_many(B, &G);
}

void PoissonBlocks::solve_in_place(const PoissonSolver& p, Eigen::Ref<Eigen::MatrixXd> B) {
  const PoissonSolver::Impl& im = *p.impl_;
  if (B.rows() != im.n || (B.cols() > 1 && B.outerStride() != B.rows())) {
    throw InvalidInput("PoissonBlocks::solve_in_place: need #V rows, columns contiguous");
  }
  if (Index(im.unknown_vertex.size()) != im.n) {  // unknowns renumbered: through solve_many
    const Eigen::MatrixXd G = Eigen::MatrixXd::Zero(Eigen::Index(im.dirichlet.size()), B.cols());
    B = im.solve_many(Eigen::MatrixXd(B), &G);
    return;
  }
  im.solve_many_identity(B);
}

void PoissonBlocks::solve_rows_in_place(const PoissonSolver& p, double* X, Eigen::Index k,
                                        bool zero_mean) {
  const PoissonSolver::Impl& im = *p.impl_;
  if (k < 1) throw InvalidInput("PoissonBlocks::solve_rows_in_place: k < 1");
  using RowBlock =
      Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>;
  RowBlock rows(X, im.n, k);
  if (!im.rows_direct()) {
    Eigen::MatrixXd B = rows;
    solve_in_place(p, B);
    rows = B;
    return;  // (with the zero mean: it costs nothing extra here)
  }
  im.solve_rows(X, k, zero_mean, nullptr, nullptr);
}

const std::vector<int>* PoissonBlocks::block_order(const PoissonSolver& p) {
  const PoissonSolver::Impl& im = *p.impl_;
  return im.rows_direct() && im.n > 0 && im.chol ? CholeskyBlocks::block_order(*im.chol) : nullptr;
}

const Eigen::VectorXd* PoissonBlocks::compatibility_weights(const PoissonSolver& p) {
  return p.impl_->one_floating ? &p.impl_->floating_one : nullptr;
}

void PoissonBlocks::solve_rows_in_order(const PoissonSolver& p, double* W, Eigen::Index k,
                                        bool zero_mean, const int* source_rows,
                                        const double* compat_sums) {
  const std::vector<int>* order = block_order(p);
  if (!order || k < 2) {
    throw InvalidInput("PoissonBlocks::solve_rows_in_order: " +
                       std::string(order ? "needs two or more columns" : "no block order here"));
  }
  p.impl_->solve_rows(W, k, zero_mean, order, source_rows, compat_sums);
}

const std::vector<Index>& PoissonSolver::dirichlet_vertices() const { return impl_->dirichlet; }
Index PoissonSolver::n_unknowns() const { return Index(impl_->unknown_vertex.size()); }
bool PoissonSolver::multigrid() const { return impl_->mg.has_value(); }
std::shared_ptr<const SparseMatrix> PoissonSolver::multigrid_pattern() const {
  return impl_->mg ? impl_->mg->fine_pattern() : nullptr;
}
double PoissonSolver::factor_nonzeros() const {
  return impl_->chol ? impl_->chol->factor_nonzeros() : 0.0;
}

Eigen::VectorXd solve_poisson(const intrinsic::IntrinsicTriangulation& tri,
                              const Eigen::VectorXd& f,
                              const std::vector<Index>& dirichlet_vertices,
                              const Eigen::VectorXd& dirichlet_values,
                              const PoissonOptions& options) {
  if (f.size() != tri.n_vertices()) {
    throw InvalidInput("solve_poisson: f has " + std::to_string(f.size()) +
                       " values, expected #V = " + std::to_string(tri.n_vertices()));
  }
  if (dirichlet_values.size() != static_cast<Eigen::Index>(dirichlet_vertices.size())) {
    throw InvalidInput("solve_poisson: " + std::to_string(dirichlet_values.size()) +
                       " Dirichlet values for " + std::to_string(dirichlet_vertices.size()) +
                       " vertices");
  }
  const PoissonSolver solver(tri, dirichlet_vertices, options);
  return solver.solve(f, dirichlet_values);
}

}  // namespace ifem::solvers
