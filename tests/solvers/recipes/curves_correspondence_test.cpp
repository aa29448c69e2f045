// Curves with integer coordinates (solvers/recipes/curves.h with
// SurfaceRefineOptions::correspondence = integer): FlipOut's operations on the signposts replayed
// on a NormalCoordinateTriangulation (intrinsic/integer/replay.h) give the same triangulation and
// the same solutions as the signposts themselves.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "intrinsic/core/errors.h"
#include "intrinsic/generators/mesh_generators.h"
#include "intrinsic/integer/replay.h"
#include "solvers/recipes/curves.h"
#include "solvers/test_util.h"

namespace ifem {
namespace {

using intrinsic::CurveShape;
using solvers::CurveCondition;

std::vector<CurveCondition> spot_curves() {
  CurveCondition bez, loop, slit;
  bez.shape = CurveShape::kBezier;
  bez.vertices = {0, 400, 1200, 2000};
  bez.values = {0.0, 1.0};
  loop.shape = CurveShape::kLoop;
  loop.vertices = {620, 1397, 1903};
  loop.values = {1.0};
  slit.vertices = {100, 900};
  slit.values = {0.25};
  slit.slit = true;
  slit.right_values = {0.75};
  return {bez, loop, slit};
}

solvers::CurveSurface spot_surface(intrinsic::Correspondence c, double resolution) {
  solvers::CurveSurfaceOptions opt;
  solvers::SurfaceRefineOptions rs;
  rs.resolution = resolution;
  rs.correspondence = c;
  opt.refine = rs;
  return solvers::prepare_curve_surface(io::read_surface((test::test_data() / "spot.obj").string()),
                                        spot_curves(), opt);
}

// Same triangulation (gluing, ids, lengths bit for bit), same Poisson and distance values, the
// same curves traced over the input, at two resolutions (the coarser one still splits curves).
TEST(CurvesIntegerCorrespondence, SameTriangulationAndValuesAsSignposts) {
  for (const double resolution : {2.0, 0.8}) {
    SCOPED_TRACE("resolution " + std::to_string(resolution));
    const solvers::CurveSurface a = spot_surface(intrinsic::Correspondence::kSignposts, resolution);
    const solvers::CurveSurface b = spot_surface(intrinsic::Correspondence::kInteger, resolution);
    ASSERT_TRUE(a.surface.signposts.has_value());
    ASSERT_FALSE(a.surface.integer.has_value());
    ASSERT_TRUE(b.surface.integer.has_value());
    ASSERT_FALSE(b.surface.signposts.has_value());
    EXPECT_GT(b.surface.refine_report.insertions, 0);
    EXPECT_NO_THROW(intrinsic::require_same_gluing(a.surface.tri, b.surface.tri, "test"));
    EXPECT_NO_THROW(
        intrinsic::require_same_gluing(b.surface.tri, b.surface.integer->intrinsic(), "test"));
    EXPECT_NO_THROW(b.surface.integer->validate());
    EXPECT_EQ(a.network.edges.size(), b.network.edges.size());
    EXPECT_EQ(a.network.constrained, b.network.constrained);
    const solvers::CurvePoissonResult ua = solvers::curve_poisson(a, Eigen::VectorXd());
    const solvers::CurvePoissonResult ub = solvers::curve_poisson(b, Eigen::VectorXd());
    ASSERT_EQ(ua.u.size(), ub.u.size());
    EXPECT_LE((ua.u - ub.u).lpNorm<Eigen::Infinity>(), 1e-9);
    EXPECT_LE((ua.u_intrinsic - ub.u_intrinsic).lpNorm<Eigen::Infinity>(), 1e-9);
    EXPECT_GT(ua.u.maxCoeff() - ua.u.minCoeff(), 0.5);  // not a constant: the check means something
    const Eigen::VectorXd da = solvers::curve_distance(a), db = solvers::curve_distance(b);
    EXPECT_LE((da - db).lpNorm<Eigen::Infinity>(), 1e-9);
    const auto pa = solvers::curve_polylines(a), pb = solvers::curve_polylines(b);
    ASSERT_EQ(pa.size(), pb.size());
    for (std::size_t c = 0; c < pa.size(); ++c) {
      ASSERT_EQ(pa[c].size(), pb[c].size()) << "curve " << c;
      for (std::size_t k = 0; k < pa[c].size(); ++k) {
        EXPECT_LE((pa[c][k] - pb[c][k]).norm(), 1e-6) << "curve " << c << " point " << k;
      }
    }
  }
}

// The log: flips undone leave it; a log started after a change cannot be replayed (the replay
// starts from the input) and says so.
TEST(CurvesIntegerCorrespondence, OperationLogUndoAndMismatch) {
  const intrinsic::TriangleMesh m = intrinsic::grid(4, 4);
  intrinsic::SignpostTriangulation st(m.faces, m.positions);
  std::vector<Index> interior;  // edges that can be flipped (tried on a copy)
  for (Index e = 0; e < st.intrinsic().n_edges(); ++e) {
    intrinsic::SignpostTriangulation probe = st;
    if (probe.flip_edge(e)) interior.push_back(e);
  }
  ASSERT_GE(interior.size(), 3u);
  st.start_operation_log();
  const std::size_t mark = st.flip_journal_mark();
  ASSERT_TRUE(st.flip_edge(interior[0]));
  ASSERT_EQ(st.operation_log().size(), 1u);
  st.undo_flips(mark);
  EXPECT_TRUE(st.operation_log().empty());
  ASSERT_TRUE(st.flip_edge(interior[2]));
  st.end_flip_journal();
  st.split_edge(interior[1], 0.4);
  st.insert_vertex(5, Eigen::Vector3d(0.2, 0.3, 0.5));
  ASSERT_EQ(st.operation_log().size(), 3u);
  const intrinsic::NormalCoordinateTriangulation nc = intrinsic::replay_on_integer(st);
  EXPECT_EQ(nc.intrinsic().n_vertices(), st.intrinsic().n_vertices());
  EXPECT_NO_THROW(nc.validate());
  st.start_operation_log();  // restarted empty: the changes so far are not in it
  try {
    intrinsic::replay_on_integer(st);
    ADD_FAILURE() << "a log missing changes replayed";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("triangulations differ"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace ifem
