#include "fem/operators.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include "helpers.h"
#include "intrinsic/core/geometry.h"
#include "intrinsic/generators/mesh_generators.h"

namespace ifem::fem {
namespace {

using intrinsic::IntrinsicTriangulation;
using intrinsic::TriangleMesh;

// Reference cotan Laplacian from 3D positions with triplets, the textbook way.
SparseMatrix positional_cotan(const TriangleMesh& m) {
  std::vector<Eigen::Triplet<double>> t;
  for (const auto& f : m.faces) {
    for (int k = 0; k < 3; ++k) {
      const Index i = f[k], j = f[(k + 1) % 3], o = f[(k + 2) % 3];
      const Eigen::Vector3d u = m.positions.row(i) - m.positions.row(o);
      const Eigen::Vector3d v = m.positions.row(j) - m.positions.row(o);
      const double cot = u.dot(v) / u.cross(v).norm();
      t.emplace_back(i, j, -0.5 * cot);
      t.emplace_back(j, i, -0.5 * cot);
      t.emplace_back(i, i, 0.5 * cot);
      t.emplace_back(j, j, 0.5 * cot);
    }
  }
  SparseMatrix L(m.positions.rows(), m.positions.rows());
  L.setFromTriplets(t.begin(), t.end());
  return L;
}

void expect_laplacian_properties(const SparseMatrix& L, bool delaunay) {
  const Eigen::VectorXd ones = Eigen::VectorXd::Ones(L.rows());
  const double scale = L.diagonal().cwiseAbs().maxCoeff();
  EXPECT_LT((L * ones).cwiseAbs().maxCoeff(), 1e-10 * scale);
  const SparseMatrix asym = SparseMatrix(L.transpose()) - L;
  EXPECT_LT(asym.cwiseAbs().sum(), 1e-12 * scale);
  if (delaunay) {
    for (int k = 0; k < L.outerSize(); ++k) {
      for (SparseMatrix::InnerIterator it(L, k); it; ++it) {
        if (it.row() != it.col()) {
          ASSERT_LE(it.value(), 1e-12 * scale);
        }
      }
    }
  }
}

TEST(Operators, MatchesPositionalCotanOnDelaunayMesh) {
  const TriangleMesh m = intrinsic::icosphere(5);
  auto tri = IntrinsicTriangulation::from_positions(m.faces, m.positions);
  ASSERT_EQ(tri.flip_to_delaunay().flips, 0u);  // the icosphere is already Delaunay
  const SparseMatrix L = cotan_laplacian(tri);
  const SparseMatrix ref = positional_cotan(m);
  EXPECT_LT((L - ref).cwiseAbs().sum(), 1e-10 * ref.cwiseAbs().sum());
  expect_laplacian_properties(L, true);
}

TEST(Operators, IntrinsicDelaunayLaplacianHasNonNegativeWeights) {
  const TriangleMesh m = test::jittered(intrinsic::uv_sphere(8, 120), 0.02);
  auto tri = IntrinsicTriangulation::from_positions(m.faces, m.positions);
  const SparseMatrix L0 = cotan_laplacian(tri);
  expect_laplacian_properties(L0, false);
  EXPECT_GT(L0.coeffs().maxCoeff(), 0.0);  // the needle fans give positive off-diagonals
  tri.flip_to_delaunay();
  expect_laplacian_properties(cotan_laplacian(tri), true);
}

TEST(Operators, MassSumsToArea) {
  const TriangleMesh m = intrinsic::grid(7, 5, 2.0, 3.0);
  const auto tri = IntrinsicTriangulation::from_positions(m.faces, m.positions);
  EXPECT_NEAR(lumped_mass(tri).sum(), 6.0, 1e-12);
  const SparseMatrix M = galerkin_mass(tri);
  EXPECT_NEAR(M.sum(), 6.0, 1e-12);
  // both masses integrate the linear function x exactly
  Eigen::VectorXd x = m.positions.col(0);
  const Eigen::VectorXd ones = Eigen::VectorXd::Ones(x.size());
  EXPECT_NEAR(ones.dot(M * x), 6.0, 1e-12);  // ∫ x over [0,2]×[0,3]
  EXPECT_NEAR(lumped_mass(tri).dot(x), 6.0, 1e-12);
}

TEST(Operators, LinearPrecisionOnFlatGrid) {
  // L annihilates linear functions at interior vertices of a flat mesh
  const TriangleMesh m = intrinsic::grid(9, 7, 1.0, 1.0, true);
  auto tri = IntrinsicTriangulation::from_positions(m.faces, m.positions);
  tri.flip_to_delaunay();
  const SparseMatrix L = cotan_laplacian(tri);
  const Eigen::VectorXd f = 2.0 * m.positions.col(0) - 3.0 * m.positions.col(1);
  const Eigen::VectorXd Lf = L * f;
  for (Index v = 0; v < tri.n_vertices(); ++v) {
    const double x = m.positions(v, 0), y = m.positions(v, 1);
    const bool interior = x > 1e-9 && x < 1 - 1e-9 && y > 1e-9 && y < 1 - 1e-9;
    if (interior) {
      EXPECT_NEAR(Lf[v], 0.0, 1e-12);
    }
  }
}

TEST(Operators, MultiEdgesAndUnreferencedVertices) {
  // 3-vertex sphere (two triangles glued along all sides) + an unreferenced vertex
  const std::vector<Triangle> f = {{0, 1, 2}, {0, 2, 1}};
  Eigen::MatrixX3d l(2, 3);
  l << 1.0, 1.2, 1.1, 1.1, 1.2, 1.0;
  auto tri = IntrinsicTriangulation::from_side_lengths(f, 4, l, nullptr);
  for (Index e = 0; e < 3; ++e) tri.flip_edge(e);  // creates a self-edge / multi-edge
  const SparseMatrix L = cotan_laplacian(tri);
  expect_laplacian_properties(L, false);
  EXPECT_EQ(L.coeff(3, 3), 0.0);
  EXPECT_EQ(lumped_mass(tri)[3], 0.0);
  // L from triplets agrees with the direct assembly
  const Eigen::VectorXd w = intrinsic::cotan_weights(tri);
  std::vector<Eigen::Triplet<double>> t;
  for (Index e = 0; e < tri.n_edges(); ++e) {
    const Index h = tri.edge_halfedge(e);
    const Index i = tri.tail(h), j = tri.head(h);
    t.emplace_back(i, j, -w[e]);
    t.emplace_back(j, i, -w[e]);
    t.emplace_back(i, i, w[e]);
    t.emplace_back(j, j, w[e]);
  }
  SparseMatrix ref(4, 4);
  ref.setFromTriplets(t.begin(), t.end());
  EXPECT_LT((L - ref).cwiseAbs().sum(), 1e-12);
}

}  // namespace
}  // namespace ifem::fem
