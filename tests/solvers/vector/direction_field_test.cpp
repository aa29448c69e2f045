// Smoothest and aligned direction fields (solvers/vector/direction_field.h): Poincaré–Hopf on
// spheres and tori for n = 1, 2, 4; a parallel field on flat domains; constraints held; bad input.
#include "solvers/vector/direction_field.h"

#include <gtest/gtest.h>

#include <cmath>
#include <complex>

#include "intrinsic/core/errors.h"
#include "solvers/test_util.h"

namespace ifem::solvers {
namespace {

using Complex = std::complex<double>;

// A flat torus: an n×n periodic grid of unit squares split along a diagonal, all lengths from
// the plane (zero curvature everywhere: a parallel field exists).
intrinsic::IntrinsicTriangulation flat_torus(int n) {
  std::vector<Triangle> faces;
  auto id = [n](int i, int j) { return Index(((j + n) % n) * n + (i + n) % n); };
  Eigen::MatrixX3d lengths(2 * n * n, 3);
  const double d = std::sqrt(2.0);
  Index f = 0;
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      faces.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      lengths.row(f++) << 1.0, 1.0, d;
      faces.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
      lengths.row(f++) << d, 1.0, 1.0;
    }
  }
  return intrinsic::IntrinsicTriangulation::from_side_lengths(faces, n * n, lengths);
}

// The largest change of u across an edge relative to parallel transport (0: a parallel field).
double max_parallel_defect(const intrinsic::IntrinsicTriangulation& tri,
                           const fem::TangentFrames& frames, const Eigen::VectorXcd& u, int n) {
  double worst = 0.0;
  for (Index h = 0; h < tri.n_halfedges(); ++h) {
    const Complex moved = std::pow(frames.transport[h], n) * u[tri.tail(h)];
    worst = std::max(worst, std::abs(u[tri.head(h)] - moved));
  }
  return worst;
}

TEST(DirectionField, SphereIndicesSumToTwoN) {
  const auto tri = test::make_tri(intrinsic::icosphere(6));
  const fem::TangentFrames frames = fem::tangent_frames(tri);
  for (const int n : {1, 2, 4}) {
    DirectionFieldOptions o;
    o.symmetry = n;
    const DirectionField f = smoothest_field(tri, frames, o);
    EXPECT_GT(f.energy, 1e-3) << n;  // no parallel field on a sphere
    const Eigen::VectorXi index = face_indices(tri, frames, f.u, n);
    EXPECT_EQ(index.sum(), 2 * n) << "Poincaré–Hopf, n = " << n;
    EXPECT_LE(index.cwiseAbs().sum(), 4 * n) << "a smoothest field has few singularities";
  }
}

TEST(DirectionField, FlatTorusHasAParallelFieldWithoutSingularities) {
  const auto tri = flat_torus(12);
  const fem::TangentFrames frames = fem::tangent_frames(tri);
  for (const int n : {1, 4}) {
    DirectionFieldOptions o;
    o.symmetry = n;
    const DirectionField f = smoothest_field(tri, frames, o);
    EXPECT_LT(std::abs(f.energy), 1e-8) << n;
    EXPECT_LT(max_parallel_defect(tri, frames, f.u, n), 1e-6) << n;
    EXPECT_EQ(face_indices(tri, frames, f.u, n).cwiseAbs().sum(), 0) << n;
  }
}

TEST(DirectionField, OneConstraintOnAFlatTorusIsTransportedEverywhere) {
  const auto tri = flat_torus(10);
  const fem::TangentFrames frames = fem::tangent_frames(tri);
  for (const int n : {1, 2}) {
    DirectionFieldOptions o;
    o.symmetry = n;
    const DirectionField f = aligned_field(tri, frames, {{40, 0.7}}, o);
    EXPECT_EQ(f.constrained, 1);
    EXPECT_EQ(f.free_components, 0);
    EXPECT_NEAR(std::arg(f.u[40]), n * 0.7, 1e-12);
    EXPECT_LT(max_parallel_defect(tri, frames, f.u, n), 1e-8) << n;
    EXPECT_EQ(face_indices(tri, frames, f.u, n).cwiseAbs().sum(), 0) << n;
  }
}

TEST(DirectionField, CrossFieldAlignedToASquaresBoundaryTurnsOnlyAtTheCorners) {
  const intrinsic::TriangleMesh m = test::jittered(intrinsic::grid(10, 10), 0.02);
  const auto tri = test::make_tri(m);
  const fem::TangentFrames frames = fem::tangent_frames(tri);
  const std::vector<DirectionConstraint> held = boundary_constraints(tri, frames);
  EXPECT_EQ(Index(held.size()), 4 * 10);
  DirectionFieldOptions o;
  o.symmetry = 4;
  const DirectionField f = aligned_field(tri, frames, held, o);
  // Poincaré–Hopf for a field along the boundary of a disk: indices sum to χ = 1, four quarter
  // turns, all next to the square's corners (where the boundary turns), none inside
  const Eigen::VectorXi index = face_indices(tri, frames, f.u, 4);
  EXPECT_EQ(index.sum(), 4);
  for (Index face = 0; face < tri.n_faces(); ++face) {
    if (index[face] == 0) continue;
    Eigen::RowVector3d c = Eigen::RowVector3d::Zero();
    for (int k = 0; k < 3; ++k) c += m.positions.row(tri.tail(3 * face + k)) / 3.0;
    const double to_corner =
        std::min(std::min(c.x(), 1.0 - c.x()), 0.2) + std::min(std::min(c.y(), 1.0 - c.y()), 0.2);
    EXPECT_LT(to_corner, 0.25) << "a singularity away from the corners, face " << face;
  }
  // a vector field along the boundary has index 1 as well
  o.symmetry = 1;
  const DirectionField g = aligned_field(tri, frames, held, o);
  EXPECT_EQ(face_indices(tri, frames, g.u, 1).sum(), 1);
}

TEST(DirectionField, BadInputIsRefused) {
  const auto tri = test::make_tri(intrinsic::icosphere(2));
  const fem::TangentFrames frames = fem::tangent_frames(tri);
  DirectionFieldOptions o;
  o.symmetry = 0;
  EXPECT_THROW(smoothest_field(tri, frames, o), InvalidInput);
  EXPECT_THROW(aligned_field(tri, frames, {{tri.n_vertices(), 0.0}}), InvalidInput);
  EXPECT_THROW(aligned_field(tri, frames, {{0, std::nan("")}}), InvalidInput);
}

}  // namespace
}  // namespace ifem::solvers
