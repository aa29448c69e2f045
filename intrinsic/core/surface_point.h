// A point on a triangulated surface, as a face and barycentric coordinates: the one type for
// points on a surface across ifem (signpost vertex locations and traces, heat-method sources).
#pragma once

#include <Eigen/Core>

#include "intrinsic/core/types.h"

namespace ifem::intrinsic {

/// A point on a triangulated surface: face `face` of some triangulation (which one is the
/// user's contract: e.g. SignpostTriangulation::vertex_location() refers to input(),
/// HeatDistanceSolver sources to triangulation()) and barycentric coordinates `bary` for its
/// corners 0, 1, 2 (corner s is the tail of halfedge 3·face + s): non-negative, summing to 1.
/// A vertex is a face corner with coordinate 1. Default: no face (kInvalidIndex), so a point
/// that was never set is rejected by every function that takes one.
struct SurfacePoint {
  Index face = kInvalidIndex;
  Eigen::Vector3d bary = Eigen::Vector3d::Zero();
};

}  // namespace ifem::intrinsic
