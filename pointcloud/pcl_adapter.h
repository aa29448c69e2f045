// Optional PCL adapter (target ifem::pcl, built only when PCL ≥ 1.13 is found): PCL clouds and
// .pcd files → ifem positions / normals → pointcloud_triangulation(). Include this header only
// if you use PCL; the PCL types are forward-declared here, so the header itself needs no PCL
// include path (your code that builds pcl::PointCloud objects does).
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "pointcloud/pointcloud_laplacian.h"

namespace pcl {
struct PointXYZ;
struct PointNormal;
template <typename PointT>
class PointCloud;
}  // namespace pcl

namespace ifem::pointcloud {

/// A PCL cloud converted to ifem arrays. PCL marks missing points (organized clouds) with NaN
/// coordinates: those are dropped, and source_index maps each kept point back to its PCL index.
struct PclPoints {
  Positions positions;              ///< #P×3, finite
  Eigen::MatrixX3d normals;         ///< #P×3 when the cloud has normals, else 0×3 (a non-finite
                                    ///< normal becomes 0: pointcloud_triangulation uses PCA there)
  std::vector<Index> source_index;  ///< #P: index of each point in the PCL cloud / file
  Index dropped_non_finite = 0;     ///< points dropped for a non-finite coordinate
  bool has_normals() const { return normals.rows() == positions.rows() && positions.rows() > 0; }
};

/// Positions of a PointXYZ cloud (non-finite points dropped).
PclPoints from_pcl(const pcl::PointCloud<pcl::PointXYZ>& cloud);

/// Positions and normals of a PointNormal cloud (non-finite points dropped).
PclPoints from_pcl(const pcl::PointCloud<pcl::PointNormal>& cloud);

/// Reads a .pcd file (ASCII, binary or binary_compressed): x y z, and normal_x normal_y
/// normal_z when the file has them.
/// @throws IoError if the file cannot be read or has no x, y, z fields
PclPoints read_pcd(const std::string& path);

/// The point-cloud triangulation of a PCL cloud: from_pcl() then pointcloud_triangulation().
/// Vertex i of the result is PCL point points_out->source_index[i] (pass points_out to get it).
/// @param[out] points_out optional: the converted points (positions, normals, source_index)
/// @param[out] report optional: what pointcloud_triangulation() did
/// @throws InvalidInput as pointcloud_triangulation()
intrinsic::IntrinsicTriangulation pcl_triangulation(const pcl::PointCloud<pcl::PointXYZ>& cloud,
                                                    const PointCloudOptions& options = {},
                                                    PclPoints* points_out = nullptr,
                                                    Report* report = nullptr);

/// Same for a PointNormal cloud (its normals are used as PointCloudOptions::use_input_normals
/// says).
intrinsic::IntrinsicTriangulation pcl_triangulation(const pcl::PointCloud<pcl::PointNormal>& cloud,
                                                    const PointCloudOptions& options = {},
                                                    PclPoints* points_out = nullptr,
                                                    Report* report = nullptr);

/// Deprecated argument order (report before points_out; reports come last,
/// docs/decisions.md D-001): the implementation until the definitions in pcl_adapter.cpp move to
/// the signatures above. Passing nullptr for both outputs is ambiguous: omit them instead.
intrinsic::IntrinsicTriangulation pcl_triangulation(const pcl::PointCloud<pcl::PointXYZ>& cloud,
                                                    const PointCloudOptions& options,
                                                    Report* report,
                                                    PclPoints* points_out = nullptr);
/// Deprecated argument order, as above.
intrinsic::IntrinsicTriangulation pcl_triangulation(const pcl::PointCloud<pcl::PointNormal>& cloud,
                                                    const PointCloudOptions& options,
                                                    Report* report,
                                                    PclPoints* points_out = nullptr);

inline intrinsic::IntrinsicTriangulation pcl_triangulation(
    const pcl::PointCloud<pcl::PointXYZ>& cloud, const PointCloudOptions& options,
    PclPoints* points_out, Report* report) {
  return pcl_triangulation(cloud, options, report, points_out);
}
inline intrinsic::IntrinsicTriangulation pcl_triangulation(
    const pcl::PointCloud<pcl::PointNormal>& cloud, const PointCloudOptions& options,
    PclPoints* points_out, Report* report) {
  return pcl_triangulation(cloud, options, report, points_out);
}

}  // namespace ifem::pointcloud
