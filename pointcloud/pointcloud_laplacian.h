// Point-cloud Laplacian (Sharp & Crane 2020, "A Laplacian for Nonmanifold Triangle Meshes",
// §5.3): kNN neighbourhoods, tangent plane by PCA, planar Delaunay triangulation of each
// point's projected neighbours keeping the triangles at the point, the union of all those
// triangles glued into a tufted cover, mollified and flipped to intrinsic Delaunay. Build L and
// M from the result with fem::cotan_laplacian / fem::lumped_mass.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "intrinsic/core/triangulation.h"
#include "intrinsic/surface/tufted_cover.h"
#include "pointcloud/knn.h"

namespace ifem::pointcloud {

/// Settings of the point-cloud pipeline.
struct PointCloudOptions {
  int k = 30;                     ///< neighbours per point, ≥ 2 (clamped to #P − 1)
  bool use_input_normals = true;  ///< use the given normals where finite and non-zero
  /// Mollification margin relative to the mean edge length (IntrinsicTriangulation::mollify);
  /// finite, ≥ 0.
  double mollify_relative_epsilon = intrinsic::kDefaultMollifyEpsilon;
  bool intrinsic_delaunay = true;  ///< flip the cover to intrinsic Delaunay
  /// false: the flips to intrinsic Delaunay skip a flip whose new edge would join a point to
  /// itself (a self-edge: a flip of a diamond whose two opposite corners are one point, which
  /// the Delaunay triangulation of the cover has where a point's fans wind around it), so the
  /// cover keeps none (it has none before the flips) and is Delaunay everywhere else. What
  /// intrinsic::simplify needs to reach its target (a point on its own link cannot be removed;
  /// docs/decisions.md D-345); L and M are then not exactly the Delaunay ones. Default true.
  bool self_edges = true;
  /// How the local triangles are glued (weights of triangles found in 1, 2, 3 stars):
  /// kNone 1/3, 2/3, 1 (×3 copies); kHalf 1/2, 1/2, 1 (×2); kUnion 1, 1, 1 (×1). See
  /// pointcloud_triangulation().
  enum class Merge { kNone, kHalf, kUnion };
  Merge merge = Merge::kHalf;
  /// @throws InvalidInput naming the field: k < 2, mollify_relative_epsilon negative or not finite
  void validate() const;
};

/// What the pipeline did, counted, with the time of each stage.
struct Report {
  Index points = 0;
  int k = 0;                     ///< neighbours actually used
  Index local_triangles = 0;     ///< triangles over all local triangulations (a triangle found
                                 ///< from each of its three corners counts three times)
  Index distinct_triangles = 0;  ///< distinct triangles among them (glued once or more into
                                 ///< the cover, as PointCloudOptions::merge says)
  Index triangles_in_stars[3] = {0, 0, 0};  ///< distinct triangles found in 1, 2, 3 stars
  Index starless_points = 0;  ///< points whose own neighbourhood gave no triangle: fewer than
                              ///< 3 distinct neighbours, collinear, or all at the point
  Index isolated_points = 0;  ///< points in no triangle at all: zero row in L, zero mass
  Index first_isolated_point = kInvalidIndex;
  Index coincident_points = 0;   ///< points with another point at exactly the same position
  Index normals_from_input = 0;  ///< points whose tangent plane came from the given normals
  intrinsic::TuftedCoverReport cover;
  intrinsic::MollifyReport mollify;
  intrinsic::FlipReport flips;
  double seconds_knn = 0, seconds_local = 0, seconds_cover = 0, seconds_idt = 0;  ///< wall time
};

/// The triangles of every point's local Delaunay star, in point order: for point i, the
/// Delaunay triangulation of its k neighbours projected to i's tangent plane (PCA of the
/// neighbourhood, or normals[i]), the triangles incident to i, as (i, a, b) counter-clockwise
/// about the plane's normal. Parallel (OpenMP) over points; deterministic.
/// @param neighbours k_nearest(points, k) or any neighbour lists over the same points
/// @param normals #P×3 or null; rows that are zero or not finite fall back to PCA
/// @param[out] report optional: local_triangles, starless_points, coincident_points and
///        normals_from_input are set
std::vector<Triangle> local_triangulations(const Positions& points, const Neighbours& neighbours,
                                           const Eigen::MatrixX3d* normals = nullptr,
                                           Report* report = nullptr);

/// The whole pipeline: a tufted cover of the union of local triangulations over the cloud's
/// points (ids = input order). A triangle found in c of the stars of its three corners has
/// weight c/3 with Merge::kNone (glued c times, cover multiplicity 6 = 2 front/back × 3), as in
/// Sharp & Crane 2020 §5.3. The default Merge::kHalf glues each distinct triangle twice if all
/// three stars have it (weight 1, the same as c/3) and once otherwise (weight 1/2 instead of
/// 2/3 or 1/3; multiplicity 4): about 1.5× fewer cover faces. Where the stars agree the two give
/// the same L and M (the flipped cover is then a covering of one intrinsic Delaunay
/// triangulation); where two stars pick one diagonal of a quad and two the other, the four
/// triangles weigh 1/2 each and cover the quad exactly once instead of 4/3 times (the three
/// compared: docs/decisions.md D-016). Merge::kUnion (each
/// distinct triangle once, multiplicity 2) is smallest but over-counts overlaps: for
/// experiments only.
/// Mollified and, unless disabled, intrinsic Delaunay. Always finite; isolated points
/// (reported) have no halfedge, hence a zero row in L and zero mass: solvers give them +inf
/// distance / 0.
/// @param points #P×3, finite (any number, including 0, 1, 2)
/// @param normals optional #P×3 (e.g. from the file)
/// @param[out] report optional: counts and stage times
/// @throws InvalidInput on a non-finite coordinate, bad options (PointCloudOptions::validate()) or
/// a
///         normals size mismatch
intrinsic::IntrinsicTriangulation pointcloud_triangulation(
    const Positions& points, const PointCloudOptions& options = {},
    const Eigen::MatrixX3d* normals = nullptr, Report* report = nullptr);

}  // namespace ifem::pointcloud
