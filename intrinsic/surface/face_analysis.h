// Combinatorial statistics of a raw face list (before any triangulation is built), for
// reporting (`ifem info`) and for choosing between the manifold path and the tufted cover.
#pragma once

#include <vector>

#include "intrinsic/core/geometry.h"  // mean_side_length(), robust_side_length()
#include "intrinsic/core/types.h"

namespace ifem::intrinsic {

/// Counts over a face list. Edges are unordered vertex pairs; faces that repeat a vertex are
/// counted in `degenerate_faces` and otherwise ignored.
struct FaceListStats {
  Index vertices = 0;              ///< all vertices, unreferenced included
  Index faces = 0;                 ///< faces given
  Index degenerate_faces = 0;      ///< faces that repeat a vertex index
  Index duplicate_faces = 0;       ///< faces on the same vertex set as an earlier face
  Index edges = 0;                 ///< distinct vertex pairs
  Index boundary_edges = 0;        ///< pairs with one face
  Index nonmanifold_edges = 0;     ///< pairs with 3+ faces
  Index nonmanifold_vertices = 0;  ///< vertices whose faces form 2+ edge-connected fans
  Index inconsistent_edges = 0;    ///< 2-face pairs traversed twice in the same direction
  Index unreferenced_vertices = 0;
  Index components = 0;      ///< connected components of referenced vertices
  Index boundary_loops = 0;  ///< connected components of the boundary-edge graph
  Index first_nonmanifold_edge[2] = {kInvalidIndex, kInvalidIndex};  ///< for messages
  /// True when every edge has at most 2 faces: the manifold path can represent it (an
  /// orientation problem can still make it fall back to the tufted cover).
  bool edge_manifold() const { return nonmanifold_edges == 0; }
};

/// Computes the statistics in O(F log F).
FaceListStats analyze_faces(const std::vector<Triangle>& faces, Index n_vertices);

/// Per vertex (#V): 1 if the vertex is an end of a boundary edge (a vertex pair that exactly one
/// side of the non-degenerate faces joins), else 0. Precondition: ids in [0, n_vertices).
std::vector<char> boundary_vertex_mask(const std::vector<Triangle>& faces, Index n_vertices);

}  // namespace ifem::intrinsic
