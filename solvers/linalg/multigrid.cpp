#include "solvers/linalg/multigrid.h"

#include <algorithm>
#include <cmath>
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

namespace {

struct Level {
  SparseMatrix A;        // this level's operator, both triangles
  Eigen::VectorXd diag;  // its diagonal
  SparseMatrix P;        // to the next coarser level (empty on the coarsest)
};

// P without its empty columns (no nonzero value); `kept` receives the old ids of the columns kept.
SparseMatrix drop_empty_columns(const SparseMatrix& P, std::vector<int>& kept) {
  kept.clear();
  for (int j = 0; j < int(P.cols()); ++j) {
    bool any = false;
    for (SparseMatrix::InnerIterator it(P, j); it && !any; ++it) any = it.value() != 0.0;
    if (any) kept.push_back(j);
  }
  if (Eigen::Index(kept.size()) == P.cols()) return P;
  SparseMatrix out(P.rows(), Eigen::Index(kept.size()));
  out.reserve(P.nonZeros());
  for (int c = 0; c < int(kept.size()); ++c) {
    out.startVec(c);
    for (SparseMatrix::InnerIterator it(P, kept[std::size_t(c)]); it; ++it) {
      if (it.value() != 0.0) out.insertBack(it.row(), c) = it.value();
    }
  }
  out.finalize();
  return out;
}

// The rows `rows` of P, in that order.
SparseMatrix select_rows(const SparseMatrix& P, const std::vector<int>& rows) {
  std::vector<int> new_row(std::size_t(P.rows()), -1);
  for (std::size_t i = 0; i < rows.size(); ++i) new_row[std::size_t(rows[i])] = int(i);
  std::vector<Eigen::Triplet<double>> t;
  t.reserve(std::size_t(P.nonZeros()));
  for (int j = 0; j < int(P.cols()); ++j) {
    for (SparseMatrix::InnerIterator it(P, j); it; ++it) {
      const int r = new_row[std::size_t(it.row())];
      if (r >= 0) t.emplace_back(r, j, it.value());
    }
  }
  SparseMatrix out(Eigen::Index(rows.size()), P.cols());
  out.setFromTriplets(t.begin(), t.end());
  return out;
}

// The Galerkin product PᵀAP (A square with both triangles stored, P with sorted columns), one
// coarse column at a time through a dense accumulator: no A·P temporary (which holds about as
// many entries as A), sorted columns, exact zeros kept out.
SparseMatrix galerkin(const SparseMatrix& A, const SparseMatrix& P) {
  const int nc = int(P.cols());
  const SparseMatrix Pt = P.transpose();  // column i: the coarse columns of fine row i
  const int* a_outer = A.outerIndexPtr();
  const int* a_inner = A.innerIndexPtr();
  const double* a_value = A.valuePtr();
  const int* t_outer = Pt.outerIndexPtr();
  const int* t_inner = Pt.innerIndexPtr();
  const double* t_value = Pt.valuePtr();
  std::vector<double> acc(std::size_t(nc), 0.0);
  std::vector<char> mark(std::size_t(nc), 0);
  std::vector<int> rows, inner, outer(std::size_t(nc) + 1, 0);
  std::vector<double> value;
  inner.reserve(std::size_t(P.nonZeros()) * 4);
  value.reserve(inner.capacity());
  for (int j = 0; j < nc; ++j) {
    rows.clear();
    for (SparseMatrix::InnerIterator pk(P, j); pk; ++pk) {
      const int k = int(pk.row());
      for (int q = a_outer[k]; q < a_outer[k + 1]; ++q) {
        const int i = a_inner[q];
        const double w = pk.value() * a_value[q];
        for (int r = t_outer[i]; r < t_outer[i + 1]; ++r) {
          const int c = t_inner[r];
          if (!mark[std::size_t(c)]) {
            mark[std::size_t(c)] = 1;
            rows.push_back(c);
          }
          acc[std::size_t(c)] += w * t_value[r];
        }
      }
    }
    std::sort(rows.begin(), rows.end());
    for (const int c : rows) {
      if (acc[std::size_t(c)] != 0.0) {
        inner.push_back(c);
        value.push_back(acc[std::size_t(c)]);
      }
      acc[std::size_t(c)] = 0.0;
      mark[std::size_t(c)] = 0;
    }
    outer[std::size_t(j) + 1] = int(inner.size());
  }
  SparseMatrix out(nc, nc);
  out.resizeNonZeros(Eigen::Index(inner.size()));
  std::copy(outer.begin(), outer.end(), out.outerIndexPtr());
  std::copy(inner.begin(), inner.end(), out.innerIndexPtr());
  std::copy(value.begin(), value.end(), out.valuePtr());
  return out;
}

void check_finite(const SparseMatrix& A, const char* what) {
  for (Eigen::Index k = 0; k < A.nonZeros(); ++k) {
    if (!std::isfinite(A.valuePtr()[k])) {
      throw InvalidInput(std::string("MultigridSolver: ") + what + " has a non-finite entry");
    }
  }
}

}  // namespace

struct MultigridSolver::Impl {
  MultigridOptions opt;
  std::vector<Level> levels;
  std::optional<CholeskySolver> coarsest;

  // Gauss–Seidel sweep over the rows in increasing (forward) or decreasing order. A is
  // symmetric, so column i holds row i.
  void gauss_seidel(const Level& lv, const Eigen::VectorXd& b, Eigen::VectorXd& x,
                    bool forward) const {
    const int n = int(lv.A.rows());
    const int* start = lv.A.outerIndexPtr();
    const int* row = lv.A.innerIndexPtr();
    const double* val = lv.A.valuePtr();
    for (int s = 0; s < n; ++s) {
      const int i = forward ? s : n - 1 - s;
      double sum = b[i];
      for (int k = start[i]; k < start[i + 1]; ++k) sum -= val[k] * x[row[k]];
      x[i] += sum / lv.diag[i];  // sum included the diagonal term: x_i = (b_i − Σ_{j≠i}) / a_ii
    }
  }

  void jacobi(const Level& lv, const Eigen::VectorXd& b, Eigen::VectorXd& x) const {
    const Eigen::VectorXd r = b - lv.A * x;
    x.array() += opt.jacobi_weight * r.array() / lv.diag.array();
  }

  void smooth(const Level& lv, const Eigen::VectorXd& b, Eigen::VectorXd& x, bool pre) const {
    for (int s = 0; s < opt.smoothing_steps; ++s) {
      if (opt.smoother == MultigridOptions::Smoother::kJacobi) {
        jacobi(lv, b, x);
      } else {
        gauss_seidel(lv, b, x, pre);
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
    x.setZero(b.size());
    smooth(lv, b, x, true);
    const Eigen::VectorXd coarse_b = lv.P.transpose() * (b - lv.A * x);
    Eigen::VectorXd coarse_x;
    v_cycle(l + 1, coarse_b, coarse_x);
    x.noalias() += lv.P * coarse_x;
    smooth(lv, b, x, false);
  }

  // PCG on one right-hand side.
  MultigridReport pcg(const Eigen::Ref<const Eigen::VectorXd>& b,
                      Eigen::Ref<Eigen::VectorXd> x) const {
    MultigridReport rep;
    const SparseMatrix& A = levels.front().A;
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
      Ap.noalias() = A * p;
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

MultigridSolver::MultigridSolver(SparseMatrix A, const std::vector<SparseMatrix>& prolongations,
                                 const MultigridOptions& options)
    : impl_(std::make_unique<Impl>()) {
  options.validate();
  if (A.rows() != A.cols() || A.rows() == 0) {
    throw InvalidInput("MultigridSolver: A must be square and not empty");
  }
  check_finite(A, "A");
  Impl& im = *impl_;
  im.opt = options;
  const Eigen::Index n = A.rows();
  SparseMatrix current = std::move(A);
  current.makeCompressed();
  im.levels.reserve(prolongations.size() + 1);  // no copies of the levels while they are added
  std::vector<int> kept;  // the previous level's columns kept: this level's rows to keep
  for (std::size_t l = 0; l <= prolongations.size(); ++l) {
    Level lv;
    lv.A = std::move(current);
    lv.diag = lv.A.diagonal();
    if (l < prolongations.size()) {
      const SparseMatrix& given = prolongations[l];
      // rows are checked against the caller's numbering (before any dropped column)
      const Eigen::Index caller_rows = l == 0 ? n : prolongations[l - 1].cols();
      if (given.rows() != caller_rows) {
        throw InvalidInput("MultigridSolver: prolongation " + std::to_string(l) + " has " +
                           std::to_string(given.rows()) + " rows, its level has " +
                           std::to_string(caller_rows) + " unknowns");
      }
      check_finite(given, "a prolongation");
      SparseMatrix P =
          l == 0 || Eigen::Index(kept.size()) == given.rows() ? given : select_rows(given, kept);
      P = drop_empty_columns(P, kept);
      if (P.cols() == 0) throw InvalidInput("MultigridSolver: a prolongation has no column");
      current = galerkin(lv.A, P);
      lv.P = std::move(P);
    }
    for (Eigen::Index i = 0; i < lv.diag.size(); ++i) {
      if (!(lv.diag[i] > 0.0)) {
        throw SolverError("MultigridSolver: level " + std::to_string(l) + " row " +
                          std::to_string(i) + " has diagonal " + std::to_string(lv.diag[i]) +
                          " (A must be positive definite)");
      }
    }
    im.levels.push_back(std::move(lv));
  }
  im.coarsest.emplace(im.levels.back().A, options.coarsest);
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

Eigen::Index MultigridSolver::size() const { return impl_->levels.front().A.rows(); }
int MultigridSolver::n_levels() const { return int(impl_->levels.size()); }
Eigen::Index MultigridSolver::level_size(int level) const {
  if (level < 0 || level >= n_levels()) throw InvalidInput("MultigridSolver: no such level");
  return impl_->levels[std::size_t(level)].A.rows();
}

double MultigridSolver::memory_bytes() const {
  double bytes = 0.0;
  for (const Level& lv : impl_->levels) {
    bytes += 12.0 * double(lv.A.nonZeros() + lv.P.nonZeros()) +
             4.0 * double(lv.A.cols() + lv.P.cols()) + 8.0 * double(lv.diag.size());
  }
  return bytes + 12.0 * impl_->coarsest->factor_nonzeros();
}

}  // namespace ifem::solvers
