// Shared checks of the tangent-field tests (vector_heat_test, frame_fields_test): angle
// statistics and the great-circle transport check on the unit sphere, written once so that the
// mesh and the point-cloud paths are held to the same truth.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "intrinsic/core/types.h"

namespace ifem::test {

constexpr double kTangentPi = 3.14159265358979323846;

/// a wrapped to (−π, π].
inline double wrap_angle(double a) { return std::remainder(a, 2.0 * kTangentPi); }

/// Mean and max of a sample of errors (call finish() once all are added).
struct ErrorStats {
  double mean = 0.0, max = 0.0;
  int n = 0;
  void add(double e) {
    mean += e;
    max = std::max(max, e);
    ++n;
  }
  void finish() { mean /= std::max(n, 1); }
};

/// Signed angle from a to b about the unit normal nrm (a, b tangent), in (−π, π].
inline double signed_angle(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                           const Eigen::Vector3d& nrm) {
  return std::atan2(a.cross(b).dot(nrm), a.dot(b));
}

/// Great-circle distance between two unit vectors.
inline double great_circle(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::atan2(a.cross(b).norm(), a.dot(b));
}

/// Parallel transport from vertex src of the unit sphere (positions p, #V×3) to the points near
/// its equator (great-circle distance π/2 ± 0.05), x the transported 3D vectors (#V×3): the angle
/// from the arc's direction to the vector must be the same at both ends. Prints and returns the
/// errors, radians.
inline ErrorStats great_circle_transport_error(const Eigen::MatrixX3d& p, const Eigen::MatrixX3d& x,
                                               Index src, const char* label) {
  const Eigen::Vector3d s = p.row(src).transpose();
  ErrorStats st;
  for (Index v = 0; v < p.rows(); ++v) {
    const Eigen::Vector3d q = p.row(v).transpose();
    if (std::abs(great_circle(s, q) - kTangentPi / 2) > 0.05) continue;
    const Eigen::Vector3d leave = (q - q.dot(s) * s).normalized();   // arc's direction at s
    const Eigen::Vector3d arrive = (q.dot(s) * q - s).normalized();  // and at q (onwards)
    const double at_source = signed_angle(leave, x.row(src).transpose(), s);
    const double at_end = signed_angle(arrive, x.row(v).transpose(), q);
    st.add(std::abs(wrap_angle(at_end - at_source)));
  }
  st.finish();
  std::printf("%s: angle error mean %.3g max %.3g rad over %d\n", label, st.mean, st.max, st.n);
  return st;
}

}  // namespace ifem::test
