// The connection Laplacian (fem/connection.h) on point-cloud triangulations: a tufted cover whose
// vertices have several fans. Hermitian, PSD (intrinsic Delaunay: non-negative weights), finite.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <complex>

#include "fem/connection.h"
#include "intrinsic/generators/mesh_generators.h"
#include "pointcloud/pointcloud_laplacian.h"
#include "support/dense_spectrum.h"

namespace ifem::pointcloud {
namespace {

TEST(PointCloudConnection, HermitianPsdAndFinite) {
  const Positions points = intrinsic::icosphere(8).positions;
  const intrinsic::IntrinsicTriangulation tri = pointcloud_triangulation(points);
  const fem::TangentFrames fr = fem::tangent_frames(tri);
  ASSERT_TRUE(fr.halfedge_angle.allFinite() && fr.transport.allFinite());
  for (Index h = 0; h < tri.n_halfedges(); ++h) {
    EXPECT_NEAR(std::abs(fr.transport[h]), 1.0, 1e-14);
    if (tri.twin(h) != kInvalidIndex) {
      EXPECT_LT(std::abs(fr.transport[h] * fr.transport[tri.twin(h)] - 1.0), 1e-14);
    }
  }
  for (const int n : {1, 2, 4}) {
    SCOPED_TRACE(n);
    const Eigen::MatrixXcd L(fem::connection_laplacian(tri, fr, n));
    ASSERT_TRUE(L.allFinite());
    const double scale = L.cwiseAbs().maxCoeff();
    EXPECT_LE((L - L.adjoint()).cwiseAbs().maxCoeff(), 1e-14 * scale);
    const Eigen::VectorXd ev = test::self_adjoint_eigenvalues(L);
    EXPECT_GE(ev.minCoeff(), -1e-10 * ev.maxCoeff());
    EXPECT_GT(ev.maxCoeff(), 0.0);
  }
}

}  // namespace
}  // namespace ifem::pointcloud
