// Isolines: the level sets {f = c} of a per-vertex field f, linear on each triangle of the input
// mesh, as polylines on the surface (marching triangles). What `ifem isolines`, the --isolines
// option of `ifem distance` / `ifem poisson` and `ifem.isolines` (Python) run. Needs only the
// input's positions, triangles and field: no intrinsic triangulation, no solve.
//
// The rule at a vertex exactly on the level: a vertex with f == c counts as above (f ≥ c), so a
// triangle is cut iff min f < c ≤ max f over its corners, and every cut point lies on an edge
// from a corner below (f < c) to a corner above. A cut at a corner with f == c is that vertex,
// one point shared by every edge and triangle there: no duplicate points and no gaps where a
// curve runs through a vertex. Consequences: a triangle with all three corners at c (a plateau)
// gives nothing; an edge with both ends at c is part of the curve iff a triangle on it has its
// third corner below c (once, however many do); c = min f gives nothing (no corner is below),
// c = max f only edges whose ends are both maxima.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "intrinsic/core/types.h"

namespace ifem::recipes {

/// One point of an isoline: where the level crosses an input edge, or an input vertex at the
/// level.
struct IsolinePoint {
  /// The crossed edge: f(below) < c ≤ f(above). At a vertex with f == c: below == above == it.
  Index below = kInvalidIndex;
  Index above = kInvalidIndex;
  /// The position is (1 − t)·V[below] + t·V[above], t = (c − f(below)) / (f(above) − f(below))
  /// in [0, 1] (0 at a vertex point); f interpolated there equals c up to rounding.
  double t = 0.0;
  /// As a surface point: a triangle holding the edge (or vertex), the first in F's order among
  /// those the level cuts, and the barycentric coordinates of the point for that row's corners
  /// F(face, 0..2) (≥ 0, sum 1, at most two nonzero).
  Index face = kInvalidIndex;
  Eigen::Vector3d bary = Eigen::Vector3d::Zero();
  Eigen::Vector3d position = Eigen::Vector3d::Zero();  ///< in V's unit
};

/// One connected piece of the level set {f = c}.
struct Isoline {
  double value = 0.0;  ///< c
  Index level = 0;     ///< index of c in the values asked for
  /// Points in order along the curve (direction unspecified), ≥ 2, consecutive ones distinct.
  std::vector<IsolinePoint> points;
  /// The curve comes back to its first point: a segment joins points.back() to points.front()
  /// (the first point is not repeated). Open curves end on the mesh boundary, at a vertex where
  /// the level set branches (a saddle exactly at c, a nonmanifold edge or vertex), or at a
  /// triangle with a non-finite corner.
  bool closed = false;
};

/// The isolines of f at each value, in the order of `values`; the pieces of one value in a fixed
/// order (those through an end or branch point first, then the loops), the same for the same
/// input. Triangles with a non-finite f at a corner are skipped (e.g. the inf of unreachable
/// vertices in a distance). Degenerate triangles and any connectivity (boundary, nonmanifold,
/// several components) are accepted. Cost: one pass over F plus the cut triangles.
/// @param positions #V×3 (finite)
/// @param triangles #F triangles of vertex ids in [0, #V)
/// @param f #V values (finite or not)
/// @param values levels c, each finite and within [min f, max f] over f's finite values
/// @throws InvalidInput on a size mismatch, a vertex id out of range, a non-finite position,
///   no finite value in f, or a value that is not finite or outside f's range (naming it and
///   the range)
std::vector<Isoline> isolines(const Positions& positions, const std::vector<Triangle>& triangles,
                              const Eigen::VectorXd& f, const std::vector<double>& values);

/// `count` levels evenly spaced strictly inside f's range over its finite values:
/// c_i = lo + (i + 1)·(hi − lo)/(count + 1), i = 0 .. count − 1 (what --count N asks for).
/// @throws InvalidInput when count < 1 or f has no finite value
std::vector<double> isoline_levels(const Eigen::VectorXd& f, Index count);

}  // namespace ifem::recipes
