// The connection from 3D frames (fem/frame_connection.h): the transport is a unit complex with
// r_ji = conj(r_ij), it carries a meridian's direction to the meridian's direction (the minimal
// rotation of the normals is parallel transport along a great circle), and the connection
// Laplacian is Hermitian PSD, the scalar Laplacian where the frames are parallel.
#include "fem/frame_connection.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <Eigen/Geometry>
#include <cmath>
#include <complex>
#include <random>

#include "fem/operators.h"
#include "intrinsic/generators/mesh_generators.h"
#include "support/dense_spectrum.h"

namespace ifem::fem {
namespace {

using Complex = std::complex<double>;

// A right-handed frame (n, e1, e2) with e1 the projection of `towards` (not parallel to n).
struct Frame {
  Eigen::Vector3d n, e1, e2;
};
Frame frame(const Eigen::Vector3d& normal, const Eigen::Vector3d& towards) {
  Frame f;
  f.n = normal.normalized();
  f.e1 = (towards - towards.dot(f.n) * f.n).normalized();
  f.e2 = f.n.cross(f.e1);
  return f;
}

Complex transport(const Frame& a, const Frame& b) {
  return frame_transport(a.n, a.e1, b.n, b.e1, b.e2);
}

TEST(FrameTransport, UnitAndConjugateBothWays) {
  std::mt19937 rng(5);
  std::normal_distribution<double> g;
  auto random_vector = [&] { return Eigen::Vector3d(g(rng), g(rng), g(rng)); };
  for (int k = 0; k < 200; ++k) {
    const Frame a = frame(random_vector(), random_vector());
    const Frame b = frame(random_vector(), random_vector());
    const Complex r = transport(a, b), back = transport(b, a);
    EXPECT_NEAR(std::abs(r), 1.0, 1e-12);
    EXPECT_NEAR(std::abs(r * back - 1.0), 0.0, 1e-10) << "r_ji = conj(r_ij)";
    EXPECT_NEAR(std::abs(transport(a, a) - 1.0), 0.0, 1e-12);
  }
  // opposite normals: defined, unit
  const Frame a = frame({0, 0, 1}, {1, 0, 0}), b = frame({0, 0, -1}, {0, 1, 0});
  EXPECT_NEAR(std::abs(transport(a, b)), 1.0, 1e-12);
}

// On the unit sphere the minimal rotation between the normals at two points of a meridian is
// the rotation about the meridian's axis: parallel transport along the great circle. A vector
// at angle α from the meridian's direction keeps that angle.
TEST(FrameTransport, KeepsTheAngleToAGreatCircle) {
  for (const double phi : {0.1, 0.7, 1.4, 2.5}) {
    const Eigen::Vector3d p(0, 0, 1), q(std::sin(phi), 0, std::cos(phi));
    const Eigen::Vector3d along_p(1, 0, 0), along_q(std::cos(phi), 0, -std::sin(phi));
    const Frame a = frame(p, Eigen::Vector3d(0.3, 1.0, 0.2));  // arbitrary e1
    const Frame b = frame(q, Eigen::Vector3d(-0.5, 0.4, 1.0));
    for (const double alpha : {0.0, 0.9, 2.0}) {
      const Eigen::Vector3d v = std::cos(alpha) * along_p + std::sin(alpha) * p.cross(along_p);
      const Complex at_a(v.dot(a.e1), v.dot(a.e2));
      const Complex at_b = transport(a, b) * at_a;
      const Eigen::Vector3d w = at_b.real() * b.e1 + at_b.imag() * b.e2;
      const Eigen::Vector3d expected =
          std::cos(alpha) * along_q + std::sin(alpha) * q.cross(along_q);
      EXPECT_LT((w - expected).norm(), 1e-12) << "phi " << phi << " alpha " << alpha;
    }
  }
}

// Frames from the positions of the unit icosphere (n = p, e1 the projected x axis, y near the
// poles), L the cotan Laplacian of the mesh.
TEST(FrameConnectionLaplacian, HermitianPsdOnASphere) {
  const intrinsic::TriangleMesh m = intrinsic::icosphere(5);
  auto tri = intrinsic::IntrinsicTriangulation::from_positions(m.faces, m.positions);
  tri.flip_to_delaunay();
  const SparseMatrix L = cotan_laplacian(tri);
  const Eigen::Index n = m.positions.rows();
  Eigen::MatrixX3d normal(n, 3), e1(n, 3), e2(n, 3);
  for (Eigen::Index v = 0; v < n; ++v) {
    const Eigen::Vector3d p = m.positions.row(v).transpose();
    const Frame f =
        frame(p, std::abs(p.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY());
    normal.row(v) = f.n.transpose();
    e1.row(v) = f.e1.transpose();
    e2.row(v) = f.e2.transpose();
  }
  for (const int sym : {1, 2, 4}) {
    const Eigen::MatrixXcd A(connection_laplacian_from_frames(L, normal, e1, e2, sym));
    ASSERT_TRUE(A.allFinite());
    const double scale = A.cwiseAbs().maxCoeff();
    EXPECT_EQ((A - A.adjoint()).cwiseAbs().maxCoeff(), 0.0) << "exactly Hermitian";
    const Eigen::VectorXd ev = test::self_adjoint_eigenvalues(A);
    EXPECT_GE(ev.minCoeff(), -1e-12 * scale);
    EXPECT_GT(ev.minCoeff(), 1e-3) << "a sphere has no parallel field, n = " << sym;
    EXPECT_LT((A.diagonal().real() - Eigen::MatrixXd(L).diagonal()).cwiseAbs().maxCoeff(),
              1e-12 * scale);
  }
  EXPECT_THROW(connection_laplacian_from_frames(L, normal.topRows(3), e1, e2, 1), InvalidInput);
  EXPECT_THROW(connection_laplacian_from_frames(L, normal, e1, e2, 0), InvalidInput);
}

// Parallel frames (a flat grid, every frame the same): the connection Laplacian is L.
TEST(FrameConnectionLaplacian, ParallelFramesGiveTheScalarLaplacian) {
  const intrinsic::TriangleMesh m = intrinsic::grid(6, 5);
  const auto tri = intrinsic::IntrinsicTriangulation::from_positions(m.faces, m.positions);
  const SparseMatrix L = cotan_laplacian(tri);
  const Eigen::Index n = m.positions.rows();
  const Eigen::MatrixX3d normal = Eigen::RowVector3d(0, 0, 1).replicate(n, 1);
  const Eigen::MatrixX3d e1 = Eigen::RowVector3d(0.6, 0.8, 0).replicate(n, 1);
  const Eigen::MatrixX3d e2 = Eigen::RowVector3d(-0.8, 0.6, 0).replicate(n, 1);
  const Eigen::MatrixXcd A(connection_laplacian_from_frames(L, normal, e1, e2, 4));
  EXPECT_LT((A - Eigen::MatrixXd(L).cast<Complex>()).cwiseAbs().maxCoeff(), 1e-14);
}

}  // namespace
}  // namespace ifem::fem
