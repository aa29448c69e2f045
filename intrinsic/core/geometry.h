// Geometry of an intrinsic triangulation from edge lengths alone: triangle areas (stable
// Heron), corner angles, cotangents, vertex angle sums and angle defects.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <numeric>
#include <vector>

#include "intrinsic/core/triangulation.h"

namespace ifem::intrinsic {

inline constexpr double kPi = 3.14159265358979323846;

/// The power of two nearest above x's magnitude (2^e with x < 2^e ≤ 2x for x > 0; 1 for x = 0 or
/// a non-finite x). Dividing lengths by it is exact, so formulas on the scaled lengths give the
/// same bits at every scale 2^k and never over- or underflow in squaring.
inline double power_of_two_scale(double x) {
  if (!(x > 0.0) || !std::isfinite(x)) return 1.0;
  int e = 0;
  std::frexp(x, &e);  // x = m·2^e, m in [0.5, 1)
  return std::ldexp(1.0, e);
}

/// The divisor that brings lengths up to m into a range where squares and fourth powers cannot
/// over- or underflow: 1 when m is already in [2^-200, 2^200] (no work on the hot paths),
/// power_of_two_scale(m) otherwise. Either way the result is a power of two, so dividing by it
/// is exact and the formulas give the same bits, up to the power of two, at every scale.
inline double length_normalizer(double m) {
  constexpr double kLow = 0x1p-200, kHigh = 0x1p200;
  return m >= kLow && m <= kHigh ? 1.0 : power_of_two_scale(m);
}

/// Euclidean distance between two points given as xyz triples, for any finite coordinates: the
/// plain formula when its sum of squares is comfortably inside the double range, else the same
/// on coordinates scaled by a power of two (exact), so neither the difference nor its square
/// over- or underflows. Scaling both points by 2^k scales the result by exactly 2^k.
inline double side_length(const double* pa, const double* pb) {
  const double dx = pa[0] - pb[0], dy = pa[1] - pb[1], dz = pa[2] - pb[2];
  const double q = dx * dx + dy * dy + dz * dz;
  if (q > 1e-290 && q < 1e290) return std::sqrt(q);
  double m = 0.0;
  for (int k = 0; k < 3; ++k) m = std::max({m, std::abs(pa[k]), std::abs(pb[k])});
  const double s = power_of_two_scale(m);
  const double ex = pa[0] / s - pb[0] / s, ey = pa[1] / s - pb[1] / s, ez = pa[2] / s - pb[2] / s;
  return std::sqrt(ex * ex + ey * ey + ez * ez) * s;
}

/// Area of a triangle with side lengths a, b, c by Kahan's stable Heron formula, evaluated on
/// the lengths scaled by a power of two so that squaring cannot overflow or underflow (the result
/// overflows to inf, or underflows to 0, only when the area itself is not representable); 0 when
/// the lengths violate the triangle inequality (never NaN for finite non-negative input).
inline double triangle_area(double a, double b, double c) {
  // sort so that a >= b >= c
  if (a < b) std::swap(a, b);
  if (a < c) std::swap(a, c);
  if (b < c) std::swap(b, c);
  const double s = length_normalizer(a);
  if (s != 1.0) a /= s, b /= s, c /= s;
  const double p = (a + (b + c)) * (c - (a - b)) * (c + (a - b)) * (a + (b - c));
  return p > 0.0 ? (0.25 * std::sqrt(p)) * s * s : 0.0;
}

/// Angle opposite side a in a triangle with sides a, b, c, in [0, π]; atan2 form, accurate for
/// needles and caps alike, and the same at every scale (lengths scaled by a power of two).
inline double opposite_angle(double a, double b, double c) {
  const double s = length_normalizer(std::max({a, b, c}));
  if (s != 1.0) a /= s, b /= s, c /= s;
  return std::atan2(4.0 * triangle_area(a, b, c), b * b + c * c - a * a);
}

/// Cotangent of the angle opposite side a (dimensionless: the same at every scale); ±inf for a
/// degenerate triangle.
inline double opposite_cotan(double a, double b, double c) {
  const double s = length_normalizer(std::max({a, b, c}));
  if (s != 1.0) a /= s, b /= s, c /= s;
  return (b * b + c * c - a * a) / (4.0 * triangle_area(a, b, c));
}

/// The z component of the cross product of two plane vectors: > 0 when b turns
/// counter-clockwise from a.
inline double cross2(const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return a.x() * b.y() - a.y() * b.x();
}

/// The planar layout of a triangle from its lengths: with its base from (0, 0) to (base, 0),
/// the third corner at distance `from_end` from (base, 0) and `from_origin` from (0, 0), on the
/// side y ≥ 0 (y from the stable area, never NaN). Precondition: base > 0.
inline Eigen::Vector2d triangle_apex(double base, double from_end, double from_origin) {
  const double s = length_normalizer(std::max({base, from_end, from_origin}));
  if (s != 1.0) base /= s, from_end /= s, from_origin /= s;
  return Eigen::Vector2d(
             (base * base + from_origin * from_origin - from_end * from_end) / (2.0 * base),
             2.0 * triangle_area(base, from_end, from_origin) / base) *
         s;
}

/// Area of the equilateral triangle of side l (the area bound that asks for edges of about l).
inline double equilateral_area(double l) { return 0.4330127018922193 * l * l; }  // √3/4 l²

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
// clipped (docs/decisions.md, "Heat step length" and "Robust length scale").

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

/// A length scale of a set of lengths that a few outliers cannot move: the mean of the lengths,
/// each clipped to at most kOutlierClip × their 99th percentile. Equal to the mean unless a
/// length exceeds 4× the 99th percentile (true of every corpus mesh, CAD meshes whose sides span
/// 200× included); the sides of a far outlier vertex (a spike 1e9 long on a 35-unit model, fewer
/// than 1% of the sides) then add at most kOutlierClip × p99 each to the sum.
/// The heat method's time step, the refinement resolution's h and the mollification margin use
/// it (docs/decisions.md, "Robust length scale"). 0 for an empty set. O(n).
double robust_mean_length(std::vector<double> lengths);
inline constexpr double kOutlierClip = 4.0;

/// robust_mean_length() of the faces' sides as given (each side of each face once), from
/// positions; the input mesh's h. Defined in surface/face_analysis.cpp (robust_mean_length in
/// core/triangulation.cpp).
double robust_side_length(const std::vector<Triangle>& faces, const Positions& positions);

/// Euler characteristic V − E + F (all vertices counted, unreferenced ones included).
inline long euler_characteristic(const IntrinsicTriangulation& tri) {
  return static_cast<long>(tri.n_vertices()) - tri.n_edges() + tri.n_faces();
}

}  // namespace ifem::intrinsic
