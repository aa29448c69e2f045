// From an input mesh to the signpost triangulation FlipOut works on, and points given on the
// input's faces to points of that triangulation: what the `ifem geodesic` command and the Python
// geodesic functions share.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "intrinsic/core/errors.h"
#include "intrinsic/core/surface_point.h"
#include "intrinsic/geodesic/flip_geodesic.h"
#include "intrinsic/io/mesh_io.h"
#include "intrinsic/refine/signpost.h"

namespace ifem::intrinsic {

/// True when some face has positive area, judged before mollification (which would turn
/// degenerate faces into slivers), as the solver pipeline judges it.
bool has_positive_area(const io::SurfaceInput& in);

/// The signpost triangulation of an input with faces (SignpostTriangulation with the given
/// relative mollification margin).
/// @throws InvalidInput when no face has positive area
/// @throws NonManifoldInput when the mesh is not edge-manifold and orientable, saying that
///         FlipOut needs that and naming the offending edge (the library's message)
SignpostTriangulation flipout_surface(const io::SurfaceInput& in, double mollify);

/// For operations the tufted cover cannot serve: `need` (e.g. "X needs an edge-manifold,
/// orientable surface (why)") followed by ", and this mesh is not: " and e's message without
/// the library's advice to use the tufted cover.
NonManifoldInput manifold_only(const NonManifoldInput& e, const std::string& need);

/// For each given face (row of `given_faces`), the face of the input triangulation it became,
/// or kInvalidIndex where it was dropped (a face repeating a vertex).
/// @param input_face_origin per input face, the given face it came from
///        (SignpostTriangulation's or NormalCoordinateTriangulation's input_face_origin())
std::vector<Index> given_face_map(const std::vector<Index>& input_face_origin,
                                  std::size_t n_given_faces);

/// A point of given face `face` with barycentric weights `w` in that face's corner order, as a
/// point of `input` (the input triangulation face_map points into, e.g. st.input() or
/// NormalCoordinateTriangulation::input(); faces may have been reoriented: weights are matched
/// corner by corner).
/// @param face_map given_face_map(input_face_origin, given_faces.size())
/// @param name how messages call the point (e.g. "points[2]" or "'face:12:0.3:0.3'")
/// @throws InvalidInput if the face was dropped
SurfacePoint given_face_point(const IntrinsicTriangulation& input,
                              const std::vector<Triangle>& given_faces,
                              const std::vector<Index>& face_map, Index face,
                              const Eigen::Vector3d& w, const std::string& name);

/// One curve for shorten_through(): intrinsic vertex ids in order, closed or open, pinned at
/// its points or not, and how messages name it.
struct CurveThrough {
  std::vector<Index> vertices;
  bool closed = false;
  bool pin = false;
  std::string name;
};

/// The shortest edge path through each curve's points (Dijkstra), then all of them shortened
/// together by FlipOut. paths: the geodesics, one per curve; initial_lengths: each edge path's
/// length before shortening; options: how FlipOut runs.
/// @throws InvalidInput prefixed with the curve's name (e.g. points on different components)
FlipOutReport shorten_through(SignpostTriangulation& st, const std::vector<CurveThrough>& curves,
                              std::vector<EdgePath>* paths, std::vector<double>* initial_lengths,
                              const FlipOutOptions& options = {});

}  // namespace ifem::intrinsic
