#include "fem/gradient.h"

#include <gtest/gtest.h>

#include <cmath>

#include "fem/operators.h"
#include "helpers.h"
#include "intrinsic/core/errors.h"
#include "intrinsic/generators/mesh_generators.h"

namespace ifem::fem {
namespace {

intrinsic::IntrinsicTriangulation make_tri(const intrinsic::TriangleMesh& m, bool delaunay) {
  auto tri = intrinsic::IntrinsicTriangulation::from_positions(m.faces, m.positions);
  if (delaunay) tri.flip_to_delaunay();
  return tri;
}

// divergence() is gradient()'s adjoint under the area-weighted inner product, so
// divergence(gradient(u)) = L u with L = cotan_laplacian (header's sign convention).
TEST(FemGradient, DivergenceOfGradientIsLaplacian) {
  const auto tri = make_tri(test::jittered(intrinsic::icosphere(5), 0.02), true);
  Eigen::VectorXd u(tri.n_vertices());
  for (Index v = 0; v < tri.n_vertices(); ++v) u[v] = std::sin(0.37 * v) + 0.01 * v;
  const Eigen::VectorXd Lu = cotan_laplacian(tri) * u;
  const Eigen::VectorXd dg = divergence(tri, gradient(tri, u));
  EXPECT_LT((Lu - dg).norm(), 1e-10 * Lu.norm());
}

// A linear function on a flat mesh has the same gradient length |(3, −2)| = √13 on every face
// (the face frames differ, the length does not); wrong sizes are refused.
TEST(FemGradient, LinearFunctionHasConstantGradient) {
  auto m = test::jittered(intrinsic::grid(6, 5), 0.05);
  m.positions.col(2).setZero();  // keep it flat
  const auto tri = make_tri(m, false);
  Eigen::VectorXd u(tri.n_vertices());
  for (Index v = 0; v < tri.n_vertices(); ++v)
    u[v] = 3.0 * m.positions(v, 0) - 2.0 * m.positions(v, 1);
  const Eigen::MatrixX2d G = gradient(tri, u);
  for (Index f = 0; f < tri.n_faces(); ++f) EXPECT_NEAR(G.row(f).norm(), std::sqrt(13.0), 1e-9);
  EXPECT_THROW(gradient(tri, Eigen::VectorXd::Zero(3)), InvalidInput);
  EXPECT_THROW(divergence(tri, Eigen::MatrixX2d::Zero(2, 2)), InvalidInput);
}

// face_corner2(): the third corner of the frame of gradient() lies at distance ℓ₂ (side 2,
// corner 2 → 0) from the origin and ℓ₁ (side 1, corner 1 → 2) from (ℓ₀, 0), above the x axis.
TEST(FemGradient, FaceCorner2ReproducesTheSideLengths) {
  const auto tri = make_tri(test::jittered(intrinsic::icosphere(3), 0.05), true);
  for (Index f = 0; f < tri.n_faces(); ++f) {
    const double l0 = tri.halfedge_length(3 * f), l1 = tri.halfedge_length(3 * f + 1),
                 l2 = tri.halfedge_length(3 * f + 2);
    const Eigen::Vector2d p = face_corner2(tri, f);
    EXPECT_GT(p.y(), 0.0);
    EXPECT_NEAR(p.norm(), l2, 1e-12 * l2);
    EXPECT_NEAR((p - Eigen::Vector2d(l0, 0.0)).norm(), l1, 1e-12 * l1);
  }
}

}  // namespace
}  // namespace ifem::fem
