// The recipes' tangent fields on flat polygons with corners (solvers/recipes/tangent_fields.h):
// boundary vertices keep their true angles (fem/connection.h), so on the manifold path transport
// returns the source's 3D vector at every vertex, corners included, and a cross field along the
// boundary of a square or an L is the constant cross, without singularities. Refined or not:
// after refinement the 3D bases come from the correspondence (tangent_basis_3d; integer
// coordinates by default, signposts in IntegerCoordinatesGiveTheSignpostsBases), right also at
// input vertices whose neighbours are all inserted vertices; a refined icosphere checks the same
// bases on a curved surface against the sphere's own parallel transport.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdio>
#include <string>
#include <utility>
#include <vector>

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

// Per input vertex of s, 1 when it has neighbours in s.tri and all of them are inserted
// vertices: no input chord can fix its 3D basis there.
std::vector<char> inserted_one_rings(const PreparedSurface& s) {
  const Index nv = s.n_input_vertices();
  std::vector<char> any(nv, 0), input(nv, 0);
  for (Index h = 0; h < s.tri.n_halfedges(); ++h) {
    const Index a = s.tri.tail(h), b = s.tri.head(h);
    for (const auto& [v, w] : {std::pair{a, b}, std::pair{b, a}}) {
      if (v >= nv) continue;
      any[v] = 1;
      if (w < nv) input[v] = 1;
    }
  }
  std::vector<char> out(nv, 0);
  for (Index v = 0; v < nv; ++v) out[v] = any[v] && !input[v];
  return out;
}

Index count(const std::vector<char>& mask) {
  return static_cast<Index>(std::count(mask.begin(), mask.end(), 1));
}

// The angle between two 3D vectors, radians.
double angle_between(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::atan2(a.cross(b).norm(), a.dot(b));
}

// Parallel transport of a 3D vector on a flat domain is the vector itself (projected to the
// plane z = 0, its length kept): exact up to round-off (the connection is flat: see
// vector_heat_test's FlatDomainsWithCornersTransportExactly), at every vertex; refined too,
// where some input vertices have only inserted neighbours (asserted, so that the 3D bases from
// the correspondence are what is tested there).
TEST(FlatDomainFields, TransportOnReturnsTheSourcesVectorEverywhere) {
  for (const bool l_shape : {false, true}) {
    for (const bool refine : {false, true}) {
      const std::string name = std::string(l_shape ? "L" : "square") + (refine ? " refined" : "");
      SCOPED_TRACE(name);
      const PreparedSurface s = prepared_polygon(l_shape, 16, 21, refine);
      const std::vector<char> lonely = inserted_one_rings(s);
      if (refine) {
        EXPECT_GT(count(lonely), 0) << "no input vertex with an all-inserted one-ring";
      }
      const VectorHeatSolver solver = vector_heat_solver(s);
      ASSERT_FALSE(solver.on_frames());
      const Index nv = s.n_input_vertices();
      for (const Index src : {Index(0), nv / 3, nv / 2, nv - 1}) {  // a corner, inside, a corner
        const Eigen::Vector3d vec(std::cos(0.4 + src), std::sin(0.4 + src), 0.7);
        const Eigen::RowVector3d want(vec.x(), vec.y(), 0.0);
        VectorHeatReport rep;
        const Eigen::MatrixX3d x = transport_on(s, solver, src, vec, &rep);
        EXPECT_EQ(rep.unreached_vertices, 0);
        double worst = 0.0, worst_angle = 0.0, worst_lonely = 0.0;
        for (Index v = 0; v < nv; ++v) {
          worst = std::max(worst, (x.row(v) - want).norm());
          const double a = angle_between(x.row(v).transpose(), want.transpose());
          worst_angle = std::max(worst_angle, a);
          if (lonely[v]) worst_lonely = std::max(worst_lonely, a);
        }
        std::printf(
            "transport_on flat %s source %d: max |x − v| %.3g, max angle %.3g rad (%.3g at %d "
            "all-inserted one-rings)\n",
            name.c_str(), int(src), worst, worst_angle, worst_lonely, int(count(lonely)));
        EXPECT_LT(worst, 1e-10) << "source " << src;
      }
    }
  }
}

// On a refined icosphere (a curved surface: the bases' normals are the faces' and the
// directions the correspondence's) transport_on agrees with the sphere's parallel transport along
// great circles (the rotation about p × q taking p to q) at the input vertices within 120° of
// the source, the all-inserted one-rings included, to the discretization error; its vectors are
// tangent to the sphere and all as long as the source's (the given vector projected to the
// source's tangent plane).
TEST(FlatDomainFields, RefinedSphereTransportFollowsGreatCircles) {
  const intrinsic::TriangleMesh m = intrinsic::icosphere(4);
  for (const bool refine : {false, true}) {
    SCOPED_TRACE(refine ? "refined" : "unrefined");
    PrepareOptions o;
    if (refine) {
      o.refine = SurfaceRefineOptions{};
      o.refine->resolution = 0.5;
    }
    const PreparedSurface s = prepare_surface(test::as_input(m), o);
    const std::vector<char> lonely = inserted_one_rings(s);
    if (refine) {
      EXPECT_GT(count(lonely), 0) << "no input vertex with an all-inserted one-ring";
    }
    const VectorHeatSolver solver = vector_heat_solver(s);
    const Index nv = s.n_input_vertices();
    for (const Index src : {Index(0), nv / 2}) {
      const Eigen::Vector3d p = m.positions.row(src).transpose().normalized();
      const Eigen::Vector3d u = p.cross(Eigen::Vector3d(0.3, -0.5, 0.8)).normalized();
      const Eigen::MatrixX3d x = transport_on(s, solver, src, u);
      double worst = 0.0, worst_lonely = 0.0, worst_normal = 0.0, worst_length = 0.0;
      for (Index v = 0; v < nv; ++v) {
        const Eigen::Vector3d q = m.positions.row(v).transpose().normalized();
        const Eigen::Vector3d xv = x.row(v).transpose();
        worst_normal = std::max(worst_normal, std::abs(xv.dot(q)) / xv.norm());
        worst_length = std::max(worst_length, std::abs(xv.norm() - x.row(src).norm()));
        if (p.dot(q) < -0.5) continue;
        const Eigen::Vector3d axis = p.cross(q);
        const double angle = std::atan2(axis.norm(), p.dot(q));
        const Eigen::Vector3d want =
            axis.norm() > 1e-12 ? Eigen::AngleAxisd(angle, axis.normalized()) * u : u;
        const double a = angle_between(xv, want);
        worst = std::max(worst, a);
        if (lonely[v]) worst_lonely = std::max(worst_lonely, a);
      }
      std::printf(
          "transport_on icosphere(4)%s source %d: max angle to the great-circle transport %.3g "
          "rad (%.3g at %d all-inserted one-rings), max |x·n|/|x| %.3g\n",
          refine ? " refined" : "", int(src), worst, worst_lonely, int(count(lonely)),
          worst_normal);
      EXPECT_LT(worst, 0.05) << "source " << src;
      EXPECT_LT(worst_normal, 0.02) << "source " << src;
      EXPECT_LT(worst_length, 1e-9) << "source " << src;
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
      // in 3D: arms along x and y at every input vertex, those with only inserted neighbours
      // included (their bases come from the correspondence)
      const std::vector<char> lonely = inserted_one_rings(s);
      if (refine) {
        EXPECT_GT(count(lonely), 0) << "no input vertex with an all-inserted one-ring";
      }
      double worst = 0.0;
      for (Index v = 0; v < r.vectors.rows(); ++v) {
        const double a = std::atan2(r.vectors(v, 1), r.vectors(v, 0));
        EXPECT_LT(std::abs(r.vectors(v, 2)), 1e-12) << v;
        worst = std::max(worst, std::abs(std::arg(std::polar(1.0, 4 * a))) / 4);
      }
      std::printf("cross field along the boundary, %s%s: max angle to the axes %.3g rad\n",
                  l_shape ? "L" : "square", refine ? " refined" : "", worst);
      EXPECT_LT(worst, 1e-9);
      settings.symmetry = 1;
      const TangentFieldResult g = direction_field_on(s, settings);
      EXPECT_EQ(g.total_index, 1);
      EXPECT_EQ(g.face_singularity.sum(), 1);
    }
  }
}

}  // namespace
}  // namespace ifem::solvers

namespace ifem::solvers {
namespace {

// The unit normal of the input triangle f (3D positions).
Eigen::Vector3d face_normal(const intrinsic::TriangleMesh& m, const Triangle& f) {
  const Eigen::Vector3d a = m.positions.row(f[0]), b = m.positions.row(f[1]),
                        c = m.positions.row(f[2]);
  return (b - a).cross(c - a).normalized();
}

// Refined with integer coordinates the 3D bases are the signposts' (D-280): the same insertions,
// every outgoing halfedge of an input vertex leaves it in the same 3D direction (tangent to an
// input face at the vertex), no fallback basis, and transport_on's vectors agree at every input
// vertex, those with an all-inserted one-ring included. A curved surface (icosphere) and a flat
// L with boundary splits.
TEST(FlatDomainFields, IntegerCoordinatesGiveTheSignpostsBases) {
  const intrinsic::TriangleMesh sphere = intrinsic::icosphere(3);
  const intrinsic::TriangleMesh ell = test::flat_l_shape(10, 0.3, 7);
  for (const auto* m : {&sphere, &ell}) {
    SCOPED_TRACE(m == &sphere ? "icosphere(3)" : "L");
    PreparedSurface s[2];
    for (int k = 0; k < 2; ++k) {
      PrepareOptions o;
      o.refine = SurfaceRefineOptions{};
      o.refine->resolution = 0.5;
      o.refine->correspondence =
          k == 0 ? intrinsic::Correspondence::kSignposts : intrinsic::Correspondence::kInteger;
      s[k] = prepare_surface(test::as_input(*m), o);
      ASSERT_TRUE(s[k].correspondence().has_value());
    }
    ASSERT_TRUE(s[1].integer.has_value());
    ASSERT_EQ(s[0].tri.n_vertices(), s[1].tri.n_vertices());
    ASSERT_EQ(s[0].tri.n_halfedges(), s[1].tri.n_halfedges());
    const std::vector<char> lonely = inserted_one_rings(s[1]);
    EXPECT_GT(count(lonely), 0) << "no input vertex with an all-inserted one-ring";
    const Index nv = s[0].n_input_vertices();
    const auto sp = *s[0].correspondence(), ic = *s[1].correspondence();
    std::vector<std::vector<Eigen::Vector3d>> normals(nv);
    for (const Triangle& f : m->faces) {
      for (const Index v : f) normals[v].push_back(face_normal(*m, f));
    }
    double worst_direction = 0.0, worst_tangent = 0.0;
    for (Index h = 0; h < s[1].tri.n_halfedges(); ++h) {
      const Index v = s[1].tri.tail(h);
      if (v >= nv) continue;
      const Eigen::Vector3d d = ic.halfedge_direction_3d(h);
      worst_direction = std::max(worst_direction, (d - sp.halfedge_direction_3d(h)).norm());
      double off = 1.0;
      for (const Eigen::Vector3d& n : normals[v]) off = std::min(off, std::abs(d.dot(n)));
      worst_tangent = std::max(worst_tangent, off);
    }
    const fem::TangentFrames frames = fem::tangent_frames(s[1].tri);
    const TangentBasis3d b0 = tangent_basis_3d(s[0].input, s[0].tri, frames, sp);
    const TangentBasis3d b1 = tangent_basis_3d(s[1].input, s[1].tri, frames, ic);
    EXPECT_EQ(b1.fallback_vertices, 0);
    const double worst_e1 = (b0.e1 - b1.e1).cwiseAbs().maxCoeff();
    const VectorHeatSolver solver0 = vector_heat_solver(s[0]), solver1 = vector_heat_solver(s[1]);
    const Eigen::Vector3d vec(0.3, -0.5, 0.8);
    const Eigen::MatrixX3d x0 = transport_on(s[0], solver0, nv / 3, vec);
    const Eigen::MatrixX3d x1 = transport_on(s[1], solver1, nv / 3, vec);
    const double worst_field = (x0 - x1).cwiseAbs().maxCoeff();
    std::printf(
        "integer vs signposts bases (%d all-inserted one-rings): directions %.3g, off the "
        "input faces %.3g, e1 %.3g, transport %.3g\n",
        int(count(lonely)), worst_direction, worst_tangent, worst_e1, worst_field);
    EXPECT_LT(worst_direction, 1e-9);
    EXPECT_LT(worst_tangent, 1e-9);
    EXPECT_LT(worst_e1, 1e-9);
    EXPECT_LT(worst_field, 1e-9);
  }
}

}  // namespace
}  // namespace ifem::solvers
