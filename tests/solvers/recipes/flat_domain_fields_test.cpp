// The recipes' tangent fields on flat polygons with corners (solvers/recipes/tangent_fields.h):
// boundary vertices keep their true angles (fem/connection.h), so on the manifold path transport
// returns the source's 3D vector at every vertex, corners included, and a cross field along the
// boundary of a square or an L is the constant cross, without singularities.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "helpers.h"
#include "solvers/recipes/pipeline.h"
#include "solvers/recipes/tangent_fields.h"
#include "solvers/test_util.h"

namespace ifem::solvers {
namespace {

// The jittered flat square or L, prepared on the manifold path (intrinsic Delaunay), refined
// when asked (inserted vertices, split boundary edges: boundary vertices of the triangulation
// that are not the input's).
PreparedSurface prepared_polygon(bool l_shape, int n, unsigned seed, bool refine = false) {
  const intrinsic::TriangleMesh m =
      l_shape ? test::flat_l_shape(n, 0.3, seed) : test::flat_square(n, 0.3, seed);
  PrepareOptions o;
  if (refine) {
    o.refine = SurfaceRefineOptions{};
    o.refine->resolution = 0.5;
  }
  PreparedSurface s = prepare_surface(test::as_input(m), o);
  EXPECT_EQ(s.path, intrinsic::SurfacePath::kManifold);
  EXPECT_EQ(s.tri.n_vertices() > s.n_input_vertices(), refine);
  return s;
}

// Parallel transport of a 3D vector on a flat domain is the vector itself (projected to the
// plane z = 0, its length kept): exact up to round-off (the connection is flat: see
// vector_heat_test's FlatDomainsWithCornersTransportExactly), at every vertex.
TEST(FlatDomainFields, TransportOnReturnsTheSourcesVectorEverywhere) {
  for (const bool l_shape : {false, true}) {
    const PreparedSurface s = prepared_polygon(l_shape, 16, 21);
    const VectorHeatSolver solver = vector_heat_solver(s);
    ASSERT_FALSE(solver.on_frames());
    const Index nv = s.n_input_vertices();
    for (const Index src : {Index(0), nv / 3, nv / 2, nv - 1}) {  // a corner, inside, a corner
      const Eigen::Vector3d vec(std::cos(0.4 + src), std::sin(0.4 + src), 0.7);
      const Eigen::RowVector3d want(vec.x(), vec.y(), 0.0);
      VectorHeatReport rep;
      const Eigen::MatrixX3d x = transport_on(s, solver, src, vec, &rep);
      EXPECT_EQ(rep.unreached_vertices, 0);
      double worst = 0.0;
      for (Index v = 0; v < nv; ++v) worst = std::max(worst, (x.row(v) - want).norm());
      std::printf("transport_on flat %s source %d: max |x − v| %.3g\n", l_shape ? "L" : "square",
                  int(src), worst);
      EXPECT_LT(worst, 1e-12) << (l_shape ? "L" : "square") << " source " << src;
    }
  }
}

// A cross field along the boundary fits every corner (π/2, 3π/2): the constant cross, arms along
// x and y at every vertex, no singular face (on the triangulation and on the input's faces,
// refined or not: boundary splits and insertions convert through the same true angles); a
// vector field along the boundary has index χ = 1 (the bisectors at the
// convex corners each take a quarter of the boundary's turning).
TEST(FlatDomainFields, CrossFieldAlongTheBoundaryIsConstant) {
  for (const bool l_shape : {false, true}) {
    for (const bool refine : {false, true}) {
      SCOPED_TRACE(std::string(l_shape ? "L" : "square") + (refine ? " refined" : ""));
      const PreparedSurface s = prepared_polygon(l_shape, 12, 5, refine);
      FieldOptions settings;
      settings.symmetry = 4;
      settings.align_boundary = true;
      const TangentFieldResult r = direction_field_on(s, settings);
      EXPECT_EQ(r.total_index, 0);
      EXPECT_EQ(r.singular_faces, 0);
      EXPECT_EQ(r.face_singularity.cwiseAbs().sum(), 0);
      EXPECT_LT(r.energy, 1e-12);
      // in 3D (unrefined only: after refinement an input vertex whose neighbours are all
      // inserted has no chord to fix its e1, and tangent_basis_3d falls back to any direction)
      for (Index v = 0; v < (refine ? 0 : r.vectors.rows()); ++v) {
        const double a = std::atan2(r.vectors(v, 1), r.vectors(v, 0));
        EXPECT_LT(std::abs(std::polar(1.0, 4 * a) - 1.0), 1e-9) << v;
      }
      settings.symmetry = 1;
      const TangentFieldResult g = direction_field_on(s, settings);
      EXPECT_EQ(g.total_index, 1);
      EXPECT_EQ(g.face_singularity.sum(), 1);
    }
  }
}

}  // namespace
}  // namespace ifem::solvers
