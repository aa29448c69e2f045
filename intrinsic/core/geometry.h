// Geometry of an intrinsic triangulation from its edge lengths: face areas, corner angles,
// cotangents, vertex angle sums, angle defects, cotan weights and mean lengths. The formulas on
// three lengths that these use live in triangle_formulas.h, included here for every caller.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <numeric>
#include <vector>

#include "intrinsic/core/surface_point.h"
#include "intrinsic/core/triangle_formulas.h"
#include "intrinsic/core/triangulation.h"

namespace ifem::intrinsic {

/// Area of face f.
inline double face_area(const IntrinsicTriangulation& tri, Index f) {
  const Index h = 3 * f;
  return triangle_area(tri.halfedge_length(h), tri.halfedge_length(h + 1),
                       tri.halfedge_length(h + 2));
}

/// Interior angle of face(h) at tail(h) (between h and prev(h)).
inline double corner_angle(const IntrinsicTriangulation& tri, Index h) {
  using T = IntrinsicTriangulation;
  return opposite_angle(tri.halfedge_length(T::next(h)), tri.halfedge_length(h),
                        tri.halfedge_length(T::prev(h)));
}

/// Cotangent of the angle of face(h) opposite h (at the corner tail(prev(h))).
inline double halfedge_cotan(const IntrinsicTriangulation& tri, Index h) {
  using T = IntrinsicTriangulation;
  return opposite_cotan(tri.halfedge_length(h), tri.halfedge_length(T::next(h)),
                        tri.halfedge_length(T::prev(h)));
}

/// Sum of all face areas, divided by the triangulation's multiplicity (so a tufted cover
/// reports the area of the surface it covers).
double total_area(const IntrinsicTriangulation& tri);

/// Per-vertex sum of corner angles (#V; 0 on unreferenced vertices).
Eigen::VectorXd vertex_angle_sums(const IntrinsicTriangulation& tri);

/// Per-vertex angle defect 2π − Θ_v − π·b_v, where b_v counts boundary halfedges leaving v:
/// 2π − Θ inside, π − Θ on a manifold boundary vertex, and the right value at nonmanifold
/// (pinched) vertices too, so that Σ defects = 2π·χ with χ = V − E + F always holds.
Eigen::VectorXd angle_defects(const IntrinsicTriangulation& tri);

/// Per-edge cotan weight w_e = (cot α + cot β)/2 (one term on a boundary edge), #E.
Eigen::VectorXd cotan_weights(const IntrinsicTriangulation& tri);

// ===== Mean lengths (the two "h"s) =====
//
// Two means, deliberately different: mean_edge_length() counts every edge of an intrinsic
// triangulation once (after flips or refinement it describes that triangulation);
// mean_side_length() counts every side of every face of a face list as given (an interior edge
// twice), from positions. The input mesh's h that the pipeline uses (heat time step, refinement
// target length, mollification margin) is robust_side_length(), the same mean with outliers
// left out (docs/decisions.md D-011, D-012, D-132).

/// Mean length over the edges of tri, each edge once (absolute, in the lengths' unit); 0 when
/// tri has no edge.
inline double mean_edge_length(const IntrinsicTriangulation& tri) {
  if (tri.n_edges() == 0) return 0.0;
  const std::vector<double>& l = tri.lengths();
  return std::accumulate(l.begin(), l.end(), 0.0) / double(l.size());
}

/// Mean Euclidean length of the faces' sides, each side of each face counted once as given (an
/// interior edge twice, a boundary edge once); absolute, in the positions' unit; 0 for no
/// faces. Defined in surface/face_analysis.cpp.
/// @param faces #F triangles over vertex ids in [0, positions.rows()) (not checked)
/// @param positions #V×3
double mean_side_length(const std::vector<Triangle>& faces, const Positions& positions);

/// robust_mean_length() of the faces' sides as given (each side of each face once), from
/// positions; the input mesh's h. Defined in surface/face_analysis.cpp.
double robust_side_length(const std::vector<Triangle>& faces, const Positions& positions);

/// The value at point p of `tri` (a face of tri and barycentric coordinates) of the function
/// linear in each face with per-vertex values x (#V of tri).
/// Precondition: p.face is a face of tri.
inline double interpolate_at(const IntrinsicTriangulation& tri, const Eigen::VectorXd& x,
                             const SurfacePoint& p) {
  double s = 0.0;
  for (int k = 0; k < 3; ++k) s += p.bary[k] * x[tri.tail(3 * p.face + k)];
  return s;
}

/// The 3D position of point p of `tri` whose vertices sit at the rows of `positions` (#V × 3),
/// linear in its face; the origin for a point without a face (kInvalidIndex).
inline Eigen::Vector3d point_position(const IntrinsicTriangulation& tri, const Positions& positions,
                                      const SurfacePoint& p) {
  Eigen::Vector3d out = Eigen::Vector3d::Zero();
  if (p.face == kInvalidIndex) return out;
  for (int k = 0; k < 3; ++k) {
    out += p.bary[k] * positions.row(tri.tail(3 * p.face + k)).transpose();
  }
  return out;
}

/// The outgoing halfedges h_0, h_1, … of vertex v, counter-clockwise from vertex_halfedge(v)
/// (face(h_i) = (v, head(h_i), head(h_{i+1}))), when v's star is a disk: an interior vertex
/// with at least 3 faces, all distinct, no self-edge at v and no outer side glued to another
/// face of the star. Returns false otherwise (`spokes` then holds nothing useful).
bool vertex_star_is_disk(const IntrinsicTriangulation& tri, Index v, std::vector<Index>* spokes);

/// The star of a flat vertex laid out isometrically in the plane: the vertex at the origin,
/// ring vertex i (head(spokes[i])) at length(h_i)·(cos φ_i, sin φ_i), φ_0 = 0 and φ_{i+1} =
/// φ_i + the angle of face(h_i) at the vertex. `spokes` as vertex_star_is_disk() gives them.
/// One layout for every representation, so their moves agree bit for bit.
std::vector<Eigen::Vector2d> flat_star_layout(const IntrinsicTriangulation& tri,
                                              const std::vector<Index>& spokes);

/// Whether planar point p lies strictly inside the kernel of the star polygon `ring`
/// (counter-clockwise): every triangle (p, ring[i], ring[i+1]) has a height above its outer
/// side of more than min_relative_height × that side's length.
bool inside_star_kernel(const std::vector<Eigen::Vector2d>& ring, const Eigen::Vector2d& p,
                        double min_relative_height);

/// The star of an inserted interior vertex v laid out isometrically in the plane (v is flat,
/// Θ_v = 2π), as every representation of the correspondence moves it: `spokes` as
/// vertex_star_is_disk() (h_i counter-clockwise from vertex_halfedge(v), face(h_i) = (v,
/// ring[i], ring[i+1])), `ring` as flat_star_layout() (v at the origin, ring[0] along h_0).
/// Returns false, with both emptied, when v is an input vertex (v < n_input: the input's
/// vertices come first), out of range, or its star is not a disk (a boundary vertex's never
/// is; a self-edge at v, or an outer side glued to another face of the star).
bool inserted_vertex_star(const IntrinsicTriangulation& tri, Index v, Index n_input,
                          std::vector<Index>* spokes, std::vector<Eigen::Vector2d>* ring);

/// What moving inserted vertex v by `displacement` (in the layout of its star) comes to, the
/// checks every representation makes before it moves v: kRefused when v has no
/// inserted_vertex_star(), the displacement is not finite, or it does not end strictly inside
/// the star's kernel (inside_star_kernel() with min_relative_height); kStays for a zero
/// displacement; else kMoves. `spokes` and `ring` receive the star (when v has one).
enum class StarMove { kRefused, kStays, kMoves };
StarMove check_star_move(const IntrinsicTriangulation& tri, Index v, Index n_input,
                         const Eigen::Vector2d& displacement, double min_relative_height,
                         std::vector<Index>* spokes, std::vector<Eigen::Vector2d>* ring);

/// Euler characteristic V − E + F (all vertices counted, unreferenced ones included).
inline long euler_characteristic(const IntrinsicTriangulation& tri) {
  return static_cast<long>(tri.n_vertices()) - tri.n_edges() + tri.n_faces();
}

}  // namespace ifem::intrinsic
