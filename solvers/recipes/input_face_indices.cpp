// A field's singularities on the input's own faces (tangent_fields.h, input_face_indices()).
//
// The field lives on the vertices of s.tri (intrinsic Delaunay, refined, or with curves), whose
// angular coordinates differ from those of the input triangulation at a vertex whose reference
// halfedge was flipped away. The signposts know the direction of every input halfedge in the
// same angular coordinate as the intrinsic halfedges at its tail, so each input vertex's value
// can be turned into the input triangulation's own coordinate, and solvers::face_indices() then
// measures the index around each input face (turning along its three sides, which are geodesics
// of the same surface, relative to the input triangulation's transport, plus its share of
// curvature). The plain intrinsic Delaunay path keeps no signposts; they are rebuilt here with
// the same construction and flips, which gives back s.tri exactly (checked, bit for bit).
// Refined with integer coordinates, the same angles come from the integers.
#include <complex>
#include <optional>

#include "intrinsic/core/errors.h"
#include "solvers/recipes/tangent_fields.h"

namespace ifem::solvers {

namespace {

using T = intrinsic::IntrinsicTriangulation;

bool same_triangulation(const T& a, const T& b) {
  return a.n_vertices() == b.n_vertices() && a.tails() == b.tails() && a.twins() == b.twins() &&
         a.lengths() == b.lengths();
}

// The input's signposts flipped like s.tri (prepare_mesh's construction and flips), or nullopt
// when they do not give back s.tri (then the input edges' directions in s.tri are unknown).
std::optional<intrinsic::SignpostTriangulation> rebuilt_signposts(const PreparedSurface& s) {
  try {
    std::optional<intrinsic::SignpostTriangulation> st;
    st.emplace(s.input.triangles, s.input.positions, s.mollify_relative_epsilon);
    if (s.flips.flips > 0) st->flip_to_delaunay();
    if (same_triangulation(st->intrinsic(), s.tri)) return st;
  } catch (const Error&) {
  }
  return std::nullopt;
}

// The indices on the input's faces (s.input.triangles' order) of u given on s.tri, where
// turn(r, g) is the angle at their common tail from input halfedge g (of `input`)
// counter-clockwise to s.tri's halfedge r, in radians (modulo the vertex's angle sum inside):
// u is turned back by it into the input triangulation's angular coordinate at each vertex.
template <class Turn>
Eigen::VectorXi indices_through(const PreparedSurface& s, const T& input,
                                const std::vector<Index>& face_origin,
                                const fem::TangentFrames& frames, const Eigen::VectorXcd& u,
                                int symmetry, Turn turn) {
  const Index nv = input.n_vertices();
  Eigen::VectorXcd u_input = Eigen::VectorXcd::Zero(nv);
  for (Index v = 0; v < nv; ++v) {
    const Index g = input.vertex_halfedge(v), r = s.tri.vertex_halfedge(v);
    if (g == kInvalidIndex || r == kInvalidIndex) continue;
    const double offset = -frames.angle_scale[v] * turn(r, g);
    u_input[v] = u[v] * std::polar(1.0, -symmetry * offset);
  }
  const Eigen::VectorXi index = face_indices(input, fem::tangent_frames(input), u_input, symmetry);
  Eigen::VectorXi out = Eigen::VectorXi::Zero(static_cast<Eigen::Index>(s.input.triangles.size()));
  for (Index f = 0; f < input.n_faces(); ++f) out[face_origin[f]] += index[f];
  return out;
}

}  // namespace

Eigen::VectorXi input_face_indices(const PreparedSurface& s, const fem::TangentFrames& frames,
                                   const Eigen::VectorXcd& u, int symmetry) {
  if (u.size() != s.tri.n_vertices() || frames.angle_scale.size() != s.tri.n_vertices()) {
    throw InvalidInput("input_face_indices: " + std::to_string(u.size()) + " values and " +
                       std::to_string(frames.angle_scale.size()) + " frames for " +
                       std::to_string(s.tri.n_vertices()) + " vertices");
  }
  if (s.path != intrinsic::SurfacePath::kManifold || !s.input.has_faces()) return {};
  if (s.integer && same_triangulation(s.integer->intrinsic(), s.tri)) {
    // refined with integer coordinates (D-330): the turn from the integers (the input corners
    // between the two halfedges plus the angle inside a wedge)
    const intrinsic::NormalCoordinateTriangulation& nc = *s.integer;
    return indices_through(s, nc.input(), nc.input_face_origin(), frames, u, symmetry,
                           [&](Index r, Index g) { return nc.angle_from_input_halfedge(r, g); });
  }
  std::optional<intrinsic::SignpostTriangulation> built;
  const intrinsic::SignpostTriangulation* st = s.signposts ? &*s.signposts : nullptr;
  if (st == nullptr || !same_triangulation(st->intrinsic(), s.tri)) {
    built = rebuilt_signposts(s);
    if (!built) return {};
    st = &*built;
  }
  // the signposts: both directions in s.tri's angular coordinate at the vertex
  return indices_through(s, st->input(), st->input_face_origin(), frames, u, symmetry,
                         [&](Index r, Index g) {
                           return st->halfedge_direction(r) - st->input_halfedge_direction(g);
                         });
}

}  // namespace ifem::solvers
