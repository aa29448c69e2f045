// Progress of long work (intrinsic/core/progress.h): the meter's contract, and each long call
// that reports (refinement, batched heat distances, single-source geodesics, eigenpairs,
// reading a file, the pipeline) reports a stage that starts at 0, never goes down, stays in
// [0, 1] and ends at exactly 1, without changing the results.
#include "intrinsic/core/progress.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <utility>
#include <vector>

#include "intrinsic/generators/mesh_generators.h"
#include "intrinsic/geodesic/flip_geodesic.h"
#include "intrinsic/io/mesh_io.h"
#include "intrinsic/refine/delaunay_refine.h"
#include "solvers/recipes/pipeline.h"
#include "solvers/scalar/eigen.h"
#include "solvers/scalar/heat_distance.h"
#include "solvers/test_util.h"

namespace ifem {
namespace {

// Every call the callback received, in order.
struct Recorder {
  std::vector<std::pair<double, std::string>> calls;
  ProgressCallback callback() {
    return [this](double f, std::string_view stage) { calls.emplace_back(f, std::string(stage)); };
  }
  // The calls of one stage, which must be contiguous.
  std::vector<double> stage(const std::string& name) const {
    std::vector<double> out;
    bool ended = false;
    for (const auto& [f, s] : calls) {
      if (s == name) {
        EXPECT_FALSE(ended) << "stage " << name << " reported again after another stage";
        out.push_back(f);
      } else if (!out.empty()) {
        ended = true;
      }
    }
    return out;
  }
};

// Starts at 0, ends at exactly 1 (once), monotone, in [0, 1], at most ~1000 calls.
void expect_well_formed(const std::vector<double>& f, const std::string& name) {
  ASSERT_GE(f.size(), 2u) << name;
  EXPECT_EQ(f.front(), 0.0) << name;
  EXPECT_EQ(f.back(), 1.0) << name;
  EXPECT_LE(f.size(), 1002u) << name;
  for (std::size_t i = 0; i < f.size(); ++i) {
    EXPECT_GE(f[i], 0.0) << name << " call " << i;
    EXPECT_LE(f[i], 1.0) << name << " call " << i;
    if (i > 0) {
      EXPECT_GE(f[i], f[i - 1]) << name << " call " << i;
    }
    if (i + 1 < f.size()) {
      EXPECT_LT(f[i], 1.0) << name << ": 1 before the end, call " << i;
    }
  }
}

TEST(Progress, SaturatingFractionIsMonotoneContinuousAndBelowOne) {
  EXPECT_EQ(saturating_fraction(0.0, 10.0), 0.0);
  EXPECT_EQ(saturating_fraction(5.0, 0.0), 0.0);
  EXPECT_DOUBLE_EQ(saturating_fraction(5.0, 10.0), 0.5);
  EXPECT_NEAR(saturating_fraction(9.0, 10.0), 0.9, 1e-15);
  EXPECT_NEAR(saturating_fraction(9.0 + 1e-9, 10.0), 0.9, 1e-9);  // continuous at 0.9
  double last = 0.0;
  for (double x = 0.0; x < 40.0; x += 0.01) {
    const double f = saturating_fraction(x, 10.0);
    EXPECT_GE(f, last) << x;
    EXPECT_LT(f, 1.0) << x;
    last = f;
  }
  EXPECT_GT(saturating_fraction(20.0, 10.0), 0.99);  // twice the estimate: nearly full
}

TEST(Progress, MeterThrottlesClampsAndFinishesOnce) {
  Recorder r;
  const ProgressCallback cb = r.callback();
  {
    ProgressMeter m(cb, "work", 1e6);
    for (int i = 1; i <= 2'000'000; ++i) m.update(double(i));  // past the total: clamped
    m.finish();
    m.finish();
  }
  const std::vector<double> f = r.stage("work");
  expect_well_formed(f, "work");
  EXPECT_GE(f.size(), 900u);  // about every 1/1000
  // estimated: never 1 before finish(), even far past the estimate
  Recorder e;
  const ProgressCallback ecb = e.callback();
  ProgressMeter m(ecb, "estimated", 100.0, true);
  for (int i = 1; i <= 1000; ++i) m.update(double(i));
  EXPECT_LT(e.calls.back().first, 1.0);
  m.finish();
  expect_well_formed(e.stage("estimated"), "estimated");
  // no callback: nothing happens
  const ProgressCallback none;
  ProgressMeter quiet(none, "none", 10.0);
  quiet.update(5.0);
  quiet.finish();
}

TEST(Progress, RefinementReportsInsertionsAndKeepsItsResult) {
  const intrinsic::TriangleMesh mesh = intrinsic::icosphere(6);
  intrinsic::RefineOptions o;
  o.max_area = 4.0 * 3.14159 / 3000.0;  // about 3000 triangles: a few hundred insertions
  intrinsic::IntrinsicTriangulation plain = test::make_tri(mesh);
  const intrinsic::RefineReport without = intrinsic::delaunay_refine(plain, o);
  Recorder r;
  o.on_progress = r.callback();
  intrinsic::IntrinsicTriangulation tri = test::make_tri(mesh);
  const intrinsic::RefineReport with = intrinsic::delaunay_refine(tri, o);
  EXPECT_EQ(with.insertions, without.insertions);
  EXPECT_EQ(tri.n_vertices(), plain.n_vertices());
  ASSERT_GT(with.insertions, 100);
  const std::vector<double> f = r.stage("refine");
  expect_well_formed(f, "refine");
  EXPECT_GT(f.size(), 20u);  // reported along the way, not only 0 and 1
  // also through signposts
  Recorder s;
  o.on_progress = s.callback();
  intrinsic::SignpostTriangulation st(mesh.faces, mesh.positions);
  EXPECT_EQ(intrinsic::delaunay_refine(st, o).insertions, without.insertions);
  expect_well_formed(s.stage("refine"), "refine (signposts)");
}

TEST(Progress, BatchedHeatDistancesReportPerBlock) {
  const auto tri = test::make_tri(intrinsic::grid(30, 30));
  std::vector<Index> sources;
  for (Index v = 0; v < 130; ++v) sources.push_back(v * 7);  // 130 sources: 5 blocks of ≤ 32
  const solvers::HeatDistanceSolver plain(tri);
  const Eigen::MatrixXd d0 = plain.compute_distances(sources);
  Recorder r;
  const solvers::HeatDistanceSolver solver(tri);
  const Eigen::MatrixXd d = solver.compute_distances(sources, nullptr, r.callback());
  EXPECT_EQ((d - d0).cwiseAbs().maxCoeff(), 0.0);
  const std::vector<double> f = r.stage("heat distances");
  expect_well_formed(f, "heat distances");
  EXPECT_GE(f.size(), 5u);  // 0, after blocks 1..4, 1
  // with path bounds (the default) the bounds take the second half of the bar
  const double total = solvers::HeatDistanceOptions{}.path_bounds ? 260.0 : 130.0;
  EXPECT_NEAR(f[1], 32.0 / total, 1e-12);
}

TEST(Progress, SingleSourceGeodesicsReportAcceptedVertices) {
  const intrinsic::TriangleMesh m = intrinsic::grid(12, 12);
  intrinsic::SignpostTriangulation st0(m.faces, m.positions);
  const auto g0 = intrinsic::single_source_geodesics(st0, 5);
  Recorder r;
  intrinsic::SignpostTriangulation st(m.faces, m.positions);
  const auto g = intrinsic::single_source_geodesics(st, 5, {}, r.callback());
  EXPECT_EQ((g.length - g0.length).cwiseAbs().maxCoeff(), 0.0);
  const std::vector<double> f = r.stage("single-source geodesics");
  expect_well_formed(f, "single-source geodesics");
  EXPECT_GT(f.size(), 50u);  // 169 vertices, one report each
}

TEST(Progress, EigenpairsReportSolves) {
  const auto tri = test::make_tri(intrinsic::icosphere(8));
  const solvers::EigenPairs e0 = solvers::eigenpairs(tri, 10);
  Recorder r;
  solvers::EigenOptions o;
  o.on_progress = r.callback();
  const solvers::EigenPairs e = solvers::eigenpairs(tri, 10, o);
  EXPECT_EQ((e.values - e0.values).cwiseAbs().maxCoeff(), 0.0);
  const std::vector<double> f = r.stage("eigenpairs");
  expect_well_formed(f, "eigenpairs");
  EXPECT_GT(f.size(), 10u);
}

TEST(Progress, ReadAndPipelineReportTheirStagesInOrder) {
  const intrinsic::TriangleMesh mesh = intrinsic::icosphere(40);  // 32k faces: a 0.8 MB PLY
  const std::filesystem::path path = std::filesystem::temp_directory_path() /
                                     ("ifem_progress_test_" + std::to_string(::getpid()) + ".ply");
  io::write_ply(path.string(), mesh.positions, mesh.faces, {}, false);
  Recorder read;
  const io::SurfaceInput in = io::read_surface(path.string(), read.callback());
  EXPECT_EQ(in.positions.rows(), mesh.positions.rows());
  const std::vector<double> f = read.stage("read");
  expect_well_formed(f, "read");
  EXPECT_GT(f.size(), 3u);  // more than one 64 KiB chunk
  // OBJ: "read", then "parse" (text parsing is the long part of a large load)
  const std::filesystem::path obj = std::filesystem::path(path).replace_extension(".obj");
  {
    std::ofstream o(obj);
    for (Eigen::Index v = 0; v < mesh.positions.rows(); ++v) {
      o << "v " << mesh.positions(v, 0) << ' ' << mesh.positions(v, 1) << ' '
        << mesh.positions(v, 2) << '\n';
    }
    for (const Triangle& t : mesh.faces) {
      o << "f " << t[0] + 1 << ' ' << t[1] + 1 << ' ' << t[2] + 1 << '\n';
    }
  }
  Recorder text;
  EXPECT_EQ(io::read_surface(obj.string(), text.callback()).triangles.size(), mesh.faces.size());
  std::filesystem::remove(obj);
  expect_well_formed(text.stage("read"), "read (obj)");
  const std::vector<double> parse = text.stage("parse");
  expect_well_formed(parse, "parse (obj)");
  EXPECT_GT(parse.size(), 100u);
  EXPECT_EQ(text.calls.front().second, "read");
  Recorder all;
  solvers::PrepareOptions po;
  po.on_progress = all.callback();
  po.refine = solvers::SurfaceRefineOptions{};
  po.refine->resolution = 1.0;
  const solvers::PreparedSurface s = solvers::load_surface(path.string(), po);
  std::filesystem::remove(path);
  EXPECT_TRUE(s.refined);
  expect_well_formed(all.stage("read"), "read (pipeline)");
  expect_well_formed(all.stage("refine"), "refine (pipeline)");
  ASSERT_FALSE(all.calls.empty());
  EXPECT_EQ(all.calls.front().second, "read");
  EXPECT_EQ(all.calls.back().second, "refine");
}

}  // namespace
}  // namespace ifem
