// summarize_mesh(): the figures of `ifem info` and ifem.mesh_info() (surface_summary.h).
#include "solvers/recipes/surface_summary.h"

#include <algorithm>

#include "intrinsic/core/errors.h"
#include "intrinsic/core/geometry.h"
#include "intrinsic/surface/tufted_cover.h"

namespace ifem::solvers {

namespace {

// Smallest and largest corner angle (degrees) and the non-Delaunay edge count of tri.
void angle_figures(const intrinsic::IntrinsicTriangulation& tri, MeshSummary* m) {
  double lo = 1e300, hi = 0.0;
  for (Index h = 0; h < tri.n_halfedges(); ++h) {
    const double t = intrinsic::corner_angle(tri, h);
    lo = std::min(lo, t);
    hi = std::max(hi, t);
  }
  Index non_delaunay = 0;
  for (Index e = 0; e < tri.n_edges(); ++e) non_delaunay += !tri.is_delaunay(e);
  const double deg = 180.0 / intrinsic::kPi;
  m->min_angle_deg = tri.n_halfedges() ? lo * deg : 0.0;
  m->max_angle_deg = hi * deg;
  m->non_delaunay_share = tri.n_edges() ? double(non_delaunay) / tri.n_edges() : 0.0;
}

}  // namespace

MeshSummary summarize_mesh(const PreparedSurface& s) {
  if (s.path == intrinsic::SurfacePath::kPointCloud) {
    throw InvalidInput("summarize_mesh: a point cloud has no mesh summary (see its cloud report)");
  }
  const intrinsic::FaceListStats& st = s.stats;
  MeshSummary m;
  m.vertices = s.tri.n_vertices();
  m.edges = st.edges;
  m.faces = s.tri.n_faces() / s.tri.multiplicity();
  m.polygons = s.input.n_polygons;
  m.unreferenced_vertices = st.unreferenced_vertices;
  m.boundary_edges = st.boundary_edges;
  m.boundary_loops = st.boundary_loops;
  m.components = st.components;
  m.euler_characteristic = static_cast<long>(st.vertices - st.unreferenced_vertices) - st.edges +
                           (st.faces - st.degenerate_faces);
  const bool orientable = st.nonmanifold_edges == 0 && st.nonmanifold_vertices == 0 &&
                          s.reason != intrinsic::PathReason::kNonOrientable;
  const long genus2 = 2L * st.components - m.euler_characteristic - st.boundary_loops;
  if (orientable && genus2 >= 0 && genus2 % 2 == 0) m.genus = genus2 / 2;
  m.nonmanifold_edges = st.nonmanifold_edges;
  m.nonmanifold_vertices = st.nonmanifold_vertices;
  m.dropped_degenerate_faces = s.build.dropped_faces;
  m.duplicate_faces = st.duplicate_faces;
  m.reoriented_faces = s.build.reoriented_faces;
  // angles of the input as given: its own triangles (the cover has them twice)
  angle_figures(
      s.path == intrinsic::SurfacePath::kManifold
          ? intrinsic::IntrinsicTriangulation::from_positions(s.input.triangles, s.input.positions)
          : intrinsic::tufted_cover(s.input.triangles, s.input.positions),
      &m);
  m.flips_to_idt = s.flips.flips;
  m.mollify_delta = s.mollify.delta;
  m.mollify_epsilon = s.mollify.epsilon;
  m.faces_below_margin = s.mollify.faces_below_margin;
  return m;
}

}  // namespace ifem::solvers
