// The tufted cover of an arbitrary triangle soup (Sharp & Crane 2020, "A Laplacian for
// Nonmanifold Triangle Meshes", §4.2): every face doubled (front/back copies), the copies glued
// cyclically around each input edge, giving an edge-manifold closed Δ-complex over the same
// vertices. Nonmanifold meshes and point clouds both go through it.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "intrinsic/core/triangulation.h"

namespace ifem::intrinsic {

/// What tufted_cover() found and repaired, counted.
struct TuftedCoverReport {
  Index input_faces = 0;            ///< faces given
  Index dropped_faces = 0;          ///< faces that repeat a vertex index (dropped)
  Index edges = 0;                  ///< distinct input edges (unordered vertex pairs)
  Index boundary_edges = 0;         ///< input edges with one face (zipped front to back)
  Index nonmanifold_edges = 0;      ///< input edges with 3+ faces
  Index max_faces_per_edge = 0;     ///< largest number of faces around one input edge
  Index unreferenced_vertices = 0;  ///< vertices no kept face uses: zero row in L, zero mass
                                    ///< (solvers report +inf distance / 0 value there)
  Index first_nonmanifold_edge[2] = {kInvalidIndex, kInvalidIndex};  ///< (lo, hi), for messages
  /// For each cover face, the input face it copies: cover faces 2k (front, corners as given)
  /// and 2k+1 (back, corners reversed) both come from kept input face parent_face[2k].
  std::vector<Index> parent_face;
};

/// Tufted cover of a face list over vertex positions. Accepts anything: duplicate faces,
/// nonmanifold edges and vertices, inconsistent orientation, non-orientable meshes, zero-area
/// faces (mollify() the result), coincident and unreferenced vertices (they keep their ids).
/// Faces that repeat a vertex index are dropped and counted.
///
/// Around an edge with 3+ faces, the faces are ordered by the angle of their third vertex about
/// the edge axis (ties by opposite vertex id, then by input face id among identical faces), so
/// the result does not depend on the input's face order beyond relabelling (the operators
/// agree to rounding). With 1 face the front and back copies are zipped; with 2 faces the
/// cover of a manifold mesh is two copies of it (or its orientation double cover).
///
/// The result has multiplicity 2: fem operators divide by it, so on an edge-manifold mesh the
/// cotan Laplacian and mass of the cover equal those of the mesh itself.
/// @param faces #F triangles over vertex ids in [0, positions.rows())
/// @param positions #V×3, finite
/// @param input_multiplicity how many times the faces cover each point of the surface (≥ 1: 1
///        for a mesh, 3 for the union of point-cloud local triangulations, where each triangle
///        shows up in the neighbourhoods of its three corners); the result has multiplicity
///        2 × input_multiplicity, so operators average over the copies
/// @param[out] report optional counts
/// @throws InvalidInput on an index out of range, a non-finite coordinate or
///         input_multiplicity < 1
IntrinsicTriangulation tufted_cover(const std::vector<Triangle>& faces, const Positions& positions,
                                    int input_multiplicity, TuftedCoverReport* report = nullptr);

/// tufted_cover() of a mesh (input_multiplicity 1).
IntrinsicTriangulation tufted_cover(const std::vector<Triangle>& faces, const Positions& positions,
                                    TuftedCoverReport* report = nullptr);

/// Tufted cover from per-side lengths (side_lengths(f, s) = length of the side from corner s to
/// corner s+1 of face f). Without positions there is no angle about an edge: around an edge
/// with 3+ faces the faces are ordered by opposite vertex id, then by their side lengths, then
/// by input face id (still independent of face order up to relabelling).
/// @throws InvalidInput on an index out of range, a negative or non-finite length, or sides of
///         one edge whose lengths disagree (1e-12 relative)
IntrinsicTriangulation tufted_cover(const std::vector<Triangle>& faces, Index n_vertices,
                                    const Eigen::MatrixX3d& side_lengths, int input_multiplicity,
                                    TuftedCoverReport* report = nullptr);

/// Same with input_multiplicity 1.
IntrinsicTriangulation tufted_cover(const std::vector<Triangle>& faces, Index n_vertices,
                                    const Eigen::MatrixX3d& side_lengths,
                                    TuftedCoverReport* report = nullptr);

/// Deprecated argument order (report before input_multiplicity; every function that returns a
/// value takes its report last, docs/decisions.md D-001): the implementation until the definitions
/// in tufted_cover.cpp move to the signatures above. Call those instead.
IntrinsicTriangulation tufted_cover(const std::vector<Triangle>& faces, const Positions& positions,
                                    TuftedCoverReport* report, int input_multiplicity);
/// Deprecated argument order, as above.
IntrinsicTriangulation tufted_cover(const std::vector<Triangle>& faces, Index n_vertices,
                                    const Eigen::MatrixX3d& side_lengths, TuftedCoverReport* report,
                                    int input_multiplicity);

inline IntrinsicTriangulation tufted_cover(const std::vector<Triangle>& faces,
                                           const Positions& positions, int input_multiplicity,
                                           TuftedCoverReport* report) {
  return tufted_cover(faces, positions, report, input_multiplicity);
}
inline IntrinsicTriangulation tufted_cover(const std::vector<Triangle>& faces,
                                           const Positions& positions, TuftedCoverReport* report) {
  return tufted_cover(faces, positions, report, 1);
}
inline IntrinsicTriangulation tufted_cover(const std::vector<Triangle>& faces, Index n_vertices,
                                           const Eigen::MatrixX3d& side_lengths,
                                           int input_multiplicity, TuftedCoverReport* report) {
  return tufted_cover(faces, n_vertices, side_lengths, report, input_multiplicity);
}
inline IntrinsicTriangulation tufted_cover(const std::vector<Triangle>& faces, Index n_vertices,
                                           const Eigen::MatrixX3d& side_lengths,
                                           TuftedCoverReport* report) {
  return tufted_cover(faces, n_vertices, side_lengths, report, 1);
}

}  // namespace ifem::intrinsic
