// Formulas on the side lengths of one triangle, needing no triangulation: exact power-of-two
// rescaling, stable Heron area, opposite angle and cotangent, the planar layout of a triangle,
// and a length scale robust to outliers. The triangulation (core/triangulation.cpp) and the
// geometry of a whole triangulation (core/geometry.h) are built on them.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <vector>

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

/// The two arguments opposite_angle() hands to atan2 for the angle opposite side a: *y = 4 ×
/// area ≥ 0 and *x = b² + c² − a², on the lengths scaled by length_normalizer (so (x, y) points
/// at the angle: a sum of such angles is below π where the cross products say so, without
/// atan2). opposite_angle(a, b, c) is std::atan2(*y, *x), bit for bit.
inline void opposite_angle_args(double a, double b, double c, double* y, double* x) {
  const double s = length_normalizer(std::max({a, b, c}));
  if (s != 1.0) a /= s, b /= s, c /= s;
  *y = 4.0 * triangle_area(a, b, c);
  *x = b * b + c * c - a * a;
}

/// Angle opposite side a in a triangle with sides a, b, c, in [0, π]; atan2 form, accurate for
/// needles and caps alike, and the same at every scale (lengths scaled by a power of two).
inline double opposite_angle(double a, double b, double c) {
  double y = 0.0, x = 0.0;
  opposite_angle_args(a, b, c, &y, &x);
  return std::atan2(y, x);
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

/// A length scale of a set of lengths that a few outliers cannot move: the mean of the lengths
/// at most kOutlierClip × their 99th percentile, the longer ones left out. Equal to the plain mean
/// unless a length exceeds kOutlierClip × the 99th percentile; a far outlier's lengths (fewer
/// than 1% of them) then only take their count out of the mean, whatever their size (a vertex
/// pulled 10^4 model sizes away moves it as little as one pulled 10 away). The heat method's time
/// step, the refinement resolution's h and the mollification margin use it (docs/decisions.md
/// D-012, D-132). In the lengths' unit; 0 for an empty set. O(n) (a copy, nth_element).
double robust_mean_length(std::vector<double> lengths);
inline constexpr double kOutlierClip = 4.0;

}  // namespace ifem::intrinsic
