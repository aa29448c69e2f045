// The optional PCL adapter (built only with PCL): .pcd round trips and in-memory clouds give
// exactly what the Positions path gives on the same (float-rounded) coordinates.
#include "pointcloud/pcl_adapter.h"

#include <gtest/gtest.h>
#include <pcl/io/pcd_io.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <limits>
#include <string>

#include "fem/operators.h"
#include "intrinsic/core/errors.h"

namespace ifem::pointcloud {
namespace {

// Fibonacci sphere, coordinates rounded to float (PCL stores floats).
Positions fibonacci_sphere_float(int n) {
  Positions p(n, 3);
  const double golden = M_PI * (3.0 - std::sqrt(5.0));
  for (int i = 0; i < n; ++i) {
    const double z = 1.0 - (2.0 * i + 1.0) / n;
    const double r = std::sqrt(1.0 - z * z);
    // volatile: the values must really be rounded to float, as PCL stores them
    const volatile float x = static_cast<float>(r * std::cos(golden * i));
    const volatile float y = static_cast<float>(r * std::sin(golden * i));
    const volatile float zf = static_cast<float>(z);
    p(i, 0) = x, p(i, 1) = y, p(i, 2) = zf;
  }
  return p;
}

std::string temp_path(const std::string& name) {
  return (std::filesystem::temp_directory_path() /
          ("ifem_pcl_" + std::to_string(::getpid()) + "_" + name))
      .string();
}

double max_abs_diff(const fem::SparseMatrix& a, const fem::SparseMatrix& b) {
  const fem::SparseMatrix d = a - b;
  double m = 0;
  for (int k = 0; k < d.outerSize(); ++k) {
    for (fem::SparseMatrix::InnerIterator it(d, k); it; ++it) m = std::max(m, std::abs(it.value()));
  }
  return m;
}

void expect_same_operators(const intrinsic::IntrinsicTriangulation& a,
                           const intrinsic::IntrinsicTriangulation& b) {
  ASSERT_EQ(a.n_vertices(), b.n_vertices());
  ASSERT_EQ(a.n_faces(), b.n_faces());
  EXPECT_EQ(max_abs_diff(fem::cotan_laplacian(a), fem::cotan_laplacian(b)), 0.0);
  EXPECT_EQ((fem::lumped_mass(a) - fem::lumped_mass(b)).cwiseAbs().maxCoeff(), 0.0);
}

TEST(PclAdapter, BinaryPcdRoundTripMatchesPositionsPath) {
  const Positions p = fibonacci_sphere_float(800);
  pcl::PointCloud<pcl::PointXYZ> cloud;
  for (Eigen::Index i = 0; i < p.rows(); ++i) {
    cloud.push_back(pcl::PointXYZ(static_cast<float>(p(i, 0)), static_cast<float>(p(i, 1)),
                                  static_cast<float>(p(i, 2))));
  }
  const std::string file = temp_path("sphere.pcd");
  ASSERT_EQ(pcl::io::savePCDFileBinary(file, cloud), 0);
  const PclPoints in = read_pcd(file);
  std::filesystem::remove(file);
  ASSERT_EQ(in.positions.rows(), p.rows());
  EXPECT_FALSE(in.has_normals());
  EXPECT_EQ(in.dropped_non_finite, 0);
  EXPECT_EQ((in.positions - p).cwiseAbs().maxCoeff(), 0.0);
  for (Index i = 0; i < p.rows(); ++i) ASSERT_EQ(in.source_index[i], i);

  Report ra, rb;
  const auto a = pointcloud_triangulation(p, {}, nullptr, &ra);
  const auto b = pointcloud_triangulation(in.positions, {}, nullptr, &rb);
  expect_same_operators(a, b);
  EXPECT_EQ(ra.isolated_points, 0);
  // and straight from the in-memory cloud
  expect_same_operators(a, pcl_triangulation(cloud));
}

TEST(PclAdapter, NormalsAndMissingPoints) {
  const Positions p = fibonacci_sphere_float(500);
  pcl::PointCloud<pcl::PointNormal> cloud;
  const float nan = std::numeric_limits<float>::quiet_NaN();
  for (Eigen::Index i = 0; i < p.rows(); ++i) {
    pcl::PointNormal q;
    q.x = static_cast<float>(p(i, 0)), q.y = static_cast<float>(p(i, 1)),
    q.z = static_cast<float>(p(i, 2));
    q.normal_x = q.x, q.normal_y = q.y, q.normal_z = q.z;  // the sphere's outward normal
    cloud.push_back(q);
    if (i % 100 == 7) {  // an organized cloud's missing point
      pcl::PointNormal m;
      m.x = m.y = m.z = nan;
      cloud.push_back(m);
    }
  }
  const std::string file = temp_path("normals.pcd");
  ASSERT_EQ(pcl::io::savePCDFileBinaryCompressed(file, cloud), 0);
  const PclPoints in = read_pcd(file);
  std::filesystem::remove(file);
  EXPECT_EQ(in.dropped_non_finite, 5);
  ASSERT_EQ(in.positions.rows(), p.rows());
  ASSERT_TRUE(in.has_normals());
  EXPECT_EQ((in.positions - p).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_EQ((in.normals - p).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_EQ(in.source_index[8], 9);  // after the first missing point

  Report ra, rb;
  const auto a = pointcloud_triangulation(p, {}, &in.normals, &ra);
  PclPoints used;
  const auto b = pcl_triangulation(cloud, {}, &rb, &used);
  EXPECT_EQ(rb.normals_from_input, p.rows());
  EXPECT_EQ(used.source_index, in.source_index);
  expect_same_operators(a, b);
}

TEST(PclAdapter, Errors) {
  EXPECT_THROW(read_pcd(temp_path("does_not_exist.pcd")), IoError);
  const std::string file = temp_path("empty.pcd");
  pcl::PointCloud<pcl::PointXYZ> empty;
  empty.push_back(pcl::PointXYZ(0, 0, 0));
  ASSERT_EQ(pcl::io::savePCDFileASCII(file, empty), 0);
  const PclPoints one = read_pcd(file);
  std::filesystem::remove(file);
  EXPECT_EQ(one.positions.rows(), 1);
  const auto tri = pointcloud_triangulation(one.positions);
  EXPECT_EQ(tri.n_faces(), 0);
}

}  // namespace
}  // namespace ifem::pointcloud
