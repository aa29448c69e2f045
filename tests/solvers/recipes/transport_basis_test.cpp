// VectorHeatSolver keeps the 3D tangent bases it was built with (vector_heat_solver(s)), and
// transport_on() uses them: the kept bases are bitwise those tangent_basis_3d() builds from the
// solver's triangulation and frames, transport_on() equals the solver's transport placed with
// rebuilt bases, repeated calls return the same bits, and a solver built without the input
// (rebuilding the bases per call) gives the same vectors.
#include <gtest/gtest.h>

#include <complex>
#include <vector>

#include "intrinsic/generators/mesh_generators.h"
#include "solvers/recipes/tangent_fields.h"
#include "solvers/test_util.h"
#include "solvers/vector/tangent_basis.h"
#include "solvers/vector/vector_heat.h"

namespace ifem::solvers {
namespace {

void expect_same_basis(const TangentBasis3d& a, const TangentBasis3d& b) {
  ASSERT_EQ(a.e1.rows(), b.e1.rows());
  EXPECT_EQ(a.normal, b.normal);
  EXPECT_EQ(a.e1, b.e1);
  EXPECT_EQ(a.e2, b.e2);
  EXPECT_EQ(a.fallback_vertices, b.fallback_vertices);
}

void expect_kept_basis_transports_alike(const intrinsic::TriangleMesh& mesh) {
  const PreparedSurface s = prepare_surface(test::as_input(mesh));
  ASSERT_EQ(s.path, intrinsic::SurfacePath::kManifold);
  const VectorHeatSolver solver = vector_heat_solver(s);
  const TangentBasis3d rebuilt = tangent_basis_3d(s.input, solver.triangulation(), solver.frames());
  expect_same_basis(solver.basis_3d(), rebuilt);
  const Index nv = s.n_input_vertices();
  const Eigen::Vector3d vec(0.3, -1.0, 0.7);
  for (const Index v : {Index(0), nv / 2, nv - 1}) {
    const Eigen::MatrixX3d x = transport_on(s, solver, v, vec);
    const std::complex<double> z(vec.dot(rebuilt.e1.row(v)), vec.dot(rebuilt.e2.row(v)));
    const Eigen::MatrixX3d ref =
        to_3d(Eigen::VectorXcd(solver.transport({{v, z}}).head(nv)), rebuilt);
    EXPECT_EQ(x, ref) << "source " << v;
    EXPECT_EQ(transport_on(s, solver, v, vec), x) << "a repeated call, source " << v;
  }
  // a solver without the input: transport_on() builds the bases itself, the same vectors
  VectorHeatOptions o;
  o.intrinsic_delaunay = false;
  o.mean_edge_length = distance_options(s).mean_edge_length;
  o.boundary_vertices = s.boundary_vertex;
  const VectorHeatSolver bare(s.tri, o);
  EXPECT_EQ(bare.basis_3d().e1.rows(), 0);
  const Eigen::MatrixX3d a = transport_on(s, solver, nv / 3, vec);
  const Eigen::MatrixX3d b = transport_on(s, bare, nv / 3, vec);
  EXPECT_LE((a - b).cwiseAbs().maxCoeff(), 1e-14 * a.cwiseAbs().maxCoeff());
}

TEST(TransportBasis, KeptOnASphere) { expect_kept_basis_transports_alike(intrinsic::icosphere(8)); }

TEST(TransportBasis, KeptOnAGridWithBoundary) {
  expect_kept_basis_transports_alike(intrinsic::grid(25, 18));
}

TEST(TransportBasis, FramePathKeepsItsFrames) {
  PrepareOptions po;
  po.force_tufted = true;
  const PreparedSurface s = prepare_surface(test::as_input(intrinsic::icosphere(6)), po);
  ASSERT_EQ(s.path, intrinsic::SurfacePath::kTufted);
  const VectorHeatSolver solver = vector_heat_solver(s);
  expect_same_basis(solver.basis_3d(), solver.frame_basis());
  expect_same_basis(solver.basis_3d(), frame_basis_3d(s.input, s.tri));
}

}  // namespace
}  // namespace ifem::solvers
