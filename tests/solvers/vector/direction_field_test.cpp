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
#include "solvers/vector/tangent_basis.h"

namespace ifem::solvers {
namespace {

using Complex = std::complex<double>;
using intrinsic::kPi;

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

// Boundary vertices keep their true angles, so a flat polygon's connection is trivial. A cross
// field along the boundary of a square or an L fits every corner (π/2 and 3π/2 are quarter
// turns): it is the constant field, parallel, no singularity anywhere. A vector field along the
// boundary takes the bisector at each corner: Poincaré–Hopf with boundary (2π Σ index = the
// field's turning along the boundary relative to transport + n Σ_interior (2π − Θ)), a
// quarter turn of the boundary at each convex corner, so Σ index = χ = 1 on the square; on the
// L, five convex corners and one reflex, also 1.
TEST(DirectionField, FieldsAlignedToAFlatPolygonsBoundary) {
  for (const bool l_shape : {false, true}) {
    SCOPED_TRACE(l_shape);
    const intrinsic::TriangleMesh m =
        l_shape ? test::flat_l_shape(10, 0.3, 2) : test::flat_square(10, 0.3, 3);
    const auto tri = test::make_tri(m);
    const fem::TangentFrames frames = fem::tangent_frames(tri);
    DirectionFieldOptions o;
    o.symmetry = 4;
    const std::vector<DirectionConstraint> held = boundary_constraints(tri, frames, 4);
    EXPECT_EQ(Index(held.size()), 4 * 10);  // both perimeters are 4
    const DirectionField f = aligned_field(tri, frames, held, o);
    EXPECT_LT(max_parallel_defect(tri, frames, f.u, 4), 1e-9);
    EXPECT_LT(f.energy, 1e-12);
    EXPECT_EQ(face_indices(tri, frames, f.u, 4).cwiseAbs().sum(), 0);
    // in 3D: every cross has an arm along x (the sides' directions)
    const TangentBasis3d basis = tangent_basis_3d(m.positions, m.faces, {}, tri, frames);
    for (Index v = 0; v < tri.n_vertices(); ++v) {
      const double arm = std::arg(f.u[v]) / 4;
      const Eigen::Vector3d d = std::cos(arm) * basis.e1.row(v) + std::sin(arm) * basis.e2.row(v);
      EXPECT_LT(std::abs(std::polar(1.0, 4 * std::atan2(d.y(), d.x())) - 1.0), 1e-9) << v;
    }
    o.symmetry = 1;
    const DirectionField g = aligned_field(tri, frames, boundary_constraints(tri, frames, 1), o);
    const Eigen::VectorXi index = face_indices(tri, frames, g.u, 1);
    EXPECT_EQ(index.sum(), 1);
  }
}

// Poincaré–Hopf with boundary on a curved disk (a bump on a jittered square; boundary angle
// sums ≤ 2π): for any field without zeros at the vertices, 2π Σ_f index_f = Σ over boundary
// halfedges of the field's turning relative to transport + n Σ_interior (2π − Θ_v), and by
// Gauss–Bonnet Σ_interior (2π − Θ_v) = 2πχ − Σ_boundary (π − Θ_v).
TEST(DirectionField, IndicesOnADiskFollowPoincareHopfWithBoundary) {
  intrinsic::TriangleMesh m = test::flat_square(12, 0.3, 8);
  for (Eigen::Index v = 0; v < m.positions.rows(); ++v) {
    const double x = m.positions(v, 0) - 0.5, y = m.positions(v, 1) - 0.45;
    m.positions(v, 2) = 0.3 * std::exp(-(x * x + y * y) / 0.04);
  }
  const auto tri = test::make_tri(m);
  const fem::TangentFrames frames = fem::tangent_frames(tri);
  const Eigen::VectorXd theta = intrinsic::vertex_angle_sums(tri);
  for (const int n : {1, 2, 4}) {
    DirectionFieldOptions o;
    o.symmetry = n;
    for (const bool aligned : {false, true}) {
      const DirectionField f =
          aligned ? aligned_field(tri, frames, boundary_constraints(tri, frames, n), o)
                  : smoothest_field(tri, frames, o);
      double along = 0.0, boundary_turn = 0.0;
      for (Index h = 0; h < tri.n_halfedges(); ++h) {
        if (tri.twin(h) != kInvalidIndex) continue;
        const Complex moved = std::pow(frames.transport[h], n) * f.u[tri.tail(h)];
        along += std::arg(f.u[tri.head(h)] / moved);
        boundary_turn += kPi - theta[tri.tail(h)];
      }
      const double expected = n * 1.0 + (along - n * boundary_turn) / (2 * kPi);
      const Eigen::VectorXi index = face_indices(tri, frames, f.u, n);
      EXPECT_NEAR(index.sum(), expected, 1e-6) << n << " " << aligned;
      // aligned: a cross fits the square's corners (no index left), a vector takes the
      // bisector there (index χ = 1); a line field meets a tie at each corner (either way)
      if (aligned && n != 2) {
        EXPECT_EQ(index.sum(), n == 4 ? 0 : 1) << n;
      }
    }
  }
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
