// What an input is made of and what preparing it did: the figures `ifem info` prints and
// ifem.mesh_info() returns, computed once here for both.
#pragma once

#include <cstddef>
#include <optional>

#include "solvers/recipes/pipeline.h"

namespace ifem::solvers {

/// Counts, topology, defects and angles of a mesh input (not a point cloud), with what
/// preparing it did. Angles and the non-Delaunay share are the input's own triangles' (before
/// mollification and flips; on the tufted path, of the cover, which has the input's faces twice).
struct MeshSummary {
  Index vertices = 0;               ///< the input's, unreferenced included
  Index edges = 0;                  ///< distinct vertex pairs of the face list
  Index faces = 0;                  ///< triangles kept (the cover's faces / its multiplicity)
  Index polygons = 0;               ///< polygons given (n-gons triangulated)
  Index unreferenced_vertices = 0;  ///< vertices no face uses
  Index boundary_edges = 0;         ///< vertex pairs with one face
  Index boundary_loops = 0;         ///< components of the boundary-edge graph
  Index components = 0;             ///< connected components of referenced vertices
  long euler_characteristic = 0;    ///< V − E + F of the face list (degenerate faces dropped)
  /// Genus of an orientable surface without nonmanifold edges or vertices; empty otherwise.
  std::optional<long> genus;
  Index nonmanifold_edges = 0;         ///< vertex pairs with 3+ faces
  Index nonmanifold_vertices = 0;      ///< vertices with 2+ edge-connected fans
  Index dropped_degenerate_faces = 0;  ///< faces that repeat a vertex (dropped)
  Index duplicate_faces = 0;           ///< faces on the vertex set of an earlier face
  Index reoriented_faces = 0;          ///< faces whose orientation was repaired
  double min_angle_deg = 0.0;          ///< smallest corner angle of the input, degrees
  double max_angle_deg = 0.0;          ///< largest corner angle of the input, degrees
  double non_delaunay_share = 0.0;     ///< share of the input's edges that are not Delaunay
  std::size_t flips_to_idt = 0;        ///< flips to the intrinsic Delaunay triangulation
  double mollify_delta = 0.0;          ///< length added to every edge by mollification
  double mollify_epsilon = 0.0;        ///< the mollification margin, absolute
  Index faces_below_margin = 0;        ///< faces that violated the margin before mollification
};

/// The summary of a prepared mesh input.
/// @throws InvalidInput if s took the point-cloud path (its figures are s.cloud's)
MeshSummary summarize_mesh(const PreparedSurface& s);

}  // namespace ifem::solvers
