// The trace recipe: straight geodesics (the exponential map) from a point of the input surface
// in a given direction, for a given length. What `ifem trace` and `ifem.trace_geodesic`
// (Python) run:
//
//   input mesh ──► its own intrinsic triangulation (input faces, Euclidean lengths: no flips,
//                  no mollification, so the traced polyline lies exactly on the input faces)
//   start + 3D direction ──► a unit tangent in one face's layout (rule below)
//              ──► intrinsic::trace_straight (unfolding face after face)
//              ──► polyline on the input (3D), the end as a point of a given face
//
// Start direction. At a face point the 3D direction is projected onto the face's plane. At a
// vertex v it is projected onto the plane normal to the angle-weighted vertex normal; in that
// plane the projections of v's edges split the plane into wedges, and each wedge is mapped
// linearly onto the corner (between the same two edges) that it stands for in v's angle
// coordinates. So a direction along an edge's projection runs along that edge, and at a flat
// vertex the rule is the identity. When the projected edges do not go round v once in order
// (a strongly folded vertex) the whole turn is scaled uniformly instead (angle θ from v's first
// edge ↦ θ·Θ_v/2π; at a boundary vertex the turn from the first to the last boundary edge ↦
// [0, Θ_v]); at a boundary vertex a direction outside that range points off the surface and is
// refused.
//
// The ray passes through vertices by unfolding the fan around them (at a flat vertex: straight
// on). At a boundary it stops (GeodesicRay::hit_boundary) or, with slide_on_boundary, goes on
// along the boundary for the rest of its length.
//
// Needs an edge-manifold, orientable triangle mesh (nonmanifold inputs are refused: a ray has
// no single continuation across an edge of 3+ faces); vertex starts need a vertex whose faces
// form one fan (not a pinched vertex).
#pragma once

#include <Eigen/Core>
#include <array>
#include <string>
#include <vector>

#include "intrinsic/core/triangulation.h"
#include "intrinsic/io/surface_input.h"
#include "solvers/recipes/text_formats.h"

namespace ifem::recipes {

/// How trace_geodesic() runs.
struct TraceGeodesicOptions {
  /// At a boundary side the ray goes on along the boundary, towards the end it was heading to,
  /// for the rest of its length; it stops where it meets a side square on (|cos| ≤ 1e-12), as
  /// at a right-angled boundary corner. false: it stops at the first boundary side.
  bool slide_on_boundary = false;
};

/// A point of the input surface as given: a face of io::SurfaceInput::triangles and the
/// barycentric weights of its corners in the input's corner order.
struct InputSurfacePoint {
  Index face = kInvalidIndex;
  std::array<double, 3> bary{};  ///< ≥ 0, summing to 1
  /// The input vertex it is (a weight within 1e-12 of 1), else kInvalidIndex.
  Index vertex = kInvalidIndex;
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  /// "face:F:u:v" with u = bary[1], v = bary[2] (17 significant digits): the point syntax of
  /// `ifem geodesic --path` and `ifem trace --from` (parse_point_token()).
  std::string token() const;
};

/// One traced ray.
struct GeodesicRay {
  /// Start, every side crossing, end: 3D points on the input's faces (consecutive points closer
  /// than 1e-14 × the mesh's bounding-box diagonal, as at a vertex passed through, are one).
  std::vector<Eigen::Vector3d> polyline;
  InputSurfacePoint end;
  Eigen::Vector3d start_direction = Eigen::Vector3d::Zero();  ///< unit 3D tangent it left in
  Eigen::Vector3d end_direction = Eigen::Vector3d::Zero();    ///< unit 3D tangent at the end
  double length = 0.0;        ///< the polyline's length: the length asked unless it stopped
  bool hit_boundary = false;  ///< stopped at a boundary side before the length asked
  Index slides = 0;           ///< boundary sides it slid along (slide_on_boundary)
};

/// A traced input, built once and traced from many times (the one-off is trace_geodesic()).
class GeodesicTracer {
 public:
  /// @throws InvalidInput when the input has no faces or no face has area
  /// @throws NonManifoldInput when it is not edge-manifold and orientable (naming the edge)
  explicit GeodesicTracer(const io::SurfaceInput& input);

  /// The straight geodesic from `start` (a vertex, or a face point of a triangle input;
  /// point_problem() in geodesic.h) leaving in `direction` (3D, any length > 0, made tangent
  /// by the rule at the top of this file) for `length` (≥ 0, the input's length unit).
  /// @throws InvalidInput: a bad start (naming it and the range), a non-finite or zero
  ///         direction, a direction along the normal (tangent part ≤ 1e-9 of it), pointing
  ///         off the surface at a boundary vertex, a start in a face without area or at a
  ///         pinched vertex, a negative or non-finite length
  /// @throws TraceError when the ray cannot be traced (a face without area on its way)
  GeodesicRay trace(const GivenPoint& start, const Eigen::Vector3d& direction, double length,
                    const TraceGeodesicOptions& options = {}) const;

  const intrinsic::IntrinsicTriangulation& triangulation() const { return tri_; }

 private:
  struct Start;
  Start face_start(const GivenPoint& p, const Eigen::Vector3d& direction) const;
  Start vertex_start(Index v, const Eigen::Vector3d& direction) const;
  Eigen::Vector3d to_3d(Index f, const Eigen::Vector2d& w) const;
  Eigen::Vector3d position(Index f, const Eigen::Vector3d& bary) const;
  InputSurfacePoint on_input(Index f, const Eigen::Vector3d& bary) const;

  io::SurfaceInput input_;  // positions, triangles, n_non_triangles (a copy)
  intrinsic::IntrinsicTriangulation tri_;
  std::vector<Index> face_origin_;  // #F of tri_: the given face
  std::vector<Index> given_face_;   // #given faces: face of tri_, or kInvalidIndex (dropped)
  std::vector<Index> out_degree_;   // #V: halfedges leaving each vertex
  double merge_distance_ = 0.0;     // polyline points closer than this are one
};

/// A directions file (`ifem trace --directions`): one direction 'X Y Z' (three finite numbers,
/// not all zero) per line, '#' starts a comment, blank lines are skipped.
/// @throws IoError naming "FILE:line" on an unreadable file, a malformed line or a zero
///         direction; a file without a direction is an error too
std::vector<Eigen::Vector3d> read_directions_file(const std::string& path);

/// "X,Y,Z" (three finite numbers, not all zero: `ifem trace --direction`) into d.
/// @return "" on success, else what is wrong (naming the text)
std::string parse_direction(const std::string& text, Eigen::Vector3d& d);

/// One ray: GeodesicTracer(input).trace(start, direction, length, options).
GeodesicRay trace_geodesic(const io::SurfaceInput& input, const GivenPoint& start,
                           const Eigen::Vector3d& direction, double length,
                           const TraceGeodesicOptions& options = {});

}  // namespace ifem::recipes
