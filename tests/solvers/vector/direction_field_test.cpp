// Smoothest and aligned direction fields (solvers/vector/direction_field.h): Poincaré–Hopf on
// spheres and tori for n = 1, 2, 4; a parallel field on flat domains; constraints held; bad input.
#include "solvers/vector/direction_field.h"

#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <initializer_list>

#include "fem/operators.h"
#include "intrinsic/core/errors.h"
#include "solvers/test_util.h"

namespace ifem::solvers {
namespace {

using Complex = std::complex<double>;

// A flat torus: an n×n periodic grid of squares of side `side` split along a diagonal, all
// lengths from the plane (zero curvature everywhere: a parallel field exists); `copies` disjoint
// copies of it, copy k with side side·scale^k (vertices k·n² ..).
intrinsic::IntrinsicTriangulation flat_torus(int n, int copies = 1, double scale = 1.0) {
  std::vector<Triangle> faces;
  Eigen::MatrixX3d lengths(2 * n * n * copies, 3);
  const double d = std::sqrt(2.0);
  Index f = 0;
  double side = 1.0;
  for (int k = 0; k < copies; ++k, side *= scale) {
    auto id = [n, k](int i, int j) { return Index(k * n * n + ((j + n) % n) * n + (i + n) % n); };
    for (int j = 0; j < n; ++j) {
      for (int i = 0; i < n; ++i) {
        faces.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
        lengths.row(f++) << side, side, d * side;
        faces.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
        lengths.row(f++) << d * side, side, side;
      }
    }
  }
  return intrinsic::IntrinsicTriangulation::from_side_lengths(faces, n * n * copies, lengths);
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

// A soup's pieces come in any size: three flat tori of sides 1, 1e-6 and 1e-12 (masses 1e-24
// apart, as a mollified zero-area face against the rest) each get their own parallel field,
// with one shift for all they made L + εM singular. A component whose vertices the caller
// unlabels, or whose operator is not finite, gets no field (u = 0), counted, not an error.
TEST(DirectionField, ComponentsOfAnySizeEachGetTheirOwnField) {
  const auto tri = flat_torus(4, 3, 1e-6);
  const fem::TangentFrames frames = fem::tangent_frames(tri);
  const Components comps = connected_components(tri);
  ASSERT_EQ(comps.count, 3);
  for (const int n : {1, 2, 4}) {
    DirectionFieldOptions o;
    o.symmetry = n;
    const DirectionField f = smoothest_field(tri, frames, o);
    EXPECT_EQ(f.free_components, 3) << n;
    EXPECT_EQ(f.empty_components, 0) << n;
    EXPECT_LT(f.iterations, o.max_iterations) << "converged, n = " << n;
    for (Index v = 0; v < tri.n_vertices(); ++v) ASSERT_NEAR(std::abs(f.u[v]), 1.0, 1e-12) << v;
    EXPECT_LT(max_parallel_defect(tri, frames, f.u, n), 1e-6) << n;
    // held at one vertex of the middle torus: that one is held, the other two are free
    const DirectionField g = aligned_field(tri, frames, {{20, 0.3}}, o);
    EXPECT_EQ(g.free_components, 2) << n;
    EXPECT_NEAR(std::arg(g.u[20] * std::polar(1.0, -n * 0.3)), 0.0, 1e-9) << n;
    EXPECT_LT(max_parallel_defect(tri, frames, g.u, n), 1e-6) << n;
  }
  const fem::ComplexSparseMatrix L = fem::connection_laplacian(tri, frames, 1);
  const Eigen::VectorXd mass = fem::lumped_mass(tri);
  Components some = comps;  // the smallest torus left out by the caller
  for (Index v = 32; v < 48; ++v) some.label[v] = kInvalidIndex;
  fem::ComplexSparseMatrix bad = L;  // the middle one with a non-finite entry
  bad.coeffRef(17, 17) = std::nan("");
  // u on each torus: 1 where it has a field, 0 where not
  auto expect_fields = [](const DirectionField& f, std::initializer_list<bool> has) {
    int k = 0;
    for (const bool on : has) {
      for (Index v = 16 * k; v < 16 * (k + 1); ++v) EXPECT_NEAR(std::abs(f.u[v]), on, 1e-12);
      ++k;
    }
  };
  const DirectionField a = smoothest_field(L, mass, some);
  EXPECT_EQ(a.free_components, 2);
  EXPECT_EQ(a.empty_components, 1);
  expect_fields(a, {true, true, false});
  const DirectionField b = aligned_field(L, mass, some, {{0, 0.5}, {40, 0.5}});
  EXPECT_EQ(b.free_components, 1);  // the first is held, the last empty (its direction skipped)
  EXPECT_EQ(b.empty_components, 1);
  expect_fields(b, {true, true, false});
  const DirectionField c = smoothest_field(bad, mass, some);
  EXPECT_EQ(c.free_components, 1);
  EXPECT_EQ(c.empty_components, 2);
  expect_fields(c, {true, false, false});
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
