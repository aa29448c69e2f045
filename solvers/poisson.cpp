#include "solvers/poisson.h"

#include <cmath>
#include <optional>
#include <string>

#include "intrinsic/errors.h"

namespace ifem::solvers {

void PoissonOptions::validate() const {
  if (!(screening >= 0.0) || !std::isfinite(screening)) {
    throw InvalidInput("PoissonOptions: screening must be finite and ≥ 0, got " +
                       std::to_string(screening));
  }
}

struct PoissonSolver::Impl {
  Index n = 0;
  std::vector<Index> dirichlet;     // caller's order
  std::vector<Index> unknown;       // vertex → unknown id, or -1
  std::vector<Index> unknown_vertex;
  Components comps;
  std::vector<char> floating;       // per component: pure Neumann (pinned, zero mean)
  std::vector<double> comp_mass;    // per component: Σ m
  Eigen::VectorXd mass;
  fem::SparseMatrix A_ud;           // unknowns × Dirichlet columns (coupling)
  std::optional<CholeskySolver> chol;

  Eigen::MatrixXd solve_many(Eigen::MatrixXd B, const Eigen::MatrixXd* g) const {
    const Index nu = static_cast<Index>(unknown_vertex.size());
    const Eigen::Index k = B.cols();
    // make pure-Neumann components compatible
    if (!floating.empty()) {
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
    Eigen::MatrixXd rhs(nu, k);
    for (Index i = 0; i < nu; ++i) rhs.row(i) = B.row(unknown_vertex[i]);
    if (g && A_ud.cols() > 0) rhs -= A_ud * (*g);
    Eigen::MatrixXd X = Eigen::MatrixXd::Zero(n, k);
    if (nu > 0) {
      const Eigen::MatrixXd y = chol->solve(rhs);
      for (Index i = 0; i < nu; ++i) X.row(unknown_vertex[i]) = y.row(i);
    }
    if (g) {
      for (std::size_t d = 0; d < dirichlet.size(); ++d) X.row(dirichlet[d]) = g->row(d);
    }
    if (!floating.empty()) {
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
    return X;
  }
};

PoissonSolver::PoissonSolver(const intrinsic::IntrinsicTriangulation& tri,
                             std::vector<Index> dirichlet_vertices, const PoissonOptions& options)
    : PoissonSolver(fem::cotan_laplacian(tri), fem::lumped_mass(tri), connected_components(tri),
                    std::move(dirichlet_vertices), options) {}

PoissonSolver::PoissonSolver(const fem::SparseMatrix& L, const Eigen::VectorXd& mass,
                             const Components& comps, std::vector<Index> dirichlet,
                             const PoissonOptions& options)
    : impl_(std::make_unique<Impl>()) {
  options.validate();
  const Index n = static_cast<Index>(L.rows());
  if (L.rows() != L.cols() || mass.size() != n || static_cast<Index>(comps.label.size()) != n) {
    throw InvalidInput("PoissonSolver: L, mass and components sizes disagree");
  }
  Impl& im = *impl_;
  im.n = n;
  im.comps = comps;
  im.mass = mass;
  std::vector<char> is_dirichlet(n, 0);
  std::vector<char> comp_has_dirichlet(comps.count, 0);
  for (const Index v : dirichlet) {
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
  im.dirichlet = std::move(dirichlet);
  // pure-Neumann components: pin their lowest vertex to 0, shift to zero mean afterwards
  std::vector<char> pinned(n, 0);
  if (options.screening == 0.0) {
    im.floating.assign(comps.count, 0);
    im.comp_mass.assign(comps.count, 0.0);
    bool any = false;
    std::vector<char> done(comps.count, 0);
    for (Index v = 0; v < n; ++v) {
      const Index c = comps.label[v];
      if (c == kInvalidIndex) continue;
      im.comp_mass[c] += mass[v];
      if (comp_has_dirichlet[c] || done[c]) continue;
      done[c] = 1;
      pinned[v] = 1;
      im.floating[c] = 1;
      any = true;
    }
    if (!any) im.floating.clear();
  }
  im.unknown.assign(n, kInvalidIndex);
  for (Index v = 0; v < n; ++v) {
    if (comps.label[v] == kInvalidIndex || is_dirichlet[v] || pinned[v]) continue;
    im.unknown[v] = static_cast<Index>(im.unknown_vertex.size());
    im.unknown_vertex.push_back(v);
  }
  const Index nu = static_cast<Index>(im.unknown_vertex.size());
  std::vector<Index> dirichlet_pos(n, kInvalidIndex);
  for (std::size_t d = 0; d < im.dirichlet.size(); ++d) dirichlet_pos[im.dirichlet[d]] = Index(d);
  // A_uu (lower + upper as stored) and A_ud, straight from L's columns
  std::vector<Eigen::Triplet<double>> tuu, tud;
  tuu.reserve(static_cast<std::size_t>(L.nonZeros()));
  const double c = options.screening;
  for (Index j = 0; j < n; ++j) {
    const Index uj = im.unknown[j];
    const Index dj = dirichlet_pos[j];
    if (uj == kInvalidIndex && dj == kInvalidIndex) continue;
    for (fem::SparseMatrix::InnerIterator it(L, j); it; ++it) {
      const Index ui = im.unknown[it.row()];
      if (ui == kInvalidIndex) continue;
      double a = it.value();
      if (it.row() == j) a += c * mass[j];
      if (uj != kInvalidIndex) {
        tuu.emplace_back(ui, uj, a);
      } else {
        tud.emplace_back(ui, dj, a);
      }
    }
  }
  if (nu > 0) {
    fem::SparseMatrix A(nu, nu);
    A.setFromTriplets(tuu.begin(), tuu.end());
    A.makeCompressed();
    im.chol.emplace(A);
  }
  im.A_ud.resize(nu, static_cast<Index>(im.dirichlet.size()));
  im.A_ud.setFromTriplets(tud.begin(), tud.end());
  im.A_ud.makeCompressed();
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
  const Eigen::MatrixXd G = g;
  return im.solve_many(b, &G).col(0);
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

const std::vector<Index>& PoissonSolver::dirichlet_vertices() const { return impl_->dirichlet; }
Index PoissonSolver::n_unknowns() const { return Index(impl_->unknown_vertex.size()); }

Eigen::VectorXd solve_poisson(const intrinsic::IntrinsicTriangulation& tri, const Eigen::VectorXd& f,
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
