// Builds the intrinsic Delaunay Laplacian of a small icosphere through the installed headers and
// libraries; exits non-zero if L·1 ≠ 0.
#include <cstdio>

#include "fem/operators.h"
#include "intrinsic/generators/mesh_generators.h"

int main() {
  const auto mesh = ifem::intrinsic::icosphere(4);
  auto tri = ifem::intrinsic::IntrinsicTriangulation::from_positions(mesh.faces, mesh.positions);
  tri.flip_to_delaunay();
  const auto L = ifem::fem::cotan_laplacian(tri);
  const double residual = (L * Eigen::VectorXd::Ones(L.rows())).cwiseAbs().maxCoeff();
  std::printf("consumer: %d vertices, |L·1| = %.3g\n", int(L.rows()), residual);
  return residual < 1e-10 ? 0 : 1;
}
