#include "solvers/linalg/multigrid.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <exception>
#include <mutex>
#include <optional>
#include <string>
#include <utility>

#include "intrinsic/core/errors.h"

namespace ifem::solvers {

void MultigridOptions::validate() const {
  if (smoothing_steps < 1) throw InvalidInput("MultigridOptions: smoothing_steps must be ≥ 1");
  if (!(jacobi_weight > 0.0 && jacobi_weight <= 1.0)) {
    throw InvalidInput("MultigridOptions: jacobi_weight must lie in (0, 1]");
  }
  if (!(tolerance > 0.0 && tolerance < 1.0)) {
    throw InvalidInput("MultigridOptions: tolerance must lie in (0, 1)");
  }
  if (max_iterations < 1) throw InvalidInput("MultigridOptions: max_iterations must be ≥ 1");
  coarsest.validate();
}

SparseMatrix renumber_rows(const SparseMatrix& P, const std::vector<int>& new_row,
                           Eigen::Index rows) {
  SparseMatrix out(rows, P.cols());
  int* outer = out.outerIndexPtr();
  outer[0] = 0;
  for (int j = 0; j < int(P.cols()); ++j) {
    int count = 0;
    for (SparseMatrix::InnerIterator it(P, j); it; ++it) {
      count += new_row[std::size_t(it.row())] >= 0;
    }
    outer[j + 1] = outer[j] + count;
  }
  out.resizeNonZeros(outer[P.cols()]);
  int k = 0;
  for (int j = 0; j < int(P.cols()); ++j) {
    for (SparseMatrix::InnerIterator it(P, j); it; ++it) {
      const int r = new_row[std::size_t(it.row())];
      if (r < 0) continue;
      out.innerIndexPtr()[k] = r;
      out.valuePtr()[k++] = it.value();
    }
  }
  return out;
}

namespace {

// to = from's storage, from left empty (Eigen 3.4's SparseMatrix has no move operations: a
// std::move() copies).
void take(SparseMatrix& to, SparseMatrix& from) {
  to = SparseMatrix();
  to.swap(from);
}

// Each level's operator is kept as its lower triangle (CSC, sorted rows, the diagonal first in
// every column): half the entries of both triangles, and every kernel below reads a column once.
// A level's operator as the kernels read it: a lower triangle, diagonal first.
using LowerMap = Eigen::Map<const SparseMatrix>;

struct Level {
  // this level's operator, lower triangle, diagonal first (a_ii = value[outer[i]]); on a fine
  // level that shares its pattern (D-365), another solver's fine operator, whose index arrays
  // are read with own_values
  std::shared_ptr<const SparseMatrix> A;
  std::vector<double> own_values;  // empty unless the pattern is shared
  // to the next coarser level (null on the coarsest); shared with the caller when used as given
  std::shared_ptr<const SparseMatrix> P;
  LowerMap op() const {
    return LowerMap(A->rows(), A->cols(), A->nonZeros(), A->outerIndexPtr(), A->innerIndexPtr(),
                    own_values.empty() ? A->valuePtr() : own_values.data());
  }
};

// y = A x for A symmetric, stored as its lower triangle (diagonal first).
void symmetric_multiply(const LowerMap& A, const double* x, double* y) {
  const int n = int(A.cols());
  const int* outer = A.outerIndexPtr();
  const int* inner = A.innerIndexPtr();
  const double* val = A.valuePtr();
  std::fill(y, y + n, 0.0);
  for (int j = 0; j < n; ++j) {
    const double xj = x[j];
    double s = val[outer[j]] * xj;
    for (int k = outer[j] + 1; k < outer[j + 1]; ++k) {
      const int i = inner[k];
      s += val[k] * x[i];
      y[i] += val[k] * xj;
    }
    y[j] += s;
  }
}

// The ids of P's columns with a nonzero value, in `kept`; when some column has none, `dropped`
// receives P without them (left untouched otherwise). Returns whether any column was dropped.
bool drop_empty_columns(const SparseMatrix& P, std::vector<int>& kept, SparseMatrix& dropped) {
  kept.clear();
  for (int j = 0; j < int(P.cols()); ++j) {
    bool any = false;
    for (SparseMatrix::InnerIterator it(P, j); it && !any; ++it) any = it.value() != 0.0;
    if (any) kept.push_back(j);
  }
  if (Eigen::Index(kept.size()) == P.cols()) return false;
  dropped.resize(P.rows(), Eigen::Index(kept.size()));
  dropped.reserve(P.nonZeros());
  for (int c = 0; c < int(kept.size()); ++c) {
    dropped.startVec(c);
    for (SparseMatrix::InnerIterator it(P, kept[std::size_t(c)]); it; ++it) {
      if (it.value() != 0.0) dropped.insertBack(it.row(), c) = it.value();
    }
  }
  dropped.finalize();
  return true;
}

// The rows `rows` (increasing) of P, in that order.
SparseMatrix select_rows(const SparseMatrix& P, const std::vector<int>& rows) {
  std::vector<int> new_row(std::size_t(P.rows()), -1);
  for (std::size_t i = 0; i < rows.size(); ++i) new_row[std::size_t(rows[i])] = int(i);
  return renumber_rows(P, new_row, Eigen::Index(rows.size()));
}

// The Galerkin product's staging (galerkin_lower): per coarse column b, its slot
// [start[b], start[b + 1]) of (row, value) pairs: first the own[b] entries of G's column b with
// rows ≥ b (sorted), then the entries G_ba of later columns a (rows a, increasing).
struct GalerkinSlots {
  std::vector<int> own;
  std::vector<std::int64_t> start;
  std::vector<int> row;
  std::vector<double> value;
};

// G = PᵀBP (B = A's strict lower part plus half its diagonal, A a lower triangle with the
// diagonal first) column by column through a dense accumulator, written into the slots of the
// lower triangle of G + Gᵀ: a counting pass sizes them, the numeric pass fills them.
GalerkinSlots galerkin_slots(const LowerMap& A, const SparseMatrix& P) {
  const int nc = int(P.cols());
  const SparseMatrix Pt = P.transpose();  // column i: the coarse columns of fine row i
  const int* a_outer = A.outerIndexPtr();
  const int* a_inner = A.innerIndexPtr();
  const double* a_value = A.valuePtr();
  const int* t_outer = Pt.outerIndexPtr();
  const int* t_inner = Pt.innerIndexPtr();
  const double* t_value = Pt.valuePtr();
  std::vector<char> mark(std::size_t(nc), 0);
  std::vector<int> rows;
  // G's column b: its pattern in `rows` (unsorted), and with `acc` its values
  auto column = [&](int b, double* acc) {
    rows.clear();
    for (SparseMatrix::InnerIterator pk(P, b); pk; ++pk) {
      const int k = int(pk.row());
      for (int q = a_outer[k]; q < a_outer[k + 1]; ++q) {
        const int i = a_inner[q];
        const double w = pk.value() * (q == a_outer[k] ? 0.5 * a_value[q] : a_value[q]);
        for (int r = t_outer[i]; r < t_outer[i + 1]; ++r) {
          const int c = t_inner[r];
          if (!mark[std::size_t(c)]) {
            mark[std::size_t(c)] = 1;
            rows.push_back(c);
          }
          if (acc) acc[c] += w * t_value[r];
        }
      }
    }
    for (const int c : rows) mark[std::size_t(c)] = 0;
  };
  GalerkinSlots g;
  g.own.assign(std::size_t(nc), 0);
  g.start.assign(std::size_t(nc) + 1, 0);
  for (int b = 0; b < nc; ++b) {  // counting pass
    column(b, nullptr);
    for (const int a : rows) {
      if (a >= b) ++g.own[std::size_t(b)];
      ++g.start[std::size_t(std::min(a, b)) + 1];
    }
  }
  for (int b = 0; b < nc; ++b) g.start[std::size_t(b) + 1] += g.start[std::size_t(b)];
  g.row.resize(static_cast<std::size_t>(g.start[std::size_t(nc)]));
  g.value.resize(g.row.size());
  std::vector<std::int64_t> cursor(g.start.begin(), g.start.end() - 1);
  for (int b = 0; b < nc; ++b) cursor[std::size_t(b)] += g.own[std::size_t(b)];
  std::vector<double> acc(std::size_t(nc), 0.0);
  for (int b = 0; b < nc; ++b) {  // numeric pass
    column(b, acc.data());
    std::sort(rows.begin(), rows.end());
    std::int64_t at = g.start[std::size_t(b)];
    for (const int a : rows) {
      std::int64_t& to = a >= b ? at : cursor[std::size_t(a)];
      g.row[std::size_t(to)] = std::max(a, b);
      g.value[std::size_t(to++)] = acc[std::size_t(a)];
      acc[std::size_t(a)] = 0.0;
    }
  }
  return g;
}

// The lower triangle of the Galerkin product C = PᵀAP from A's lower triangle (diagonal first),
// P with sorted columns. With B = A's strict lower part plus half its diagonal, A = B + Bᵀ and
// C = G + Gᵀ for G = PᵀBP. G's entries G_ab with a ≥ b belong to C's column b, those with a < b
// to C's column a (row b) (galerkin_slots()); each column's two sorted runs are merged here,
// duplicates summed, the diagonal 2·G_bb first, exact zeros left out. No A·P temporary, no full
// copy of A, no triplets.
SparseMatrix galerkin_lower(const LowerMap& A, const SparseMatrix& P) {
  const int nc = int(P.cols());
  const GalerkinSlots g = galerkin_slots(A, P);
  auto merge = [&](int b, auto&& emit) {
    std::int64_t p = g.start[std::size_t(b)], q = p + g.own[std::size_t(b)];
    const std::int64_t p_end = q, q_end = g.start[std::size_t(b) + 1];
    while (p < p_end || q < q_end) {
      const bool from_p =
          q == q_end || (p < p_end && g.row[std::size_t(p)] <= g.row[std::size_t(q)]);
      const bool both = from_p && q < q_end && g.row[std::size_t(p)] == g.row[std::size_t(q)];
      const int row = g.row[std::size_t(from_p ? p : q)];
      double v = from_p ? g.value[std::size_t(p++)] : g.value[std::size_t(q++)];
      if (both) v += g.value[std::size_t(q++)];
      if (row == b) {
        emit(row, 2.0 * v);
      } else if (v != 0.0) {
        emit(row, v);
      }
    }
  };
  SparseMatrix out(nc, nc);
  int* outer = out.outerIndexPtr();
  outer[0] = 0;
  for (int b = 0; b < nc; ++b) {
    int count = 0;
    merge(b, [&](int, double) { ++count; });
    outer[b + 1] = outer[b] + count;
  }
  out.resizeNonZeros(outer[nc]);
  int* inner = out.innerIndexPtr();
  double* value = out.valuePtr();
  int k = 0;
  for (int b = 0; b < nc; ++b) {
    merge(b, [&](int row, double v) {
      inner[k] = row;
      value[k++] = v;
    });
  }
  return out;
}

// Checks a lower triangle (level `level`): rows increasing below a leading diagonal entry in
// every column, and the diagonal positive (the kernels read it as the column's first value).
// @throws InvalidInput on rows out of order; SolverError on a missing or non-positive diagonal
void check_lower(const LowerMap& A, std::size_t level) {
  const int* outer = A.outerIndexPtr();
  const int* inner = A.innerIndexPtr();
  for (int j = 0; j < int(A.cols()); ++j) {
    for (int k = outer[j]; k < outer[j + 1]; ++k) {
      if (inner[k] < j || (k > outer[j] && inner[k] <= inner[k - 1])) {
        throw InvalidInput(
            "MultigridSolver: the lower triangle's rows must increase within each column "
            "(level " +
            std::to_string(level) + ", column " + std::to_string(j) + ")");
      }
    }
    const double diag =
        outer[j] < outer[j + 1] && inner[outer[j]] == j ? A.valuePtr()[outer[j]] : 0.0;
    if (!(diag > 0.0)) {
      throw SolverError("MultigridSolver: level " + std::to_string(level) + " row " +
                        std::to_string(j) + " has diagonal " + std::to_string(diag) +
                        " (A must be positive definite)");
    }
  }
}

void check_finite(const SparseMatrix& A, const char* what) {
  for (Eigen::Index k = 0; k < A.nonZeros(); ++k) {
    if (!std::isfinite(A.valuePtr()[k])) {
      throw InvalidInput(std::string("MultigridSolver: ") + what + " has a non-finite entry");
    }
  }
}

// Whether lower triangle A has exactly the pattern of `pattern` (same size, column starts and
// rows; both compressed). Null: no.
bool same_pattern(const SparseMatrix& A, const SparseMatrix* pattern) {
  if (!pattern || !pattern->isCompressed() || !A.isCompressed() || pattern->rows() != A.rows() ||
      pattern->cols() != A.cols() || pattern->nonZeros() != A.nonZeros()) {
    return false;
  }
  return std::equal(A.outerIndexPtr(), A.outerIndexPtr() + A.cols() + 1,
                    pattern->outerIndexPtr()) &&
         std::equal(A.innerIndexPtr(), A.innerIndexPtr() + A.nonZeros(), pattern->innerIndexPtr());
}

}  // namespace

struct MultigridSolver::Impl {
  MultigridOptions opt;
  std::vector<Level> levels;
  std::optional<CholeskySolver> coarsest;

  // Forward Gauss–Seidel sweep on the correction: d_i = (r_i − Σ_{j<i} a_ij d_j) / a_ii in
  // increasing i, i.e. x + d is one sweep from x when r = b − Ax. Column i of the lower triangle
  // holds a_ki (k > i): each d_i is pushed into the later rows of r, which is overwritten.
  static void forward_sweep(const Level& lv, Eigen::VectorXd& r, Eigen::VectorXd& d) {
    const int n = int(lv.op().cols());
    const int* start = lv.op().outerIndexPtr();
    const int* row = lv.op().innerIndexPtr();
    const double* val = lv.op().valuePtr();
    d.resize(n);
    for (int i = 0; i < n; ++i) {
      const double di = r[i] / val[start[i]];
      d[i] = di;
      for (int k = start[i] + 1; k < start[i + 1]; ++k) r[row[k]] -= val[k] * di;
    }
  }

  // After a forward sweep with correction d, the residual b − A(x + d): row i's equation holds
  // with the rows before it updated, so r_i = −Σ_{j>i} a_ij d_j (column i below the diagonal).
  static void residual_after_forward(const Level& lv, const Eigen::VectorXd& d,
                                     Eigen::VectorXd& r) {
    const int n = int(lv.op().cols());
    const int* start = lv.op().outerIndexPtr();
    const int* row = lv.op().innerIndexPtr();
    const double* val = lv.op().valuePtr();
    r.resize(n);
    for (int i = 0; i < n; ++i) {
      double s = 0.0;
      for (int k = start[i] + 1; k < start[i + 1]; ++k) s -= val[k] * d[row[k]];
      r[i] = s;
    }
  }

  // Backward Gauss–Seidel sweep on the correction: d_i = (r_i − Σ_{j>i} a_ij d_j) / a_ii in
  // decreasing i (column i below the diagonal holds those a_ij).
  static void backward_sweep(const Level& lv, const Eigen::VectorXd& r, Eigen::VectorXd& d) {
    const int n = int(lv.op().cols());
    const int* start = lv.op().outerIndexPtr();
    const int* row = lv.op().innerIndexPtr();
    const double* val = lv.op().valuePtr();
    d.resize(n);
    for (int i = n - 1; i >= 0; --i) {
      double s = r[i];
      for (int k = start[i] + 1; k < start[i + 1]; ++k) s -= val[k] * d[row[k]];
      d[i] = s / val[start[i]];
    }
  }

  // x += ω D⁻¹ r (damped Jacobi)
  void jacobi_step(const Level& lv, const Eigen::VectorXd& r, Eigen::VectorXd& x) const {
    const int* start = lv.op().outerIndexPtr();
    const double* val = lv.op().valuePtr();
    for (Eigen::Index i = 0; i < x.size(); ++i) x[i] += opt.jacobi_weight * r[i] / val[start[i]];
  }

  // r = b − A x
  static void residual(const Level& lv, const Eigen::VectorXd& b, const Eigen::VectorXd& x,
                       Eigen::VectorXd& r) {
    r.resize(b.size());
    symmetric_multiply(lv.op(), x.data(), r.data());
    r = b - r;
  }

  // Pre-smoothing from x = 0: x after the sweeps and r = b − Ax.
  void pre_smooth(const Level& lv, const Eigen::VectorXd& b, Eigen::VectorXd& x,
                  Eigen::VectorXd& r) const {
    const bool jacobi = opt.smoother == MultigridOptions::Smoother::kJacobi;
    x.setZero(b.size());
    r = b;
    Eigen::VectorXd d;
    for (int s = 0; s < opt.smoothing_steps; ++s) {
      if (jacobi) {
        jacobi_step(lv, r, x);
        residual(lv, b, x, r);
      } else {
        forward_sweep(lv, r, d);
        x += d;
        residual_after_forward(lv, d, r);
      }
    }
  }

  // Post-smoothing of x (backward sweeps for Gauss–Seidel: the cycle stays symmetric).
  void post_smooth(const Level& lv, const Eigen::VectorXd& b, Eigen::VectorXd& x) const {
    const bool jacobi = opt.smoother == MultigridOptions::Smoother::kJacobi;
    Eigen::VectorXd r, d;
    for (int s = 0; s < opt.smoothing_steps; ++s) {
      residual(lv, b, x, r);
      if (jacobi) {
        jacobi_step(lv, r, x);
      } else {
        backward_sweep(lv, r, d);
        x += d;
      }
    }
  }

  // x = V-cycle applied to b on level l, from x = 0.
  void v_cycle(std::size_t l, const Eigen::VectorXd& b, Eigen::VectorXd& x) const {
    if (l + 1 == levels.size()) {
      x = coarsest->solve(b);
      return;
    }
    const Level& lv = levels[l];
    Eigen::VectorXd r;
    pre_smooth(lv, b, x, r);
    const Eigen::VectorXd coarse_b = lv.P->transpose() * r;
    r = Eigen::VectorXd();
    Eigen::VectorXd coarse_x;
    v_cycle(l + 1, coarse_b, coarse_x);
    x.noalias() += *lv.P * coarse_x;
    post_smooth(lv, b, x);
  }

  // PCG on one right-hand side.
  MultigridReport pcg(const Eigen::Ref<const Eigen::VectorXd>& b,
                      Eigen::Ref<Eigen::VectorXd> x) const {
    MultigridReport rep;
    const Level& fine = levels.front();
    const double b_norm = b.norm();
    x.setZero();
    if (b_norm == 0.0) {
      rep.converged = true;
      return rep;
    }
    Eigen::VectorXd r = b, z, p, Ap;
    v_cycle(0, r, z);
    p = z;
    double rz = r.dot(z);
    double res = b_norm;
    while (rep.iterations < opt.max_iterations) {
      Ap.resize(p.size());
      symmetric_multiply(fine.op(), p.data(), Ap.data());
      const double pAp = p.dot(Ap);
      if (!(pAp > 0.0)) break;  // breakdown: A or the cycle not definite
      const double alpha = rz / pAp;
      x += alpha * p;
      r -= alpha * Ap;
      ++rep.iterations;
      res = r.norm();
      if (res <= opt.tolerance * b_norm) break;
      v_cycle(0, r, z);
      const double rz_new = r.dot(z);
      p = z + (rz_new / rz) * p;
      rz = rz_new;
    }
    rep.relative_residual = res / b_norm;
    rep.converged = rep.relative_residual <= opt.tolerance;
    rep.reduction_per_cycle =
        rep.iterations > 0 ? std::pow(rep.relative_residual, 1.0 / rep.iterations) : 1.0;
    if (!rep.converged && opt.throw_if_not_converged) {
      throw SolverError("MultigridSolver: relative residual " +
                        std::to_string(rep.relative_residual) + " after " +
                        std::to_string(rep.iterations) + " iterations, tolerance " +
                        std::to_string(opt.tolerance) +
                        " (raise max_iterations, or the "
                        "hierarchy does not fit the matrix)");
    }
    return rep;
  }
};

namespace {

// Each P of the vector as a shared matrix, its storage swapped in (no copy).
std::vector<std::shared_ptr<const SparseMatrix>> shared(std::vector<SparseMatrix>& prolongations) {
  std::vector<std::shared_ptr<const SparseMatrix>> out;
  out.reserve(prolongations.size());
  for (SparseMatrix& P : prolongations) {
    auto p = std::make_shared<SparseMatrix>();
    p->swap(P);
    out.push_back(std::move(p));
  }
  return out;
}

// The constructors' common part: the levels from the fine operator (`current`, or `values` on
// `fine_pattern` when values is non-null) and the prolongations; the coarsest factor.
void build_levels(MultigridSolver::Impl& im, SparseMatrix& current,
                  std::shared_ptr<const SparseMatrix> fine_pattern, std::vector<double>* values,
                  std::vector<std::shared_ptr<const SparseMatrix>> prolongations,
                  const MultigridOptions& options) {
  im.opt = options;
  const Eigen::Index n = values ? fine_pattern->rows() : current.rows();
  im.levels.reserve(prolongations.size() + 1);
  std::vector<int> kept;         // the previous level's columns kept: this level's rows to keep
  Eigen::Index caller_rows = n;  // rows are checked against the caller's numbering
  for (std::size_t l = 0; l <= prolongations.size(); ++l) {
    Level& lv = im.levels.emplace_back();
    if (l == 0 && values) {  // given on another solver's pattern
      lv.A = std::move(fine_pattern);
      lv.own_values = std::move(*values);
    } else {
      if (l == 0 && !prolongations.empty() && same_pattern(current, fine_pattern.get())) {
        // the values only; the index arrays are fine_pattern's (D-365)
        lv.own_values.assign(current.valuePtr(), current.valuePtr() + current.nonZeros());
        current = SparseMatrix();
        lv.A = std::move(fine_pattern);
      } else {
        auto mine = std::make_shared<SparseMatrix>();
        take(*mine, current);
        lv.A = std::move(mine);
      }
    }
    check_lower(lv.op(), l);
    if (l == prolongations.size()) break;
    std::shared_ptr<const SparseMatrix> P = std::move(prolongations[l]);
    if (!P) throw InvalidInput("MultigridSolver: prolongation " + std::to_string(l) + " is null");
    if (P->rows() != caller_rows) {
      throw InvalidInput("MultigridSolver: prolongation " + std::to_string(l) + " has " +
                         std::to_string(P->rows()) + " rows, its level has " +
                         std::to_string(caller_rows) + " unknowns");
    }
    caller_rows = P->cols();
    check_finite(*P, "a prolongation");
    // a changed P (uncompressed, rows of dropped columns, empty columns) is this level's own
    SparseMatrix changed;
    bool own = false;
    if (!P->isCompressed()) {
      changed = *P;
      changed.makeCompressed();
      own = true;
    }
    if (l > 0 && Eigen::Index(kept.size()) != P->rows()) {
      SparseMatrix selected = select_rows(own ? changed : *P, kept);
      take(changed, selected);
      own = true;
    }
    SparseMatrix dropped;
    if (drop_empty_columns(own ? changed : *P, kept, dropped)) {
      take(changed, dropped);
      own = true;
    }
    if (own) {
      auto mine = std::make_shared<SparseMatrix>();
      mine->swap(changed);
      P = std::move(mine);
    }
    if (P->cols() == 0) throw InvalidInput("MultigridSolver: a prolongation has no column");
    SparseMatrix coarse = galerkin_lower(lv.op(), *P);
    take(current, coarse);
    lv.P = std::move(P);
  }
  im.coarsest.emplace(*im.levels.back().A, options.coarsest);  // own values (not shared)
}
}  // namespace

MultigridSolver::MultigridSolver(const SparseMatrix& A, std::vector<SparseMatrix> prolongations,
                                 const MultigridOptions& options, Stored stored)
    : MultigridSolver(SparseMatrix(A), shared(prolongations), options, stored) {}

MultigridSolver::MultigridSolver(SparseMatrix&& A, std::vector<SparseMatrix> prolongations,
                                 const MultigridOptions& options, Stored stored)
    : MultigridSolver(std::move(A), shared(prolongations), options, stored) {}

// Eigen 3.4's SparseMatrix has no move constructor or move assignment: std::move() copies. The
// levels are therefore handed on with swap() (take()), never with a move.
MultigridSolver::MultigridSolver(SparseMatrix&& A,
                                 std::vector<std::shared_ptr<const SparseMatrix>> prolongations,
                                 const MultigridOptions& options, Stored stored,
                                 std::shared_ptr<const SparseMatrix> fine_pattern)
    : impl_(std::make_unique<Impl>()) {
  options.validate();
  if (A.rows() != A.cols() || A.rows() == 0) {
    throw InvalidInput("MultigridSolver: A must be square and not empty");
  }
  check_finite(A, "A");
  SparseMatrix current;
  if (stored == Stored::kBothTriangles) {
    SparseMatrix lower = A.triangularView<Eigen::Lower>();
    A = SparseMatrix();
    take(current, lower);
  } else {
    take(current, A);
    current.makeCompressed();
  }
  build_levels(*impl_, current, std::move(fine_pattern), nullptr, std::move(prolongations),
               options);
}

MultigridSolver::MultigridSolver(std::shared_ptr<const SparseMatrix> fine_pattern,
                                 std::vector<double>&& values,
                                 std::vector<std::shared_ptr<const SparseMatrix>> prolongations,
                                 const MultigridOptions& options)
    : impl_(std::make_unique<Impl>()) {
  options.validate();
  if (!fine_pattern || fine_pattern->rows() != fine_pattern->cols() || fine_pattern->rows() == 0 ||
      !fine_pattern->isCompressed() || Eigen::Index(values.size()) != fine_pattern->nonZeros() ||
      prolongations.empty()) {
    throw InvalidInput(
        "MultigridSolver: values on a pattern need a square, compressed, non-empty pattern, one "
        "value per entry and at least one prolongation");
  }
  for (const double v : values) {
    if (!std::isfinite(v)) throw InvalidInput("MultigridSolver: A has a non-finite entry");
  }
  SparseMatrix current;
  build_levels(*impl_, current, std::move(fine_pattern), &values, std::move(prolongations),
               options);
}

MultigridSolver::~MultigridSolver() = default;
MultigridSolver::MultigridSolver(MultigridSolver&&) noexcept = default;
MultigridSolver& MultigridSolver::operator=(MultigridSolver&&) noexcept = default;

Eigen::VectorXd MultigridSolver::solve(const Eigen::VectorXd& b, MultigridReport* report) const {
  if (b.size() != size()) throw InvalidInput("MultigridSolver::solve: wrong size");
  Eigen::VectorXd x(b.size());
  const MultigridReport rep = impl_->pcg(b, x);
  if (report) *report = rep;
  return x;
}

Eigen::MatrixXd MultigridSolver::solve(const Eigen::MatrixXd& B,
                                       std::vector<MultigridReport>* reports) const {
  if (B.rows() != size()) throw InvalidInput("MultigridSolver::solve: wrong rows");
  Eigen::MatrixXd X(B.rows(), B.cols());
  std::vector<MultigridReport> reps(std::size_t(B.cols()));
  std::exception_ptr error;
  std::mutex error_lock;
#pragma omp parallel for schedule(dynamic, 1) if (B.cols() > 1)
  for (Eigen::Index j = 0; j < B.cols(); ++j) {
    try {
      reps[std::size_t(j)] = impl_->pcg(B.col(j), X.col(j));
    } catch (...) {
      const std::lock_guard<std::mutex> lock(error_lock);
      if (!error) error = std::current_exception();
    }
  }
  if (error) std::rethrow_exception(error);
  if (reports) *reports = std::move(reps);
  return X;
}

void MultigridSolver::solve(const double* b, double* x, Eigen::Index cols) const {
  if (cols < 0) throw InvalidInput("MultigridSolver::solve: negative column count");
  const Eigen::Index n = size();
  const Eigen::MatrixXd B = Eigen::Map<const Eigen::MatrixXd>(b, n, cols);
  Eigen::Map<Eigen::MatrixXd>(x, n, cols) = solve(B);
}

Eigen::VectorXd MultigridSolver::cycle(const Eigen::VectorXd& r) const {
  if (r.size() != size()) throw InvalidInput("MultigridSolver::cycle: wrong size");
  Eigen::VectorXd z;
  impl_->v_cycle(0, r, z);
  return z;
}

Eigen::Index MultigridSolver::size() const { return impl_->levels.front().A->rows(); }
int MultigridSolver::n_levels() const { return int(impl_->levels.size()); }
Eigen::Index MultigridSolver::level_size(int level) const {
  if (level < 0 || level >= n_levels()) throw InvalidInput("MultigridSolver: no such level");
  return impl_->levels[std::size_t(level)].A->rows();
}

std::shared_ptr<const SparseMatrix> MultigridSolver::fine_pattern() const {
  return impl_->levels.front().A;
}

double MultigridSolver::memory_bytes() const {
  double bytes = 0.0;
  for (const Level& lv : impl_->levels) {
    const double p_entries = lv.P ? double(lv.P->nonZeros()) : 0.0;
    const double p_cols = lv.P ? double(lv.P->cols()) : 0.0;
    const double a_entries = double(lv.A->nonZeros());
    if (lv.own_values.empty()) {
      bytes += 12.0 * a_entries + 4.0 * double(lv.A->cols());
    } else {
      bytes += 8.0 * a_entries;  // the pattern is another solver's
    }
    bytes += 12.0 * p_entries + 4.0 * p_cols;
  }
  return bytes + 12.0 * impl_->coarsest->factor_nonzeros();
}

}  // namespace ifem::solvers
