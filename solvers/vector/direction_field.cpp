// Smoothest and aligned n-direction fields and their singularities (direction_field.h).
#include "solvers/vector/direction_field.h"

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <complex>
#include <random>
#include <string>
#include <utility>

#include "fem/frame_connection.h"
#include "fem/operators.h"
#include "intrinsic/core/errors.h"
#include "intrinsic/core/geometry.h"
#include "solvers/linalg/cholesky.h"
#include "solvers/scalar/components.h"

namespace ifem::solvers {

namespace {

using Complex = std::complex<double>;
using T = intrinsic::IntrinsicTriangulation;
constexpr double kTwoPi = 2.0 * intrinsic::kPi;

// u / |u| where |u| > 0, else 0.
Eigen::VectorXcd normalized_per_vertex(const Eigen::VectorXcd& u) {
  Eigen::VectorXcd out = Eigen::VectorXcd::Zero(u.size());
  const double scale = u.cwiseAbs().maxCoeff();
  for (Eigen::Index v = 0; v < u.size(); ++v) {
    const double a = std::abs(u[v]);
    if (a > 1e-300 * scale && a > 0.0) out[v] = u[v] / a;
  }
  return out;
}

// The search space of one step, column-wise: the iterate x, the inverse-iteration direction w
// and the previous step p, with L applied to each (#V×3 each; p is 0 on the first step).
struct SearchSpace {
  Eigen::MatrixXcd S, LS;
};

// Per component c: Σ_{v ∈ c} m_v conj(S(v, a)) S(v, b).
std::vector<Complex> component_dots(const SearchSpace& s, int a, int b, const Eigen::VectorXd& mass,
                                    const Components& comps) {
  std::vector<Complex> dot(comps.count, Complex(0.0));
  for (Eigen::Index v = 0; v < s.S.rows(); ++v) {
    const Index c = comps.label[v];
    if (c != kInvalidIndex) dot[c] += mass[v] * std::conj(s.S(v, a)) * s.S(v, b);
  }
  return dot;
}

// Column k of S (and LS alike) made M-orthogonal to columns 0..k−1 (M-orthonormal already) and
// M-normalized, per component, by Gram–Schmidt applied twice (one pass loses the direction when
// column k is nearly parallel to the others, as w is to x near convergence). A column that
// vanishes against the others (below 1e-13 of its norm) becomes 0 on that component.
void orthonormalize(SearchSpace& s, int k, const Eigen::VectorXd& mass, const Components& comps) {
  const Eigen::Index n = s.S.rows();
  const std::vector<Complex> before = component_dots(s, k, k, mass, comps);
  for (int pass = 0; pass < 2; ++pass) {
    for (int j = 0; j < k; ++j) {
      const std::vector<Complex> d = component_dots(s, j, k, mass, comps);
      for (Eigen::Index v = 0; v < n; ++v) {
        const Index c = comps.label[v];
        if (c == kInvalidIndex) continue;
        s.S(v, k) -= d[c] * s.S(v, j);
        s.LS(v, k) -= d[c] * s.LS(v, j);
      }
    }
  }
  const std::vector<Complex> after = component_dots(s, k, k, mass, comps);
  std::vector<double> scale(comps.count, 0.0);
  for (Index c = 0; c < comps.count; ++c) {
    const double a = after[c].real(), b = before[c].real();
    scale[c] = a > 1e-26 * b && a > 0.0 ? 1.0 / std::sqrt(a) : 0.0;
  }
  for (Eigen::Index v = 0; v < n; ++v) {
    const double f = comps.label[v] == kInvalidIndex ? 0.0 : scale[comps.label[v]];
    s.S(v, k) *= f;
    s.LS(v, k) *= f;
  }
}

// The coefficients y (3) of the Ritz vector of smallest Ritz value in the span of S's columns
// on component c (Rayleigh–Ritz with Sᴴ L S; the columns are M-orthonormal or 0 there).
std::vector<Eigen::Vector3cd> smallest_ritz(const SearchSpace& s, const Components& comps) {
  std::vector<Eigen::Matrix3cd> gl(comps.count, Eigen::Matrix3cd::Zero());
  for (Eigen::Index v = 0; v < s.S.rows(); ++v) {
    const Index c = comps.label[v];
    if (c != kInvalidIndex) gl[c].noalias() += s.S.row(v).adjoint() * s.LS.row(v);
  }
  std::vector<Eigen::Vector3cd> y(comps.count, Eigen::Vector3cd::Zero());
  for (Index c = 0; c < comps.count; ++c) {
    // the zero columns (a component where w or p vanished) are left out of the problem
    std::vector<int> keep;
    for (int j = 0; j < 3; ++j) {
      if (std::abs(gl[c](j, j)) > 0.0 || j == 0) keep.push_back(j);
    }
    Eigen::MatrixXcd g(keep.size(), keep.size());
    for (std::size_t a = 0; a < keep.size(); ++a) {
      for (std::size_t b = 0; b < keep.size(); ++b) g(a, b) = gl[c](keep[a], keep[b]);
    }
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXcd> es((g + g.adjoint()) / 2.0);
    for (std::size_t a = 0; a < keep.size(); ++a) y[c][keep[a]] = es.eigenvectors()(a, 0);
  }
  return y;
}

// The components that carry a field: some vertex of positive mass and only finite entries of L
// on their rows. The others ("empty": all vertices unlabelled by the caller, zero mass, or a
// non-finite operator) get u = 0; work.label is kInvalidIndex on their vertices.
struct LiveComponents {
  Components work;
  Index empty = 0;
};

LiveComponents live_components(const fem::ComplexSparseMatrix& L, const Eigen::VectorXd& mass,
                               const Components& comps) {
  std::vector<char> has_mass(comps.count, 0), finite(comps.count, 1);
  for (Eigen::Index v = 0; v < L.rows(); ++v) {
    const Index c = comps.label[v];
    if (c == kInvalidIndex) continue;
    if (mass[v] > 0.0 && std::isfinite(mass[v])) has_mass[c] = 1;
    if (!std::isfinite(mass[v])) finite[c] = 0;
  }
  for (int col = 0; col < L.outerSize(); ++col) {
    for (fem::ComplexSparseMatrix::InnerIterator it(L, col); it; ++it) {
      const Index c = comps.label[it.row()];
      if (c != kInvalidIndex && !std::isfinite(std::abs(it.value()))) finite[c] = 0;
    }
  }
  LiveComponents live{comps, 0};
  for (Index c = 0; c < comps.count; ++c) live.empty += !(has_mass[c] && finite[c]);
  for (Index& c : live.work.label) {
    if (c != kInvalidIndex && !(has_mass[c] && finite[c])) c = kInvalidIndex;
  }
  return live;
}

// L without the rows and columns of the vertices outside the live components.
fem::ComplexSparseMatrix restricted(const fem::ComplexSparseMatrix& L, const Components& work) {
  std::vector<Eigen::Triplet<Complex>> entries;
  entries.reserve(static_cast<std::size_t>(L.nonZeros()));
  for (int col = 0; col < L.outerSize(); ++col) {
    if (work.label[col] == kInvalidIndex) continue;
    for (fem::ComplexSparseMatrix::InnerIterator it(L, col); it; ++it) {
      if (work.label[it.row()] != kInvalidIndex) entries.emplace_back(it.row(), col, it.value());
    }
  }
  fem::ComplexSparseMatrix out(L.rows(), L.cols());
  out.setFromTriplets(entries.begin(), entries.end());
  return out;
}

// L + ε_c M (L restricted to the live components), ε_c = 1e-8 · (largest diagonal of L on c) /
// (largest mass on c): each component shifted on its own scale, so that a component much smaller
// than the others (a small piece of a soup, a mollified zero-area face: masses 1e-13 of the
// rest) is positive definite too; the identity on the other vertices and those of zero mass.
// *shift: ε_c per component (0 on empty ones), the Rayleigh quotient below which an eigenvalue
// is indistinguishable from 0 (a parallel field).
fem::ComplexSparseMatrix shifted_operator(const fem::ComplexSparseMatrix& L,
                                          const Eigen::VectorXd& mass, const Components& work,
                                          std::vector<double>* shift) {
  const Eigen::Index n = L.rows();
  std::vector<double> diag(work.count, 0.0), heaviest(work.count, 0.0);
  const Eigen::VectorXcd d = L.diagonal();
  for (Eigen::Index v = 0; v < n; ++v) {
    const Index c = work.label[v];
    if (c == kInvalidIndex) continue;
    diag[c] = std::max(diag[c], std::abs(d[v]));
    heaviest[c] = std::max(heaviest[c], mass[v]);
  }
  shift->assign(work.count, 0.0);
  for (Index c = 0; c < work.count; ++c) {
    if (heaviest[c] > 0.0) (*shift)[c] = 1e-8 * diag[c] / heaviest[c];
  }
  fem::ComplexSparseMatrix A = L;
  for (Eigen::Index v = 0; v < n; ++v) {
    const Index c = work.label[v];
    const bool solved = c != kInvalidIndex && mass[v] > 0.0;
    const double scale = solved && diag[c] > 0.0 ? 1e-8 * diag[c] / heaviest[c] : 1.0;
    A.coeffRef(v, v) += solved ? scale * mass[v] : 1.0;
  }
  return A;
}

// Smallest eigenvector of L u = λ M u on every component on its own (the matrices are block
// diagonal over components), by LOBPCG with the exact preconditioner (L + εM)⁻¹ (Knyazev 2001):
// each step does one solve, w = (L + εM)⁻¹ M x, as inverse iteration would, then takes the best
// vector (Rayleigh–Ritz) of span{x, w, p}, p the previous step, orthonormalized first. Why not
// plain inverse iteration: docs/decisions.md, "Direction fields: LOBPCG". Only the live
// components of comps (live_components()) are solved; u = 0 elsewhere.
DirectionField inverse_iteration(const fem::ComplexSparseMatrix& L_all, const Eigen::VectorXd& mass,
                                 const Components& all, const DirectionFieldOptions& o) {
  const Eigen::Index n = L_all.rows();
  const LiveComponents live = live_components(L_all, mass, all);
  const Components& comps = live.work;
  const fem::ComplexSparseMatrix L = live.empty > 0 ? restricted(L_all, comps) : L_all;
  std::vector<double> shift;
  // the iterations' dense solves by our kernel on CHOLMOD's factor in place (docs/decisions.md
  // D-113: a smoothest 4-field 0.83-0.95 of CHOLMOD's time in most interleaved runs)
  CholeskyOptions chol_opt;
  chol_opt.solve_kernel = CholeskyOptions::SolveKernel::kSupernodalDouble;
  const ComplexCholeskySolver solver(shifted_operator(L, mass, comps, &shift), chol_opt);
  std::mt19937 rng(7);
  std::normal_distribution<double> gauss;
  SearchSpace s{Eigen::MatrixXcd::Zero(n, 3), Eigen::MatrixXcd::Zero(n, 3)};
  for (Eigen::Index v = 0; v < n; ++v) {
    if (comps.label[v] != kInvalidIndex) s.S(v, 0) = Complex(gauss(rng), gauss(rng));
  }
  s.LS.col(0) = L * s.S.col(0);
  orthonormalize(s, 0, mass, comps);
  DirectionField f;
  std::vector<double> rho(comps.count, 0.0), previous(comps.count, -1.0);
  for (f.iterations = 1; f.iterations <= o.max_iterations; ++f.iterations) {
    s.S.col(1) = solver.solve(Eigen::VectorXcd((mass.array() * s.S.col(0).array()).matrix()));
    s.LS.col(1) = L * s.S.col(1);
    orthonormalize(s, 1, mass, comps);
    orthonormalize(s, 2, mass, comps);
    // L applied again: near convergence w and p are differences of nearly equal vectors scaled
    // up to unit norm, and the same operations on LS drift away from L·S (on a one-triangle
    // piece of a soup, to Ritz values of −10⁶ where λ ≈ 0); two products cost far less than
    // the solve
    s.LS.col(1) = L * s.S.col(1);
    s.LS.col(2) = L * s.S.col(2);
    const std::vector<Eigen::Vector3cd> y = smallest_ritz(s, comps);
    std::fill(rho.begin(), rho.end(), 0.0);
    for (Eigen::Index v = 0; v < n; ++v) {
      const Index c = comps.label[v];
      const Eigen::Vector3cd yc = c == kInvalidIndex ? Eigen::Vector3cd::Zero() : y[c];
      const Complex p = s.S(v, 1) * yc[1] + s.S(v, 2) * yc[2];
      const Complex lp = s.LS(v, 1) * yc[1] + s.LS(v, 2) * yc[2];
      s.S(v, 0) = s.S(v, 0) * yc[0] + p;
      s.LS(v, 0) = s.LS(v, 0) * yc[0] + lp;
      s.S(v, 2) = p;
      s.LS(v, 2) = lp;
      if (c != kInvalidIndex) rho[c] += (std::conj(s.S(v, 0)) * s.LS(v, 0)).real();
    }
    orthonormalize(s, 0, mass, comps);  // renormalized: round-off creeps in over the steps
    // converged when every component's Rayleigh quotient is: its change below the tolerance,
    // relative, or below the component's shift (λ ≈ 0 on a flat piece, where a relative change
    // is noise)
    bool converged = true;
    f.energy = 0.0;
    for (Index c = 0; c < comps.count; ++c) {
      f.energy += rho[c];
      converged =
          converged && std::abs(rho[c] - previous[c]) <= o.tolerance * std::abs(rho[c]) + shift[c];
    }
    f.energy /= double(std::max<Index>(comps.count - live.empty, 1));
    if (converged) break;
    previous = rho;
  }
  f.iterations = std::min(f.iterations, o.max_iterations);
  // a last plain inverse-iteration step: where the field is below round-off of its largest
  // value (localized eigenvectors, e.g. on rocketship), the Ritz combination leaves noise at
  // 1e-16 of the maximum, with spurious singularities; the solve resolves that tail smoothly
  const Eigen::VectorXcd x =
      solver.solve(Eigen::VectorXcd((mass.array() * s.S.col(0).array()).matrix()));
  f.energy = (x.adjoint() * (L * x))(0).real() /
             std::max((x.adjoint() * (mass.array() * x.array()).matrix())(0).real(), 1e-300);
  f.u = normalized_per_vertex(x);
  f.empty_components = live.empty;
  f.free_components = comps.count - live.empty;
  return f;
}

}  // namespace

void DirectionFieldOptions::validate() const {
  if (symmetry < 1) {
    throw InvalidInput("direction field: symmetry must be ≥ 1, got " + std::to_string(symmetry));
  }
  if (max_iterations < 1) {
    throw InvalidInput("direction field: max_iterations must be ≥ 1, got " +
                       std::to_string(max_iterations));
  }
  if (!(tolerance > 0.0)) {
    throw InvalidInput("direction field: tolerance must be > 0, got " + std::to_string(tolerance));
  }
}

namespace {

void check_operators(const fem::ComplexSparseMatrix& L, const Eigen::VectorXd& mass,
                     const Components& comps) {
  if (L.rows() != L.cols() || mass.size() != L.rows() ||
      static_cast<Eigen::Index>(comps.label.size()) != L.rows()) {
    throw InvalidInput("direction field: the connection Laplacian (" + std::to_string(L.rows()) +
                       "×" + std::to_string(L.cols()) + "), the mass (" +
                       std::to_string(mass.size()) + ") and the components (" +
                       std::to_string(comps.label.size()) + ") do not match");
  }
}

}  // namespace

DirectionField smoothest_field(const fem::ComplexSparseMatrix& L_n, const Eigen::VectorXd& mass,
                               const Components& comps, const DirectionFieldOptions& options) {
  options.validate();
  check_operators(L_n, mass, comps);
  return inverse_iteration(L_n, mass, comps, options);
}

DirectionField smoothest_field(const intrinsic::IntrinsicTriangulation& tri,
                               const fem::TangentFrames& frames,
                               const DirectionFieldOptions& options) {
  options.validate();
  return smoothest_field(fem::connection_laplacian(tri, frames, options.symmetry),
                         fem::lumped_mass(tri), connected_components(tri), options);
}

namespace {

// The held powers: per constrained vertex the mean of e^{i n angle} over its constraints.
std::vector<Complex> held_powers(const std::vector<DirectionConstraint>& constraints, Index nv,
                                 int n, Index* held) {
  std::vector<Complex> sum(nv, Complex(0.0));
  std::vector<int> count(nv, 0);
  for (std::size_t k = 0; k < constraints.size(); ++k) {
    const DirectionConstraint& c = constraints[k];
    if (c.vertex < 0 || c.vertex >= nv) {
      throw InvalidInput("direction constraint " + std::to_string(k) + ": vertex " +
                         std::to_string(c.vertex) + " out of range [0, " + std::to_string(nv) +
                         ")");
    }
    if (!std::isfinite(c.angle)) {
      throw InvalidInput("direction constraint " + std::to_string(k) + " (vertex " +
                         std::to_string(c.vertex) + "): the angle is not finite");
    }
    sum[c.vertex] += std::polar(1.0, n * c.angle);
    ++count[c.vertex];
  }
  *held = 0;
  for (Index v = 0; v < nv; ++v) {
    if (count[v] == 0) continue;
    ++*held;
    sum[v] /= double(count[v]);
    if (std::abs(sum[v]) < 1e-12) sum[v] = Complex(1e-12);  // opposite directions cancelled
  }
  return sum;
}

// L u = 0 on the free vertices of constrained components, u fixed on constrained vertices.
void solve_dirichlet(const fem::ComplexSparseMatrix& L, const std::vector<char>& is_held,
                     const std::vector<char>& solve_here, Eigen::VectorXcd& u) {
  const Eigen::Index n = L.rows();
  std::vector<Index> row(n, kInvalidIndex);
  Index m = 0;
  for (Eigen::Index v = 0; v < n; ++v) {
    if (solve_here[v] && !is_held[v]) row[v] = m++;
  }
  if (m == 0) return;
  std::vector<Eigen::Triplet<Complex>> entries;
  Eigen::VectorXcd rhs = Eigen::VectorXcd::Zero(m);
  for (int col = 0; col < L.outerSize(); ++col) {
    for (fem::ComplexSparseMatrix::InnerIterator it(L, col); it; ++it) {
      const Index r = row[it.row()];
      if (r == kInvalidIndex) continue;
      if (row[col] != kInvalidIndex) {
        entries.emplace_back(r, row[col], it.value());
      } else if (is_held[col]) {
        rhs[r] -= it.value() * u[col];
      }
    }
  }
  fem::ComplexSparseMatrix A(m, m);
  A.setFromTriplets(entries.begin(), entries.end());
  const Eigen::VectorXcd x = ComplexCholeskySolver(A).solve(rhs);
  for (Eigen::Index v = 0; v < n; ++v) {
    if (row[v] != kInvalidIndex) u[v] = x[row[v]];
  }
}

}  // namespace

DirectionField aligned_field(const fem::ComplexSparseMatrix& L_all, const Eigen::VectorXd& mass,
                             const Components& all,
                             const std::vector<DirectionConstraint>& constraints,
                             const DirectionFieldOptions& options) {
  options.validate();
  check_operators(L_all, mass, all);
  const Index nv = static_cast<Index>(L_all.rows());
  DirectionField f;
  const std::vector<Complex> held = held_powers(constraints, nv, options.symmetry, &f.constrained);
  const LiveComponents live = live_components(L_all, mass, all);
  const Components& comps = live.work;
  const fem::ComplexSparseMatrix L = live.empty > 0 ? restricted(L_all, comps) : L_all;
  std::vector<char> component_held(comps.count, 0), is_held(nv, 0), solve_here(nv, 0);
  for (Index v = 0; v < nv; ++v) {
    is_held[v] = held[v] != Complex(0.0) && comps.label[v] != kInvalidIndex;
    if (is_held[v]) component_held[comps.label[v]] = 1;
  }
  for (Index v = 0; v < nv; ++v) {
    solve_here[v] = comps.label[v] != kInvalidIndex && component_held[comps.label[v]];
  }
  Eigen::VectorXcd u = Eigen::VectorXcd::Zero(nv);
  for (Index v = 0; v < nv; ++v) u[v] = is_held[v] ? held[v] : Complex(0.0);
  solve_dirichlet(L, is_held, solve_here, u);
  for (Index c = 0; c < comps.count; ++c) f.free_components += !component_held[c];
  f.free_components -= live.empty;  // the empty ones hold nothing either, and have no field
  f.empty_components = live.empty;
  if (f.free_components > 0) {  // their own smoothest field
    const DirectionField s = inverse_iteration(L, mass, comps, options);
    for (Index v = 0; v < nv; ++v) {
      if (!solve_here[v]) u[v] = s.u[v];
    }
    f.iterations = s.iterations;
  }
  const double mu = (u.adjoint() * (mass.array() * u.array()).matrix())(0).real();
  f.energy = (u.adjoint() * (L * u))(0).real() / std::max(mu, 1e-300);
  f.u = normalized_per_vertex(u);
  return f;
}

DirectionField aligned_field(const intrinsic::IntrinsicTriangulation& tri,
                             const fem::TangentFrames& frames,
                             const std::vector<DirectionConstraint>& constraints,
                             const DirectionFieldOptions& options) {
  options.validate();
  return aligned_field(fem::connection_laplacian(tri, frames, options.symmetry),
                       fem::lumped_mass(tri), connected_components(tri), constraints, options);
}

namespace {

// The direction at tail(h) of the incoming boundary edge that closes h's fan (walking
// counter-clockwise from h): the last halfedge's direction turned by its scaled corner.
double incoming_boundary_direction(const intrinsic::IntrinsicTriangulation& tri,
                                   const fem::TangentFrames& frames, Index h) {
  Index x = h;
  for (Index guard = 0; guard <= tri.n_halfedges(); ++guard) {
    const Index n = tri.twin(T::prev(x));
    if (n == kInvalidIndex || n == h) break;
    x = n;
  }
  return frames.halfedge_angle[x] +
         frames.angle_scale[tri.tail(x)] * intrinsic::corner_angle(tri, x);
}

}  // namespace

std::vector<DirectionConstraint> boundary_constraints(const intrinsic::IntrinsicTriangulation& tri,
                                                      const fem::TangentFrames& frames,
                                                      int symmetry) {
  if (symmetry < 1) {
    throw InvalidInput("boundary_constraints: symmetry must be ≥ 1, got " +
                       std::to_string(symmetry));
  }
  if (frames.halfedge_angle.size() != tri.n_halfedges() ||
      frames.angle_scale.size() != tri.n_vertices()) {
    throw InvalidInput("boundary_constraints: the frames are not those of this triangulation");
  }
  std::vector<DirectionConstraint> out;
  for (Index v = 0; v < tri.n_vertices(); ++v) {
    const Index h = tri.vertex_halfedge(v);
    if (h == kInvalidIndex || tri.twin(h) != kInvalidIndex) continue;
    const double a = frames.halfedge_angle[h];
    const double b = incoming_boundary_direction(tri, frames, h) + intrinsic::kPi;
    // n·(b − a) reduced to (−π, π]: the shorter arc between the two n-directions
    double arc = std::remainder(symmetry * (b - a), kTwoPi);
    if (arc <= -intrinsic::kPi) arc += kTwoPi;
    out.push_back({v, a + 0.5 * arc / symmetry});
  }
  return out;
}

Eigen::VectorXi face_indices(const intrinsic::IntrinsicTriangulation& tri,
                             const fem::TangentFrames& frames, const Eigen::VectorXcd& u,
                             int symmetry) {
  Eigen::VectorXi index = Eigen::VectorXi::Zero(tri.n_faces());
  for (Index f = 0; f < tri.n_faces(); ++f) {
    double turn = 0.0;
    bool defined = true;
    for (int s = 0; s < 3; ++s) {
      const Index h = T::halfedge(f, s);
      const Complex ui = u[tri.tail(h)], uj = u[tri.head(h)];
      if (ui == Complex(0.0) || uj == Complex(0.0)) defined = false;
      if (!defined) break;
      // the field's turning along h relative to transport, and the face's share of the
      // curvature that rescaling the corner angles put on it
      turn += std::arg(uj / (std::pow(frames.transport[h], symmetry) * ui));
      turn += symmetry * (frames.angle_scale[tri.tail(h)] - 1.0) * intrinsic::corner_angle(tri, h);
    }
    if (defined) index[f] = static_cast<int>(std::lround(turn / kTwoPi));
  }
  return index;
}

namespace {

// A triangle's corners in the order that turns counter-clockwise about their normals.
Triangle counter_clockwise(const Positions& p, const TangentBasis3d& basis, Triangle f) {
  const Eigen::Vector3d a = p.row(f[0]), b = p.row(f[1]), c = p.row(f[2]);
  const Eigen::Vector3d n =
      (basis.normal.row(f[0]) + basis.normal.row(f[1]) + basis.normal.row(f[2])).transpose();
  if ((b - a).cross(c - a).dot(n) < 0.0) std::swap(f[1], f[2]);
  return f;
}

}  // namespace

Eigen::VectorXi frame_face_indices(const Positions& positions,
                                   const std::vector<Triangle>& triangles,
                                   const TangentBasis3d& basis, const Eigen::VectorXcd& u,
                                   int symmetry) {
  const Index nv =
      static_cast<Index>(std::min<Eigen::Index>({positions.rows(), basis.normal.rows(), u.size()}));
  Eigen::VectorXi index = Eigen::VectorXi::Zero(static_cast<Index>(triangles.size()));
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    for (const Index v : triangles[t]) {
      if (v < 0 || v >= nv) {
        throw InvalidInput("frame_face_indices: triangle " + std::to_string(t) + " has vertex " +
                           std::to_string(v) + " out of range [0, " + std::to_string(nv) + ")");
      }
    }
    const Triangle f = counter_clockwise(positions, basis, triangles[t]);
    double turn = 0.0;
    Complex holonomy(1.0, 0.0);
    bool defined = true;
    for (int k = 0; k < 3 && defined; ++k) {
      const Index i = f[k], j = f[(k + 1) % 3];
      const Complex ui = u[i], uj = u[j];
      defined = ui != Complex(0.0) && uj != Complex(0.0);
      const Complex r =
          fem::frame_transport(basis.normal.row(i).transpose(), basis.e1.row(i).transpose(),
                               basis.normal.row(j).transpose(), basis.e1.row(j).transpose(),
                               basis.e2.row(j).transpose());
      holonomy *= r;
      turn += std::arg(uj / (std::pow(r, symmetry) * ui));
    }
    turn += symmetry * std::arg(holonomy);
    if (defined) index[static_cast<Index>(t)] = static_cast<int>(std::lround(turn / kTwoPi));
  }
  return index;
}

}  // namespace ifem::solvers
