// Heat distance against the exact geodesic distances in ../shared/data/reference (MANIFEST.md),
// with CGAL's heat method as the baseline to match or beat.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <regex>

#include "intrinsic/errors.h"
#include "intrinsic/mesh_io.h"
#include "intrinsic/tufted_cover.h"
#include "solvers/heat_distance.h"
#include "test_util.h"

namespace ifem::solvers {
namespace {

namespace fs = std::filesystem;

struct Rel {
  double mean = 0, max = 0;
};

Rel relative_error(const Eigen::VectorXd& d, const Eigen::VectorXd& exact) {
  Rel r;
  double sum = 0;
  int n = 0;
  for (Eigen::Index v = 0; v < exact.size(); ++v) {
    if (!std::isfinite(exact[v]) || exact[v] <= 0) continue;
    const double e = std::abs(d[v] - exact[v]) / exact[v];
    sum += std::isfinite(e) ? e : 1e9;
    r.max = std::max(r.max, e);
    ++n;
  }
  r.mean = sum / std::max(n, 1);
  return r;
}

double mean_input_edge(const io::SurfaceInput& in) {
  double s = 0;
  long n = 0;
  for (const auto& t : in.triangles) {
    for (int i = 0; i < 3; ++i) {
      s += (in.positions.row(t[i]) - in.positions.row(t[(i + 1) % 3])).norm();
      ++n;
    }
  }
  return s / std::max(n, 1L);
}

// Per-mesh bound on the mean relative error: CGAL's figure (the issue's target) with a small
// slack for meshes where we measured the same; a factor-2 time-step or scale bug exceeds these.
TEST(SolversReference, HeatDistanceVsExact) {
  IFEM_REQUIRE_SHARED_DATA();
  const bool run_large = std::getenv("IFEM_TEST_LARGE") != nullptr;
  std::printf("%-22s %6s %8s | %9s %9s | %9s %9s | %9s | %s\n", "mesh", "src", "V", "mean_rel",
              "max_rel", "cgal_mean", "cgal_max", "h=IDT", "note");
  const std::regex name(R"((.+)\.src(\d+)\.exact\.txt)");
  int checked = 0;
  for (const fs::path& p : test::shared_files("reference")) {
    std::smatch mt;
    const std::string fname = p.filename().string();
    if (!std::regex_match(fname, mt, name)) continue;
    const std::string stem = mt[1];
    const Index src = Index(std::stol(mt[2]));
    if (stem == "igea_268k" && !run_large) {
      std::printf("%-22s %6d   skipped (large; set IFEM_TEST_LARGE=1)\n", stem.c_str(), src);
      continue;
    }
    fs::path mesh;
    for (const auto& m : test::shared_files("meshes")) {
      if (m.stem().string() == stem) mesh = m;
    }
    ASSERT_FALSE(mesh.empty()) << stem;
    const io::SurfaceInput in = io::read_mesh(mesh.string());
    const Eigen::VectorXd exact = io::read_values(p.string());
    const Eigen::VectorXd cgal =
        io::read_values((p.parent_path() / (stem + ".src" + mt[2].str() + ".cgal-heat.txt")).string());
    ASSERT_EQ(exact.size(), in.positions.rows());
    intrinsic::IntrinsicTriangulation tri;
    std::string note;
    try {
      tri = intrinsic::IntrinsicTriangulation::from_positions(in.triangles, in.positions);
    } catch (const NonManifoldInput&) {
      tri = intrinsic::tufted_cover(in.triangles, in.positions);
      note = "tufted";
    }
    tri.mollify(1e-5);
    tri.flip_to_delaunay();
    HeatDistanceOptions opt;
    opt.mean_edge_length = mean_input_edge(in);
    const Eigen::VectorXd d = HeatDistanceSolver(tri, opt).compute_distance({src});
    HeatDistanceOptions idt;
    idt.step_length = HeatDistanceOptions::StepLength::kIntrinsicDelaunay;
    const Eigen::VectorXd d_idt = HeatDistanceSolver(tri, idt).compute_distance({src});
    const Rel r = relative_error(d, exact), rc = relative_error(cgal, exact),
              ri = relative_error(d_idt, exact);
    std::printf("%-22s %6d %8ld | %9.4f %9.3f | %9.4f %9.3f | %9.4f | %s\n", stem.c_str(), src,
                long(exact.size()), r.mean, r.max, rc.mean, rc.max, ri.mean, note.c_str());
    // unreachable in the reference ⇒ unreachable here (tufted meshes may reach more)
    for (Eigen::Index v = 0; v < exact.size(); ++v) {
      if (std::isfinite(exact[v])) ASSERT_TRUE(std::isfinite(d[v])) << stem << " vertex " << v;
    }
    if (note == "tufted") {
      // repaired reference (cut surface): a nonmanifold-aware distance may be shorter
      EXPECT_LT(r.mean, std::max(0.25, 1.1 * rc.mean)) << stem;
    } else {
      EXPECT_LE(r.mean, 1.05 * rc.mean + 0.001) << stem << " src " << src;
    }
    ++checked;
  }
  EXPECT_GT(checked, 0);
}

}  // namespace
}  // namespace ifem::solvers
