// The Delaunay star of one point among its projected neighbours: the triangles of the planar
// Delaunay triangulation incident to the centre, found as the convex hull of the neighbours
// inverted about the centre (circles through the centre become lines).
#pragma once

#include <Eigen/Core>
#include <array>
#include <vector>

namespace ifem::pointcloud {

/// Delaunay triangles incident to the origin among the planar points q (the origin itself is
/// the centre and is not listed). Appends to `out` one pair (a, b) of indices into q per
/// triangle (origin, q[a], q[b]), counter-clockwise, in counter-clockwise order around the
/// origin. Robust by construction: points within `min_relative_distance` × max|q| of the
/// origin (duplicates of the centre) are ignored, exact duplicates count once (smallest index),
/// collinear or too few points give no triangle; never throws, never produces NaN. O(n log n).
/// Returns the number of triangles appended.
int delaunay_star(const std::vector<Eigen::Vector2d>& q, std::vector<std::array<int, 2>>& out,
                  double min_relative_distance = 1e-9);

/// Scratch memory for delaunay_star(), reused across calls (one per thread) so that the
/// per-point loop of the point-cloud pipeline does not allocate.
struct StarWorkspace {
  struct Point {
    double x, y;
    int index;  // into q, or -1 for the origin
  };
  std::vector<Point> w, hull;
};

/// delaunay_star() with caller-owned scratch memory (same result).
int delaunay_star(const std::vector<Eigen::Vector2d>& q, std::vector<std::array<int, 2>>& out,
                  StarWorkspace& workspace, double min_relative_distance = 1e-9);

}  // namespace ifem::pointcloud
