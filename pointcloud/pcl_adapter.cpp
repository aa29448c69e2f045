#include "pointcloud/pcl_adapter.h"

#include <pcl/PCLPointCloud2.h>
#include <pcl/conversions.h>
#include <pcl/io/pcd_io.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <cmath>
#include <string>
#include <type_traits>
#include <utility>

#include "intrinsic/core/errors.h"

namespace ifem::pointcloud {
namespace {

template <class Point>
PclPoints convert(const pcl::PointCloud<Point>& cloud, bool with_normals) {
  PclPoints out;
  const std::size_t n = cloud.points.size();
  checked_index(n, "from_pcl");
  Index kept = 0;
  for (const Point& p : cloud.points) {
    kept += std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z);
  }
  out.positions.resize(kept, 3);
  out.source_index.resize(kept);
  if (with_normals) out.normals.resize(kept, 3);
  Index k = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const Point& p = cloud.points[i];
    if (!(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z))) continue;
    out.positions.row(k) << p.x, p.y, p.z;
    out.source_index[k] = static_cast<Index>(i);
    if constexpr (std::is_same_v<Point, pcl::PointNormal>) {
      if (with_normals) {
        const bool ok =
            std::isfinite(p.normal_x) && std::isfinite(p.normal_y) && std::isfinite(p.normal_z);
        if (ok) {
          out.normals.row(k) << p.normal_x, p.normal_y, p.normal_z;
        } else {
          out.normals.row(k).setZero();
        }
      }
    }
    ++k;
  }
  out.dropped_non_finite = static_cast<Index>(n) - kept;
  return out;
}

template <class Point>
intrinsic::IntrinsicTriangulation triangulate(const pcl::PointCloud<Point>& cloud,
                                              const PointCloudOptions& options, Report* report,
                                              PclPoints* points_out) {
  PclPoints pts = from_pcl(cloud);
  intrinsic::IntrinsicTriangulation tri = pointcloud_triangulation(
      pts.positions, options, pts.has_normals() ? &pts.normals : nullptr, report);
  if (points_out) *points_out = std::move(pts);
  return tri;
}

}  // namespace

PclPoints from_pcl(const pcl::PointCloud<pcl::PointXYZ>& cloud) { return convert(cloud, false); }

PclPoints from_pcl(const pcl::PointCloud<pcl::PointNormal>& cloud) { return convert(cloud, true); }

PclPoints read_pcd(const std::string& path) {
  pcl::PCLPointCloud2 blob;
  pcl::PCDReader reader;
  if (reader.read(path, blob) < 0) throw IoError(path + ": cannot read the .pcd file (PCL)");
  bool x = false, y = false, z = false, nx = false, ny = false, nz = false;
  for (const auto& f : blob.fields) {
    x |= f.name == "x", y |= f.name == "y", z |= f.name == "z";
    nx |= f.name == "normal_x", ny |= f.name == "normal_y", nz |= f.name == "normal_z";
  }
  if (!(x && y && z)) throw IoError(path + ": the .pcd file has no x, y, z fields");
  if (nx && ny && nz) {
    pcl::PointCloud<pcl::PointNormal> cloud;
    pcl::fromPCLPointCloud2(blob, cloud);
    return convert(cloud, true);
  }
  pcl::PointCloud<pcl::PointXYZ> cloud;
  pcl::fromPCLPointCloud2(blob, cloud);
  return convert(cloud, false);
}

intrinsic::IntrinsicTriangulation pcl_triangulation(const pcl::PointCloud<pcl::PointXYZ>& cloud,
                                                    const PointCloudOptions& options,
                                                    Report* report, PclPoints* points_out) {
  return triangulate(cloud, options, report, points_out);
}

intrinsic::IntrinsicTriangulation pcl_triangulation(const pcl::PointCloud<pcl::PointNormal>& cloud,
                                                    const PointCloudOptions& options,
                                                    Report* report, PclPoints* points_out) {
  return triangulate(cloud, options, report, points_out);
}

}  // namespace ifem::pointcloud
