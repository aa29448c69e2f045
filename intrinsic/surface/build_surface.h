// One entry point from a face list to an intrinsic Delaunay triangulation, choosing the path:
// the manifold Δ-complex when it can represent the input with non-negative cotan weights, the
// tufted cover (Sharp & Crane 2020) otherwise. Library users, the CLI and the tests share it.
#pragma once

#include <string>
#include <vector>

#include "intrinsic/core/triangulation.h"
#include "intrinsic/surface/tufted_cover.h"

namespace ifem::intrinsic {

enum class SurfacePath { kManifold, kTufted };

/// Options of build_surface(); defaults are what the CLI uses.
struct SurfaceOptions {
  double mollify_relative_epsilon = intrinsic::kDefaultMollifyEpsilon;  ///< see IntrinsicTriangulation::mollify
  bool intrinsic_delaunay = true;          ///< flip to the intrinsic Delaunay triangulation
  bool force_tufted = false;               ///< take the tufted cover even when not needed
};

/// The triangulation and everything that was chosen, repaired and counted on the way.
struct SurfaceTriangulation {
  IntrinsicTriangulation tri;
  SurfacePath path = SurfacePath::kManifold;
  std::string reason;        ///< why this path, in words
  BuildReport build;         ///< manifold path (dropped / reoriented faces, face origin)
  TuftedCoverReport tufted;  ///< tufted path
  MollifyReport mollify;
  FlipReport flips;
  /// Vertices on the input's boundary (an edge with one face), #V. The tufted cover has no
  /// boundary of its own, so solvers that treat boundaries (heat method) read it from here.
  std::vector<char> boundary_vertex;
  double seconds_build = 0, seconds_flip = 0;
  const char* path_name() const { return path == SurfacePath::kManifold ? "manifold" : "tufted"; }
};

/// Builds the intrinsic (Delaunay) triangulation of a face list over vertex positions.
///
/// Path: manifold when every edge has at most two faces and the gluing is orientable, and —
/// with intrinsic_delaunay — no boundary edge keeps a negative cotan weight after the flips
/// (a boundary edge opposite an obtuse angle cannot be flipped, and its weight would make an
/// off-diagonal entry of L positive). Otherwise the tufted cover, whose boundary edges are
/// glued front to back and so can be flipped: its Laplacian has non-negative weights always.
/// Vertices keep the input's ids and order on both paths.
/// @throws InvalidInput on an index out of range or a non-finite coordinate
SurfaceTriangulation build_surface(const std::vector<Triangle>& faces, const Positions& positions,
                                   const SurfaceOptions& options = {});

/// Number of boundary edges of tri with a negative cotan weight (tolerance 1e-12 relative to
/// the largest weight).
Index negative_boundary_weights(const IntrinsicTriangulation& tri);

}  // namespace ifem::intrinsic
