// One entry point from a face list to an intrinsic Delaunay triangulation, choosing the path:
// the manifold Δ-complex when it can represent the input with non-negative cotan weights, the
// tufted cover (Sharp & Crane 2020) otherwise. solvers::prepare_surface() builds on it (and adds
// point clouds and refinement); library users, the CLI and the tests share both.
#pragma once

#include <string>
#include <vector>

#include "intrinsic/core/triangulation.h"
#include "intrinsic/surface/face_analysis.h"
#include "intrinsic/surface/tufted_cover.h"

namespace ifem::intrinsic {

/// Which representation carries the surface.
enum class SurfacePath {
  kManifold,    ///< the input's own faces glued into a Δ-complex (edge-manifold, orientable)
  kTufted,      ///< the tufted cover of the faces (any triangle soup; no boundary of its own)
  kPointCloud,  ///< the tufted cover of kNN local triangulations (solvers::prepare_surface)
};

/// Why that path was taken.
enum class PathReason {
  kEdgeManifoldOrientable,   ///< manifold: every edge has ≤ 2 faces and the gluing orients
  kTuftedRequested,          ///< tufted: asked for (SurfaceOptions::force_tufted)
  kNonmanifoldEdges,         ///< tufted: an edge has 3 or more faces
  kNonOrientable,            ///< tufted: no consistent orientation exists (Moebius-like loop)
  kNegativeBoundaryWeights,  ///< tufted: boundary edges opposite obtuse angles would keep
                             ///< negative cotan weights on the manifold path
  kNoFaces,                  ///< point cloud: the input has no faces
  kPointCloudRequested,      ///< point cloud: asked for although the input has faces
};

/// "manifold", "tufted" or "pointcloud".
const char* to_string(SurfacePath path);
/// A short phrase for a reason ("nonmanifold edges", ...), for messages and reports.
const char* to_string(PathReason reason);

/// Options of build_surface().
struct SurfaceOptions {
  /// Relative mollification margin (IntrinsicTriangulation::mollify), ≥ 0.
  double mollify_relative_epsilon = kDefaultMollifyEpsilon;
  bool intrinsic_delaunay = true;  ///< flip to the intrinsic Delaunay triangulation
  bool force_tufted = false;       ///< take the tufted cover even when not needed
  /// @throws InvalidInput if the margin is negative or not finite
  void validate() const;
};

/// The triangulation and everything that was chosen, repaired and counted on the way.
struct SurfaceTriangulation {
  IntrinsicTriangulation tri;
  SurfacePath path = SurfacePath::kManifold;
  PathReason reason = PathReason::kEdgeManifoldOrientable;
  /// The reason in words with its details (counts, the first nonmanifold edge), for people:
  /// code decides on `reason`, never on this text.
  std::string reason_detail;
  FaceListStats stats;       ///< the face list's combinatorics (analyze_faces)
  BuildReport build;         ///< manifold path (dropped / reoriented faces, face origin)
  TuftedCoverReport tufted;  ///< tufted path
  MollifyReport mollify;
  FlipReport flips;
  /// Vertices on the input's boundary (an edge with one face), #V. The tufted cover has no
  /// boundary of its own, so solvers that treat boundaries (heat method) read it from here.
  std::vector<char> boundary_vertex;
  double seconds_build = 0, seconds_flip = 0;
  const char* path_name() const { return to_string(path); }
};

/// Builds the intrinsic (Delaunay) triangulation of a face list over vertex positions.
///
/// Path: manifold when every edge has at most two faces and the gluing is orientable, and —
/// with intrinsic_delaunay — no boundary edge keeps a negative cotan weight after the flips
/// (a boundary edge opposite an obtuse angle cannot be flipped, and its weight would make an
/// off-diagonal entry of L positive). Otherwise the tufted cover, whose boundary edges are
/// glued front to back and so can be flipped: its Laplacian has non-negative weights always.
/// Vertices keep the input's ids and order on both paths.
/// @param faces #F triangles over vertex ids in [0, #V)
/// @param positions #V×3, finite
/// @throws InvalidInput on an index out of range, a non-finite coordinate or bad options
SurfaceTriangulation build_surface(const std::vector<Triangle>& faces, const Positions& positions,
                                   const SurfaceOptions& options = {});

/// Number of boundary edges of tri with a negative cotan weight (tolerance 1e-12 relative to
/// the largest weight).
Index negative_boundary_weights(const IntrinsicTriangulation& tri);

}  // namespace ifem::intrinsic
