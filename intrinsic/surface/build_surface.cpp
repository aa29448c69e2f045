#include "intrinsic/surface/build_surface.h"

#include <chrono>

#include "intrinsic/core/geometry.h"
#include "intrinsic/surface/face_analysis.h"

namespace ifem::intrinsic {
namespace {

double now() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

std::string plural(Index n, const char* what) {
  return std::to_string(n) + " " + what + (n == 1 ? "" : "s");
}

}  // namespace

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
  SurfaceTriangulation s;
  const Index nv = checked_index(static_cast<std::size_t>(positions.rows()), "build_surface");
  double t0 = now();
  const FaceListStats st = analyze_faces(faces, nv);
  s.boundary_vertex.assign(nv, 0);
  if (st.boundary_edges > 0) {
    // sides whose vertex pair occurs once among all sides
    std::vector<std::pair<std::uint64_t, Index>> keys;
    keys.reserve(3 * faces.size());
    for (const Triangle& t : faces) {
      if (t[0] == t[1] || t[1] == t[2] || t[2] == t[0]) continue;
      for (int k = 0; k < 3; ++k) {
        const std::uint64_t a = std::min(t[k], t[(k + 1) % 3]), b = std::max(t[k], t[(k + 1) % 3]);
        keys.emplace_back(a << 32 | b, 0);
      }
    }
    std::sort(keys.begin(), keys.end());
    for (std::size_t i = 0; i < keys.size();) {
      std::size_t j = i + 1;
      while (j < keys.size() && keys[j].first == keys[i].first) ++j;
      if (j - i == 1) {
        s.boundary_vertex[keys[i].first >> 32] = 1;
        s.boundary_vertex[keys[i].first & 0xffffffffu] = 1;
      }
      i = j;
    }
  }

  std::string why_tufted;
  if (options.force_tufted) {
    why_tufted = "tufted cover requested";
  } else if (!st.edge_manifold()) {
    why_tufted = plural(st.nonmanifold_edges, "nonmanifold edge") + ", first (" +
                 std::to_string(st.first_nonmanifold_edge[0]) + "," +
                 std::to_string(st.first_nonmanifold_edge[1]) + ")";
  } else {
    try {
      s.tri = IntrinsicTriangulation::from_positions(faces, positions, &s.build);
      s.path = SurfacePath::kManifold;
      s.reason = "edge-manifold and orientable";
      if (s.build.reoriented_faces) {
        s.reason += " (" + plural(s.build.reoriented_faces, "face") + " reoriented)";
      }
      s.mollify = s.tri.mollify(options.mollify_relative_epsilon);
      s.seconds_build = now() - t0;
      if (options.intrinsic_delaunay) {
        t0 = now();
        s.flips = s.tri.flip_to_delaunay();
        s.seconds_flip = now() - t0;
        const Index bad = negative_boundary_weights(s.tri);
        if (bad == 0) return s;
        why_tufted = plural(bad, "boundary edge") +
                     " opposite obtuse angles keep negative cotan weights on the manifold path";
      } else {
        return s;
      }
    } catch (const NonManifoldInput& e) {
      const std::string what = e.what();
      why_tufted =
          what.find("non-orientable") != std::string::npos ? "non-orientable gluing" : what;
    }
  }
  t0 = now();
  s.tri = tufted_cover(faces, positions, &s.tufted);
  s.path = SurfacePath::kTufted;
  s.reason = why_tufted;
  s.build = BuildReport{};
  s.build.input_faces = s.tufted.input_faces;
  s.build.dropped_faces = s.tufted.dropped_faces;
  s.build.unreferenced_vertices = s.tufted.unreferenced_vertices;
  s.build.face_origin = s.tufted.parent_face;
  s.mollify = s.tri.mollify(options.mollify_relative_epsilon);
  s.seconds_build += now() - t0;
  s.flips = FlipReport{};
  if (options.intrinsic_delaunay) {
    t0 = now();
    s.flips = s.tri.flip_to_delaunay();
    s.seconds_flip += now() - t0;
  }
  return s;
}

}  // namespace ifem::intrinsic
