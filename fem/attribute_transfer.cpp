// Function transfer between the input and an intrinsic triangulation: pointwise or L2 with the
// mixed mass matrix over the common subdivision.
#include "fem/attribute_transfer.h"

#include <Eigen/IterativeLinearSolvers>
#include <array>
#include <cmath>
#include <memory>
#include <optional>
#include <vector>

#include "intrinsic/core/errors.h"

namespace ifem::fem {

using intrinsic::CorrespondenceView;
using intrinsic::PointLocator;

const char* to_string(TransferMethod m) {
  return m == TransferMethod::kPointwise ? "pointwise" : "l2";
}

TransferMethod parse_transfer_method(const std::string& word) {
  if (word == "pointwise") return TransferMethod::kPointwise;
  if (word == "l2") return TransferMethod::kL2;
  throw InvalidInput("transfer method: '" + word +
                     "' is neither 'pointwise' (interpolate at the other side's vertices) nor "
                     "'l2' (Galerkin projection, preserves the integral)");
}

namespace {

// The corners' vertex ids of face f.
std::array<Index, 3> corners(const intrinsic::IntrinsicTriangulation& t, Index f) {
  return {t.tail(3 * f), t.tail(3 * f + 1), t.tail(3 * f + 2)};
}

void check_values(const Eigen::VectorXd& values, Index expected, const char* what) {
  if (values.size() != expected) {
    throw InvalidInput("transfer: " + std::to_string(values.size()) + " values, expected one per " +
                       what + " (" + std::to_string(expected) + ")");
  }
  for (Index i = 0; i < values.size(); ++i) {
    if (!std::isfinite(values[i])) {
      throw InvalidInput("transfer: value " + std::to_string(i) + " is not a finite number");
    }
  }
}

// Solves M x = b for the consistent mass M of t; vertices without faces (zero rows) keep
// `fallback`'s values. Conjugate gradients with the diagonal as preconditioner: the diagonally
// scaled P1 mass matrix has condition number at most 4 on any triangulation (its element
// matrices' is 4), so the residual shrinks by about 3 per iteration whatever the mesh.
Eigen::VectorXd mass_solve(const intrinsic::IntrinsicTriangulation& t, Eigen::VectorXd b,
                           const Eigen::VectorXd& fallback) {
  SparseMatrix m = galerkin_mass(t);
  Eigen::VectorXd diag = m.diagonal();
  std::vector<Eigen::Triplet<double>> fix;
  for (Index v = 0; v < m.rows(); ++v) {
    if (diag[v] > 0.0) continue;
    fix.emplace_back(v, v, 1.0);
    b[v] = fallback[v];
  }
  if (!fix.empty()) {
    SparseMatrix id(m.rows(), m.cols());
    id.setFromTriplets(fix.begin(), fix.end());
    m += id;
  }
  Eigen::ConjugateGradient<SparseMatrix, Eigen::Lower | Eigen::Upper> cg;
  cg.setTolerance(1e-15);
  cg.setMaxIterations(200);
  cg.compute(m);
  Eigen::VectorXd x = cg.solve(b);
  if (!x.allFinite() || !(cg.error() <= 1e-12)) {
    throw SolverError("transfer: the mass matrix solve did not converge (relative residual " +
                      std::to_string(cg.error()) + " after " + std::to_string(cg.iterations()) +
                      " iterations; degenerate faces?)");
  }
  return x;
}

}  // namespace

SparseMatrix mixed_mass(const PointLocator& locator, const CorrespondenceView& view) {
  const intrinsic::IntrinsicTriangulation& tri = view.intrinsic();
  const intrinsic::IntrinsicTriangulation& in = view.input();
  std::vector<Eigen::Triplet<double>> entries;
  entries.reserve(9 * std::size_t(locator.n_pieces()));
  for (Index p = 0; p < locator.n_pieces(); ++p) {
    const Eigen::Matrix3d& a = locator.at_intrinsic(p);  // rows: intrinsic corners
    const Eigen::Matrix3d& b = locator.at_input(p);      // rows: input corners
    // ∫ over a triangle of the product of two linear functions with corner values a_j, b_j:
    // A/12 (Σ a_j b_j + Σ a_j Σ b_j)
    const Eigen::Matrix3d block =
        locator.area(p) / 12.0 *
        (a * b.transpose() + a.rowwise().sum() * b.rowwise().sum().transpose());
    const auto vi = corners(tri, locator.intrinsic_face(p));
    const auto vj = corners(in, locator.input_face(p));
    for (int k = 0; k < 3; ++k) {
      for (int m = 0; m < 3; ++m) entries.emplace_back(vi[k], vj[m], block(k, m));
    }
  }
  SparseMatrix out(tri.n_vertices(), view.n_input_vertices());
  out.setFromTriplets(entries.begin(), entries.end());
  return out;
}

Eigen::VectorXd transfer(const CorrespondenceView& view, const Eigen::VectorXd& values,
                         TransferMethod method, bool back, const PointLocator* locator) {
  const Index nv = view.intrinsic().n_vertices(), n_in = view.n_input_vertices();
  check_values(values, back ? nv : n_in, back ? "intrinsic vertex" : "input vertex");
  if (method == TransferMethod::kPointwise) {
    return back ? Eigen::VectorXd(values.head(n_in)) : view.input_to_intrinsic(values);
  }
  std::optional<PointLocator> own;
  if (!locator) locator = &own.emplace(view);
  const SparseMatrix mix = mixed_mass(*locator, view);
  if (back) return mass_solve(view.input(), mix.transpose() * values, values.head(n_in));
  Eigen::VectorXd fallback = Eigen::VectorXd::Zero(nv);
  fallback.head(n_in) = values;
  return mass_solve(view.intrinsic(), mix * values, fallback);
}

}  // namespace ifem::fem
