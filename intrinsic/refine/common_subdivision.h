// The common subdivision of a signpost triangulation (the overlay of the intrinsic and the input
// triangulations as a 3D mesh on the input surface) and the PLY writers for it and for traced
// polylines.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "intrinsic/refine/signpost.h"

namespace ifem::intrinsic {

/// The common subdivision of a signpost triangulation: the overlay of the intrinsic and the
/// input triangulations, as a 3D triangle mesh on the input surface. Each of its polygons (the
/// intersection of one intrinsic face with one input face, convex) is split into a fan of
/// triangles, which record both faces. Its total area is the input's.
struct CommonSubdivision {
  Positions positions;  ///< vertices: input vertices first (same ids), then
                        ///< inserted intrinsic vertices, then edge crossings
  std::vector<Triangle> faces;
  std::vector<Index> intrinsic_face;  ///< per face: the intrinsic face it lies in
  std::vector<Index> input_face;      ///< per face: the input face, as an index into the
                                      ///< faces given (SignpostTriangulation::input_faces())
};

/// Builds the common subdivision by tracing every intrinsic edge over the input and cutting
/// each input face along the traced segments. @throws TraceError when a trace fails
CommonSubdivision common_subdivision(const SignpostTriangulation& st);

/// Writes a common subdivision as a PLY triangle mesh with face properties `intrinsic_face`
/// and `input_face` (int). Atomic. @throws IoError if the file cannot be written
void write_common_subdivision_ply(const std::string& path, const CommonSubdivision& cs,
                                  bool binary = true);

/// Writes polylines (e.g. SignpostTriangulation::traced_edges_3d()) as a PLY line set:
/// vertices (x, y, z as double) and edges (vertex1, vertex2 as int), binary little-endian or
/// ASCII; opens in MeshLab, ParaView, Polyscope. Atomic (writes path.tmp, then renames).
/// @throws IoError if the file cannot be written
void write_polylines_ply(const std::string& path,
                         const std::vector<std::vector<Eigen::Vector3d>>& polylines,
                         bool binary = true);

}  // namespace ifem::intrinsic
