// PathGraph's upper bounds and the heat method's clamp into [chord, path] (D-141): bounds that
// hold against exact geodesic distances, and a clamp that never moves a value away from them.
#include "solvers/scalar/path_bounds.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "intrinsic/core/errors.h"
#include "solvers/recipes/pipeline.h"
#include "solvers/scalar/heat_distance.h"
#include "solvers/test_util.h"

namespace ifem::solvers {
namespace {

using test::relative_error;

// On a flat grid the geodesic distance is the Euclidean one: every graph path is at least that,
// the diamond diagonals are there (more arcs than twice the edges), and a vertex two rows and
// one column away (not on an edge line) is reached by its straight segment exactly.
TEST(PathBounds, FlatGridPathsAreUpperBoundsAndUseDiagonals) {
  const intrinsic::TriangleMesh m = intrinsic::grid(12, 9, 2.0, 1.5);
  const auto tri = test::make_tri(m);
  const PathGraph g(tri);
  EXPECT_GT(g.n_arcs(), 2 * tri.n_edges());
  const Index src = 5 * 13 + 6;  // an interior vertex of the 13×10 vertex grid
  const Eigen::VectorXd d = g.shortest_paths({{src, 0.0}});
  double worst = 0.0;
  for (Index v = 0; v < tri.n_vertices(); ++v) {
    const double e = (m.positions.row(v) - m.positions.row(src)).norm();
    EXPECT_GE(d[v], e * (1 - 1e-12)) << v;
    worst = std::max(worst, d[v] / std::max(e, 1e-300));
  }
  EXPECT_LT(worst, 1.09);  // edges alone: up to 1/cos(30°) = 1.155 off the edge directions
  EXPECT_THROW(g.shortest_paths({{-1, 0.0}}), InvalidInput);
  EXPECT_THROW(g.shortest_paths({{0, -1.0}}), InvalidInput);
}

// On every reference: the graph's paths are ≥ the exact distance, the clamped heat distance is
// nowhere farther from the exact one than the raw heat distance (per vertex), and its mean error
// is lower. Bundled references always; ../shared ones below 20k vertices when present.
TEST(PathBounds, ClampNeverIncreasesErrorOnReferences) {
  int bundled = 0, shared = 0;
  for (const test::ReferenceCase& c : test::reference_cases()) {
    ASSERT_FALSE(c.mesh.empty()) << c.exact;
    const io::SurfaceInput in = io::read_mesh(c.mesh.string());
    if (in.positions.rows() > 20000) continue;
    const PreparedSurface s = prepare_surface(in);
    const Eigen::VectorXd exact = io::read_values(c.exact.string());
    HeatDistanceOptions on = distance_options(s), off = on;
    off.path_bounds = false;
    const Index src = Index(c.src);
    const Eigen::VectorXd raw = HeatDistanceSolver(s.tri, off).compute_distance({src});
    const Eigen::VectorXd bounded = HeatDistanceSolver(s.tri, on).compute_distance({src});
    const Eigen::VectorXd upper = PathGraph(s.tri).shortest_paths({{src, 0.0}});
    for (Index v = 0; v < Index(exact.size()); ++v) {
      if (!std::isfinite(exact[v])) continue;
      if (c.stem != "conrod") {  // conrod: the reference is on CGAL's cut surface (longer)
        EXPECT_GE(upper[v], exact[v] * (1 - 1e-9)) << c.stem << " vertex " << v;
      }
      EXPECT_LE(std::abs(bounded[v] - exact[v]), std::abs(raw[v] - exact[v]) + 1e-12 * exact[v])
          << c.stem << " vertex " << v;
    }
    EXPECT_LT(relative_error(bounded, exact).mean, relative_error(raw, exact).mean) << c.stem;
    ++(c.bundled ? bundled : shared);
  }
  test::expect_references_checked(bundled, shared);
}

// path_bounds off gives the heat method's own values; from a surface point at a vertex the
// bounds are those of the vertex source; bad positions are refused.
TEST(PathBounds, OptionsAndSurfacePoints) {
  const intrinsic::TriangleMesh m = intrinsic::icosphere(3);
  const auto tri = test::make_tri(m);
  HeatDistanceOptions on;
  on.vertex_positions = m.positions;
  HeatDistanceOptions off = on;
  off.path_bounds = false;
  const HeatDistanceSolver a(tri, on), b(tri, off);
  const Eigen::VectorXd da = a.compute_distance({0}), db = b.compute_distance({0});
  EXPECT_LE((da - db).cwiseAbs().maxCoeff(), 0.1 * db.maxCoeff());
  // a vertex is a point with barycentric coordinates (1, 0, 0) in a face it is a corner of
  Index f = 0;
  while (a.triangulation().tail(3 * f) != 0) ++f;
  const SurfacePoint p{f, Eigen::Vector3d(1, 0, 0)};
  HeatDistanceOptions intrinsic_only = on;
  intrinsic_only.vertex_positions.resize(0, 3);
  const HeatDistanceSolver c(tri, intrinsic_only);
  const Eigen::VectorXd dp = c.compute_distance_from_points({p}), dv = c.compute_distance({0});
  EXPECT_LE((dp - dv).cwiseAbs().maxCoeff(), 1e-9 * dv.maxCoeff());
  // the batch applies the same bounds per column
  const Eigen::MatrixXd batch = a.compute_distances({0, 7});
  EXPECT_LE((batch.col(0) - da).cwiseAbs().maxCoeff(), 1e-9 * da.maxCoeff());
  HeatDistanceOptions bad = on;
  bad.vertex_positions(3, 1) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(bad.validate(), InvalidInput);
  HeatDistanceOptions too_many = on;
  too_many.vertex_positions.resize(tri.n_vertices() + 1, 3);
  too_many.vertex_positions.setZero();
  EXPECT_THROW(HeatDistanceSolver(tri, too_many), InvalidInput);
}

}  // namespace
}  // namespace ifem::solvers
