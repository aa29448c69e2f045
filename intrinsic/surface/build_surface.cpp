#include "intrinsic/surface/build_surface.h"

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "intrinsic/core/errors.h"
#include "intrinsic/core/geometry.h"
#include "intrinsic/core/timer.h"

namespace ifem::intrinsic {
namespace {

std::string plural(Index n, const char* what) {
  return std::to_string(n) + " " + what + (n == 1 ? "" : "s");
}

// The tufted cover of the faces, mollified and (optionally) flipped, into s.
void take_tufted_path(const std::vector<Triangle>& faces, const Positions& positions,
                      const SurfaceOptions& options, SurfaceTriangulation& s) {
  Stopwatch watch;
  s.tri = tufted_cover(faces, positions, &s.tufted);
  s.path = SurfacePath::kTufted;
  s.build = BuildReport{};
  s.build.input_faces = s.tufted.input_faces;
  s.build.dropped_faces = s.tufted.dropped_faces;
  s.build.unreferenced_vertices = s.tufted.unreferenced_vertices;
  s.build.face_origin = s.tufted.parent_face;
  s.mollify = s.tri.mollify(options.mollify_relative_epsilon);
  s.seconds_build += watch.restart();
  s.flips = FlipReport{};
  if (options.intrinsic_delaunay) {
    s.flips = s.tri.flip_to_delaunay();
    s.seconds_flip += watch.seconds();
  }
}

// Tries the manifold path: true when it represents the input (s filled), false with s.reason /
// s.reason_detail saying why not. Non-orientability is only found while gluing: the typed
// NonOrientableInput of from_positions() is that answer (edge-manifoldness is checked first,
// from the face statistics, so no other NonManifoldInput can arrive here).
bool try_manifold_path(const std::vector<Triangle>& faces, const Positions& positions,
                       const SurfaceOptions& options, SurfaceTriangulation& s) {
  Stopwatch watch;
  try {
    s.tri = IntrinsicTriangulation::from_positions(faces, positions, &s.build);
  } catch (const NonOrientableInput& e) {
    s.reason = PathReason::kNonOrientable;
    s.reason_detail = e.what();
    return false;
  }
  s.path = SurfacePath::kManifold;
  s.reason = PathReason::kEdgeManifoldOrientable;
  s.reason_detail = to_string(s.reason);
  if (s.build.reoriented_faces) {
    s.reason_detail += " (" + plural(s.build.reoriented_faces, "face") + " reoriented)";
  }
  s.mollify = s.tri.mollify(options.mollify_relative_epsilon);
  s.seconds_build = watch.restart();
  if (!options.intrinsic_delaunay) return true;
  s.flips = s.tri.flip_to_delaunay();
  s.seconds_flip = watch.seconds();
  const Index bad = negative_boundary_weights(s.tri);
  if (bad == 0) return true;
  s.reason = PathReason::kNegativeBoundaryWeights;
  s.reason_detail = plural(bad, "boundary edge") +
                    " opposite obtuse angles keep negative cotan weights on the manifold path";
  return false;
}

}  // namespace

const char* to_string(SurfacePath path) {
  switch (path) {
    case SurfacePath::kManifold:
      return "manifold";
    case SurfacePath::kTufted:
      return "tufted";
    case SurfacePath::kPointCloud:
      return "pointcloud";
  }
  return "?";
}

const char* to_string(PathReason reason) {
  switch (reason) {
    case PathReason::kEdgeManifoldOrientable:
      return "edge-manifold and orientable";
    case PathReason::kTuftedRequested:
      return "tufted cover requested";
    case PathReason::kNonmanifoldEdges:
      return "nonmanifold edges";
    case PathReason::kNonOrientable:
      return "non-orientable gluing";
    case PathReason::kNegativeBoundaryWeights:
      return "boundary edges opposite obtuse angles keep negative cotan weights";
    case PathReason::kNoFaces:
      return "no faces: point cloud";
    case PathReason::kPointCloudRequested:
      return "point cloud requested";
  }
  return "?";
}

void SurfaceOptions::validate() const {
  if (!(mollify_relative_epsilon >= 0.0) || !std::isfinite(mollify_relative_epsilon)) {
    throw InvalidInput("SurfaceOptions: mollify_relative_epsilon must be finite and ≥ 0, got " +
                       std::to_string(mollify_relative_epsilon));
  }
}

Index negative_boundary_weights(const IntrinsicTriangulation& tri) {
  if (!tri.has_boundary()) return 0;
  const Eigen::VectorXd w = cotan_weights(tri);
  const double tol = 1e-12 * w.cwiseAbs().maxCoeff();
  Index n = 0;
  for (Index e = 0; e < tri.n_edges(); ++e) n += tri.is_boundary_edge(e) && w[e] < -tol;
  return n;
}

SurfaceTriangulation build_surface(const std::vector<Triangle>& faces, const Positions& positions,
                                   const SurfaceOptions& options) {
  options.validate();
  SurfaceTriangulation s;
  const Index nv = checked_index(static_cast<std::size_t>(positions.rows()), "build_surface");
  s.stats = analyze_faces(faces, nv);
  s.boundary_vertex =
      s.stats.boundary_edges > 0 ? boundary_vertex_mask(faces, nv) : std::vector<char>(nv, 0);
  if (options.force_tufted) {
    s.reason = PathReason::kTuftedRequested;
    s.reason_detail = to_string(s.reason);
  } else if (!s.stats.edge_manifold()) {
    s.reason = PathReason::kNonmanifoldEdges;
    s.reason_detail = plural(s.stats.nonmanifold_edges, "nonmanifold edge") + ", first (" +
                      std::to_string(s.stats.first_nonmanifold_edge[0]) + "," +
                      std::to_string(s.stats.first_nonmanifold_edge[1]) + ")";
  } else if (try_manifold_path(faces, positions, options, s)) {
    return s;
  }
  take_tufted_path(faces, positions, options, s);
  return s;
}

}  // namespace ifem::intrinsic
