#include "solvers/scalar/eigen.h"

#include <Spectra/SymGEigsShiftSolver.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "fem/prolongation.h"
#include "intrinsic/core/errors.h"
#include "intrinsic/simplify/simplify.h"
#include "solvers/linalg/cholesky.h"

namespace ifem::solvers {

namespace {

// Spectra shift-invert operator: y = (L − σM)⁻¹ x through CholeskySolver.
class ShiftInvertOp {
 public:
  using Scalar = double;
  ShiftInvertOp(const fem::SparseMatrix& L, const Eigen::VectorXd& m) : L_(L), m_(m) {}
  Eigen::Index rows() const { return L_.rows(); }
  Eigen::Index cols() const { return L_.cols(); }
  void set_shift(double sigma) {
    // lower triangle of L − σM (all CHOLMOD reads)
    fem::SparseMatrix A = L_.triangularView<Eigen::Lower>();
    std::vector<Eigen::Index>
        missing;  // columns without a stored diagonal (not from cotan_laplacian)
    for (Eigen::Index j = 0; j < A.outerSize(); ++j) {
      bool found = false;
      for (fem::SparseMatrix::InnerIterator it(A, j); it; ++it) {
        if (it.row() == j) {
          it.valueRef() -= sigma * m_[j];
          found = true;
        }
      }
      if (!found) missing.push_back(j);
    }
    for (const Eigen::Index j : missing) A.coeffRef(j, j) = -sigma * m_[j];
    A.makeCompressed();
    // one BLAS thread: OpenBLAS's factor differs in round-off between thread counts (the k = 50
    // eigenvectors then differ inside degenerate clusters), and was no slower at this size
    // (docs/decisions.md, "Eigenpairs: Spectra, factor at one BLAS thread")
    CholeskyOptions copt;
    copt.factor_blas_threads = 1;
    chol_ = std::make_unique<CholeskySolver>(A, copt);
  }
  // one back-substitution per Lanczos step: no allocation (CHOLMOD's workspace is kept)
  void perform_op(const double* x, double* y) const {
    chol_->solve(x, y);
    if (meter_) meter_->update(++solves_);
  }
  // counts the back-substitutions into `meter` from now on
  void report_to(ProgressMeter* meter) { meter_ = meter; }

 private:
  ProgressMeter* meter_ = nullptr;
  mutable double solves_ = 0.0;
  const fem::SparseMatrix& L_;
  const Eigen::VectorXd& m_;
  std::unique_ptr<CholeskySolver> chol_;
};

// B operator: the diagonal lumped mass.
class DiagonalOp {
 public:
  using Scalar = double;
  explicit DiagonalOp(const Eigen::VectorXd& m) : m_(m) {}
  Eigen::Index rows() const { return m_.size(); }
  Eigen::Index cols() const { return m_.size(); }
  void perform_op(const double* x, double* y) const {
    for (Eigen::Index i = 0; i < m_.size(); ++i) y[i] = m_[i] * x[i];
  }

 private:
  const Eigen::VectorXd& m_;
};

// The problem on the referenced vertices (positive mass) and their ids in the input.
struct Restricted {
  fem::SparseMatrix L;
  Eigen::VectorXd m;
  std::vector<Index> vertex;
};

Restricted restrict_to_mass(const fem::SparseMatrix& L_full, const Eigen::VectorXd& mass_full) {
  const Index n = Index(L_full.rows());
  Restricted p;
  std::vector<Index> id(n, kInvalidIndex);
  for (Index v = 0; v < n; ++v) {
    if (mass_full[v] > 0.0) {
      id[v] = Index(p.vertex.size());
      p.vertex.push_back(v);
    }
  }
  const Index nr = Index(p.vertex.size());
  if (nr == n) {
    p.L = L_full;
    p.m = mass_full;
  } else {
    std::vector<Eigen::Triplet<double>> trip;
    for (Index j = 0; j < n; ++j) {
      if (id[j] == kInvalidIndex) continue;
      for (fem::SparseMatrix::InnerIterator it(L_full, j); it; ++it) {
        if (id[it.row()] != kInvalidIndex) trip.emplace_back(id[it.row()], id[j], it.value());
      }
    }
    p.L.resize(nr, nr);
    p.L.setFromTriplets(trip.begin(), trip.end());
    p.m.resize(nr);
    for (Index i = 0; i < nr; ++i) p.m[i] = mass_full[p.vertex[i]];
  }
  p.L.makeCompressed();
  return p;
}

// ‖Lφ − λMφ‖₂ / ‖λMφ‖₂ per pair (EigenPairs::residuals).
Eigen::VectorXd relative_residuals(const fem::SparseMatrix& L, const Eigen::VectorXd& m,
                                   const Eigen::VectorXd& values, const Eigen::MatrixXd& vectors) {
  const Index k = Index(values.size());
  Eigen::VectorXd r(k);
  const double scale = k > 0 ? values.cwiseAbs().maxCoeff() : 0.0;
  for (Index j = 0; j < k; ++j) {
    const Eigen::VectorXd mx = m.cwiseProduct(vectors.col(j));
    const double lambda = std::abs(values[j]) < 1e-9 * scale ? scale : std::abs(values[j]);
    const double denominator = lambda * mx.norm();
    r[j] = denominator > 0.0 ? (L * vectors.col(j) - values[j] * mx).norm() / denominator : 0.0;
  }
  return r;
}

// Rayleigh–Ritz of L φ = λ M φ in span(X): the Ritz values ascending and the Ritz vectors
// (M-orthonormal). X's columns are M-orthonormalised first, so nearly parallel columns (a
// subspace iteration's) only lose the directions they do not span.
void rayleigh_ritz(const fem::SparseMatrix& L, const Eigen::VectorXd& m, Eigen::MatrixXd& X,
                   Eigen::VectorXd& values) {
  const Eigen::MatrixXd B = X.transpose() * m.asDiagonal() * X;
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> gram(B);
  const Eigen::VectorXd g = gram.eigenvalues();
  const double floor = 1e-13 * g.maxCoeff();
  Index keep = 0;
  for (Index i = 0; i < Index(g.size()); ++i) keep += g[i] > floor;
  Eigen::MatrixXd W(X.cols(), keep);  // B^(-1/2) on the well-spanned directions
  for (Index i = Index(g.size()) - keep, c = 0; i < Index(g.size()); ++i, ++c) {
    W.col(c) = gram.eigenvectors().col(i) / std::sqrt(g[i]);
  }
  const Eigen::MatrixXd Q = X * W;  // M-orthonormal
  const Eigen::MatrixXd A = Q.transpose() * (L * Q);
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> ritz(0.5 * (A + A.transpose()));
  values = ritz.eigenvalues();
  X = Q * ritz.eigenvectors();
}

// Spectral coarsening (EigenOptions::coarse), on the vertices with mass; `vertex` maps them to
// the triangulation's ids.
EigenPairs coarse_eigenpairs(const intrinsic::IntrinsicTriangulation& tri, Index k,
                             const EigenOptions& options) {
  const Restricted p = restrict_to_mass(fem::cotan_laplacian(tri), fem::lumped_mass(tri));
  const Index n = tri.n_vertices(), nr = Index(p.vertex.size());
  if (k < 1 || k >= nr) {
    throw InvalidInput("eigenpairs: k = " + std::to_string(k) + " must be in [1, " +
                       std::to_string(nr) + ") (the number of vertices with mass)");
  }
  if (options.coarse <= k + options.extra_pairs || options.coarse >= n) {
    throw InvalidInput(
        "eigenpairs: coarse = " + std::to_string(options.coarse) +
        " must be above k + extra_pairs = " + std::to_string(k + options.extra_pairs) +
        " and below the " + std::to_string(n) + " vertices");
  }
  intrinsic::SimplifyOptions so;
  so.target_vertices = options.coarse;
  const intrinsic::Simplification s = intrinsic::simplify(tri, so);
  const fem::SparseMatrix P = fem::prolongation(s);
  const Eigen::VectorXd mc = fem::lumped_mass(s.coarse);
  Index nc = 0;
  for (Index i = 0; i < Index(mc.size()); ++i) nc += mc[i] > 0.0;
  const Index q = std::min<Index>(2 * (k + options.extra_pairs), nc - 1);
  if (q < k) {
    throw InvalidInput("eigenpairs: the coarse triangulation has " + std::to_string(nc) +
                       " vertices with mass, too few for k = " + std::to_string(k));
  }
  EigenOptions sub = options;
  sub.coarse = 0;
  sub.extra_pairs = 0;
  const EigenPairs ce = eigenpairs(fem::cotan_laplacian(s.coarse), mc, q, sub);
  const Eigen::MatrixXd fine = P * ce.vectors;  // n × q
  Eigen::MatrixXd X(nr, q);
  for (Index i = 0; i < nr; ++i) X.row(i) = fine.row(p.vertex[i]);
  Eigen::VectorXd values;
  rayleigh_ritz(p.L, p.m, X, values);
  EigenPairs out;
  out.solves = ce.solves;
  if (options.coarse_iterations > 0) {
    ShiftInvertOp op(p.L, p.m);
    op.set_shift(-options.shift_scale / p.m.sum());
    Eigen::MatrixXd Y(nr, X.cols());
    for (Index it = 0; it < options.coarse_iterations; ++it) {
      const Eigen::MatrixXd MX = p.m.asDiagonal() * X;
      for (Index j = 0; j < Index(X.cols()); ++j) op.perform_op(&MX(0, j), &Y(0, j));
      X = Y;
      rayleigh_ritz(p.L, p.m, X, values);
      out.solves += Index(X.cols());
    }
  }
  if (Index(values.size()) < k) {
    throw SolverError("eigenpairs: the coarse subspace spans " + std::to_string(values.size()) +
                      " directions, fewer than k = " + std::to_string(k));
  }
  out.iterations = options.coarse_iterations;
  out.coarse_vertices = s.coarse.n_vertices();
  out.values = values.head(k);
  out.residuals = relative_residuals(p.L, p.m, out.values, X.leftCols(k));
  out.vectors = Eigen::MatrixXd::Zero(n, k);
  for (Index i = 0; i < nr; ++i) out.vectors.row(p.vertex[i]) = X.row(i).head(k);
  return out;
}

}  // namespace

void EigenOptions::validate() const {
  if (extra_pairs < 0 || ncv < 0 || max_iterations < 1 || !(tolerance > 0.0) ||
      !(shift_scale > 0.0) || coarse < 0 || coarse_iterations < 0) {
    throw InvalidInput(
        "EigenOptions: need extra_pairs ≥ 0, ncv ≥ 0, max_iterations ≥ 1, "
        "tolerance > 0, shift_scale > 0, coarse ≥ 0, coarse_iterations ≥ 0");
  }
}

EigenPairs eigenpairs(const fem::SparseMatrix& L_full, const Eigen::VectorXd& mass_full, Index k,
                      const EigenOptions& options) {
  options.validate();
  if (options.coarse > 0) {
    throw InvalidInput("eigenpairs: coarse = " + std::to_string(options.coarse) +
                       " needs the triangulation (the overload taking an IntrinsicTriangulation)");
  }
  const Index n = Index(L_full.rows());
  if (L_full.cols() != n || mass_full.size() != n) {
    throw InvalidInput("eigenpairs: L is " + std::to_string(L_full.rows()) + "×" +
                       std::to_string(L_full.cols()) + " but mass has " +
                       std::to_string(mass_full.size()) + " entries");
  }
  const Restricted p = restrict_to_mass(L_full, mass_full);
  const fem::SparseMatrix& L = p.L;
  const Eigen::VectorXd& m = p.m;
  const std::vector<Index>& vertex = p.vertex;
  const Index nr = Index(vertex.size());
  if (k < 1 || k >= nr) {
    throw InvalidInput("eigenpairs: k = " + std::to_string(k) + " must be in [1, " +
                       std::to_string(nr) + ") (the number of vertices with mass)");
  }
  const Index nev = std::min<Index>(k + options.extra_pairs, nr - 1);
  Index ncv = options.ncv > 0 ? options.ncv : std::max<Index>(2 * nev + 1, 20);
  ncv = std::min(ncv, nr);
  if (ncv <= nev) {
    throw InvalidInput("eigenpairs: k = " + std::to_string(k) + " is too large for " +
                       std::to_string(nr) + " vertices");
  }
  const double sigma = -options.shift_scale / m.sum();
  ShiftInvertOp op(L, m);
  DiagonalOp bop(m);
  Spectra::SymGEigsShiftSolver<ShiftInvertOp, DiagonalOp, Spectra::GEigsMode::ShiftInvert> eigs(
      op, bop, nev, ncv, sigma);
  // Spectra's basis products go to OpenBLAS (EIGEN_USE_BLAS for this file, solvers/CMakeLists.txt),
  // at one thread: faster than Eigen's own kernels, and OpenBLAS's threaded GEMV changes the
  // round-off with the thread count (docs/decisions.md, "Eigenpairs: Spectra over OpenBLAS")
  const BlasThreadScope one_blas_thread(1);
  // Lanczos fills a basis of ncv vectors, then each restart adds ncv − nev: a few restarts
  const double expected_solves = double(ncv) + 3.0 * double(ncv - nev);
  ProgressMeter meter(options.on_progress, "eigenpairs", expected_solves, true);
  op.report_to(&meter);
  eigs.init();
  const Eigen::Index nconv = eigs.compute(Spectra::SortRule::LargestMagn, options.max_iterations,
                                          options.tolerance, Spectra::SortRule::SmallestAlge);
  if (eigs.info() != Spectra::CompInfo::Successful || nconv < k) {
    throw SolverError("eigenpairs: " + std::to_string(nconv) + " of " + std::to_string(nev) +
                      " eigenpairs converged after " + std::to_string(eigs.num_iterations()) +
                      " iterations (asked for " + std::to_string(k) +
                      "); try a larger ncv or max_iterations");
  }
  meter.finish();
  const Eigen::VectorXd values = eigs.eigenvalues();
  const Eigen::MatrixXd vectors = eigs.eigenvectors();
  // ascending order (Spectra's SmallestAlge sorting already is, but do not rely on it)
  std::vector<Index> order(values.size());
  for (Index i = 0; i < Index(order.size()); ++i) order[i] = i;
  std::sort(order.begin(), order.end(), [&](Index a, Index b) { return values[a] < values[b]; });
  EigenPairs out;
  out.iterations = Index(eigs.num_iterations());
  out.solves = Index(eigs.num_operations());
  out.values.resize(k);
  out.vectors = Eigen::MatrixXd::Zero(n, k);
  for (Index j = 0; j < k; ++j) {
    out.values[j] = values[order[j]];
    for (Index i = 0; i < nr; ++i) out.vectors(vertex[i], j) = vectors(i, order[j]);
  }
  Eigen::MatrixXd own(nr, k);
  for (Index j = 0; j < k; ++j) own.col(j) = vectors.col(order[j]);
  out.residuals = relative_residuals(L, m, out.values, own);
  return out;
}

EigenPairs eigenpairs(const intrinsic::IntrinsicTriangulation& tri, Index k,
                      const EigenOptions& options) {
  options.validate();
  if (options.coarse > 0) return coarse_eigenpairs(tri, k, options);
  return eigenpairs(fem::cotan_laplacian(tri), fem::lumped_mass(tri), k, options);
}

}  // namespace ifem::solvers
