// What a mesh or point-cloud file held (SurfaceInput) and a named scalar property: the types the
// readers fill and the writers take (mesh_io.h), apart from the functions so that the readers'
// private helpers (detail.h) need not include mesh_io.h.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "intrinsic/core/types.h"

namespace ifem::io {

/// A named per-vertex scalar (a PLY vertex property).
struct VertexProperty {
  std::string name;
  Eigen::VectorXd values;  ///< #V
};

/// What a file held, as given: positions in file order and polygons triangulated.
struct SurfaceInput {
  Positions positions;  ///< #V×3, file order
  /// Triangles in polygon order, each oriented like its polygon; a triangle is kept as is. A
  /// polygon of n > 3 corners gives n − 2 triangles whose diagonals never coincide with a side
  /// of any polygon in the file or a diagonal chosen for an earlier polygon — so no triangle
  /// repeats and no edge gets more faces than the polygons imply — preferring short diagonals
  /// (a quad takes the shorter valid diagonal; ties keep the fan from its first corner).
  /// Polygons that repeat a vertex are fanned from their first corner (v0, vi, vi+1).
  std::vector<Triangle> triangles;
  std::vector<Index> triangle_polygon;  ///< #T: index of the file polygon each triangle came from
  Index n_polygons = 0;                 ///< polygons in the file (faces, strips decoded)
  Index n_non_triangles = 0;            ///< polygons with more than 3 corners
  Eigen::MatrixX3d normals;             ///< #V×3 when the file has per-vertex normals, else 0×3
  std::vector<VertexProperty> vertex_properties;  ///< other per-vertex scalars (PLY), as doubles
  /// Per-face scalars of a PLY `face` element (other than its index list), as doubles: one
  /// value per item of that element, in file order (= n_polygons without tristrips; a polygon's
  /// triangles share it through triangle_polygon).
  std::vector<VertexProperty> face_properties;
  Index welded_vertices = 0;  ///< STL only: corners merged because positions were equal
  std::string format;         ///< e.g. "obj", "off", "ply-binary-le", "stl-ascii", "xyz"
  bool has_faces() const { return !triangles.empty(); }
};

}  // namespace ifem::io
