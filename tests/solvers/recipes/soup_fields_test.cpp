// Tangent fields and transport on a triangle soup (solvers/recipes/tangent_fields.h):
// tests/data/soup_icosphere.obj, an icosphere cut into 8 pieces with their own (coincident)
// vertices, a lone flat triangle and a zero-area face (tests/data/make_soup.py). On the manifold
// and the tufted path: every piece with area gets its own smoothest field (unit vectors; on the
// tufted path the flat triangle's parallel), the zero-area piece none (vectors 0), counted
// against an independent count of the components; aligned to the boundary, Poincaré–Hopf per
// piece (index n on each of the 9 disks); transport finite on the source's piece and NaN on the
// others.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <complex>
#include <numeric>
#include <vector>

#include "fem/connection.h"
#include "helpers.h"
#include "intrinsic/core/errors.h"
#include "intrinsic/core/geometry.h"
#include "solvers/recipes/tangent_fields.h"

namespace ifem::solvers {
namespace {

using intrinsic::kPi;
constexpr Index kLone = 240;  // the lone flat triangle: vertices 240..242 (in the plane z = 0)
constexpr Index kFlat = 243;  // the zero-area face: vertices 243..245, all at (0, 0, 2)

// The input's pieces, counted from its faces alone (union–find), and which have area.
struct Pieces {
  std::vector<Index> of;  // #V: piece id
  Index count = 0, flat = 0;
};

Pieces pieces(const io::SurfaceInput& in) {
  const Index nv = static_cast<Index>(in.positions.rows());
  std::vector<Index> parent(nv);
  std::iota(parent.begin(), parent.end(), 0);
  auto find = [&](Index v) {
    while (parent[v] != v) v = parent[v] = parent[parent[v]];
    return v;
  };
  for (const Triangle& f : in.triangles) {
    parent[find(f[1])] = find(f[0]);
    parent[find(f[2])] = find(f[0]);
  }
  Pieces p;
  p.of.assign(nv, kInvalidIndex);
  std::vector<Index> id(nv, kInvalidIndex);
  for (Index v = 0; v < nv; ++v) {
    const Index r = find(v);
    if (id[r] == kInvalidIndex) id[r] = p.count++;
    p.of[v] = id[r];
  }
  std::vector<double> area(p.count, 0.0);
  for (const Triangle& f : in.triangles) {
    const Eigen::Vector3d a = in.positions.row(f[0]), b = in.positions.row(f[1]),
                          c = in.positions.row(f[2]);
    area[p.of[f[0]]] += 0.5 * (b - a).cross(c - a).norm();
  }
  for (const double a : area) p.flat += a == 0.0;
  return p;
}

PreparedSurface soup(bool tufted) {
  PrepareOptions o;
  o.force_tufted = tufted;
  return load_surface((test::test_data() / "soup_icosphere.obj").string(), o);
}

class SoupFields : public ::testing::TestWithParam<bool> {};  // param: the tufted path

TEST_P(SoupFields, EveryPieceWithAreaGetsItsOwnFieldTheFlatOneNone) {
  const PreparedSurface s = soup(GetParam());
  EXPECT_EQ(s.path,
            GetParam() ? intrinsic::SurfacePath::kTufted : intrinsic::SurfacePath::kManifold);
  const Pieces p = pieces(s.input);
  ASSERT_EQ(p.count, 10);
  ASSERT_EQ(p.flat, 1);
  for (const int n : {1, 2, 4}) {
    FieldOptions o;
    o.symmetry = n;
    const TangentFieldResult r = direction_field_on(s, o);
    EXPECT_EQ(r.components, p.count) << n;
    EXPECT_EQ(r.free_components, p.count - p.flat) << n;
    EXPECT_EQ(r.empty_components, p.flat) << n;
    EXPECT_EQ(r.flat_components, p.flat) << n;
    for (Index v = 0; v < s.n_input_vertices(); ++v) {
      EXPECT_NEAR(r.vectors.row(v).norm(), v >= kFlat ? 0.0 : 1.0, 1e-9) << v << ", n " << n;
    }
    // the lone flat triangle's field is parallel on both paths (boundary vertices keep their
    // true angles, fem/connection.h): its corners' directions agree up to 2π/n, to 1e-4 rad
    // (the manifold path's angles are those of the mollified lengths: 3e-6·n rad off here)
    for (Index v = kLone + 1; v < kLone + 3; ++v) {
      EXPECT_NEAR(r.vectors(v, 2), 0.0, 1e-9);
      const double turn = n * (std::atan2(r.vectors(v, 1), r.vectors(v, 0)) -
                               std::atan2(r.vectors(kLone, 1), r.vectors(kLone, 0)));
      EXPECT_NEAR(std::remainder(turn, 2 * kPi), 0.0, 1e-4) << v << ", n " << n;
    }
    // a direction on the zero-area face is skipped; one on a piece holds that piece
    o.constraints = {{kFlat, {1, 0, 0}, ""}, {kLone, {0, 1, 0}, ""}};
    const TangentFieldResult h = direction_field_on(s, o);
    EXPECT_EQ(h.skipped_constraints, 1);
    EXPECT_EQ(h.free_components, p.count - p.flat - 1);
    EXPECT_NEAR(
        std::remainder(n * std::atan2(h.vectors(kLone, 1), h.vectors(kLone, 0)) - n * kPi / 2,
                       2 * kPi),
        0.0, 1e-9);
  }
}

// Aligned to the boundary, the 9 disks (the zero-area face has no field) follow Poincaré–Hopf
// with boundary: 2π Σ_f index_f = 2π n Σ χ + Σ over boundary halfedges of (the field's turning
// relative to transport − n (π − Θ_tail)), χ = 1 per disk, Θ the true angle sums. For vectors
// that is 9 (a vector takes the bisector at a corner, index χ each); a cross or a line field
// leaves an index at corners whose turn it does not fit. On the tufted path n = 1 only: the
// frame path's face indices (frame_face_indices) take each side's turn in (−π, π] of the n-th
// power, and along a coarse boundary (a lone triangle: n·120° per side) that wraps.
TEST(SoupFieldsAligned, EachDiskFollowsPoincareHopfWithBoundary) {
  const PreparedSurface tufted = soup(true);
  FieldOptions one;
  one.align_boundary = true;
  EXPECT_EQ(direction_field_on(tufted, one).total_index, 9);
  const PreparedSurface s = soup(false);
  ASSERT_EQ(s.tri.n_vertices(), s.n_input_vertices());  // unrefined: angles are s.tri's
  const fem::TangentFrames frames = fem::tangent_frames(s.tri);
  const Eigen::VectorXd theta = intrinsic::vertex_angle_sums(s.tri);
  for (const int n : {1, 2, 4}) {
    FieldOptions o;
    o.symmetry = n;
    o.align_boundary = true;
    const TangentFieldResult r = direction_field_on(s, o);
    EXPECT_EQ(r.empty_components, 1) << n;
    if (n == 1) {
      EXPECT_EQ(r.total_index, 9);
    }
    double along = 0.0, boundary_turn = 0.0;
    for (Index h = 0; h < s.tri.n_halfedges(); ++h) {
      if (s.tri.twin(h) != kInvalidIndex || s.tri.tail(h) >= kFlat) continue;
      const std::complex<double> ut = std::polar(1.0, n * r.angle[s.tri.tail(h)]);
      const std::complex<double> uh = std::polar(1.0, n * r.angle[s.tri.head(h)]);
      along += std::arg(uh / (std::pow(frames.transport[h], n) * ut));
      boundary_turn += kPi - theta[s.tri.tail(h)];
    }
    EXPECT_NEAR(double(r.total_index), 9.0 * n + (along - n * boundary_turn) / (2 * kPi), 1e-6)
        << n;
  }
}

TEST_P(SoupFields, TransportIsFiniteOnTheSourcesPieceAndNaNElsewhere) {
  const PreparedSurface s = soup(GetParam());
  const Pieces p = pieces(s.input);
  const VectorHeatSolver solver = vector_heat_solver(s);
  for (const Index source : {Index(0), kLone}) {
    VectorHeatReport report;
    const Eigen::MatrixX3d x = transport_on(s, solver, source, {1, 0, 0}, &report);
    const double length = x.row(source).norm();
    EXPECT_GT(length, 0.1);
    Index reached = 0;
    for (Index v = 0; v < s.n_input_vertices(); ++v) {
      if (p.of[v] == p.of[source]) {
        ++reached;
        ASSERT_TRUE(x.row(v).allFinite()) << v;
        EXPECT_NEAR(x.row(v).norm(), length, 1e-9) << v;
        // on the flat triangle transport is the identity (frame path; the manifold path's
        // coordinates are rescaled at boundary vertices)
        if (source == kLone && GetParam()) {
          EXPECT_LT((x.row(v) - Eigen::RowVector3d(1, 0, 0)).norm(), 1e-9);
        }
      } else {
        EXPECT_TRUE(x.row(v).array().isNaN().all()) << v;
      }
    }
    EXPECT_EQ(report.unreached_vertices + report.unresolved_vertices,
              s.n_input_vertices() - reached);
  }
}

INSTANTIATE_TEST_SUITE_P(ManifoldAndTufted, SoupFields, ::testing::Values(false, true));

}  // namespace
}  // namespace ifem::solvers
