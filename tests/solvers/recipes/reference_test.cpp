// Heat distance against the exact geodesic distances in tests/data/reference (always) and
// ../shared/data/reference (MANIFEST.md; when present), with CGAL's heat method as the baseline
// to match or beat. Each test fails when it checked no reference.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iterator>
#include <map>
#include <optional>
#include <regex>
#include <set>
#include <string>

#include "intrinsic/core/errors.h"
#include "intrinsic/io/mesh_io.h"
#include "intrinsic/surface/build_surface.h"
#include "intrinsic/surface/face_analysis.h"
#include "solvers/recipes/pipeline.h"
#include "solvers/scalar/heat_distance.h"
#include "solvers/test_util.h"

namespace ifem::solvers {
namespace {

namespace fs = std::filesystem;
using test::Rel;
using test::relative_error;

// One reference file <stem>.src<N>.exact.txt of ../shared/data/reference: its mesh's stem and
// the source vertex N.
struct Reference {
  std::string stem;
  std::string src_text;  // N as in the file name
  Index src = 0;
};

// The reference that `p` names; nothing for other files.
std::optional<Reference> parse_reference(const fs::path& p) {
  static const std::regex name(R"((.+)\.src(\d+)\.exact\.txt)");
  std::smatch mt;
  const std::string fname = p.filename().string();
  if (!std::regex_match(fname, mt, name)) return std::nullopt;
  return Reference{mt[1].str(), mt[2].str(), Index(std::stol(mt[2]))};
}

// The mesh of ../shared/data/meshes with this stem; empty when there is none.
fs::path shared_mesh(const std::string& stem) {
  fs::path mesh;
  for (const auto& m : test::shared_files("meshes")) {
    if (m.stem().string() == stem) mesh = m;
  }
  return mesh;
}

// CGAL's heat-method distances next to the exact reference `p`.
Eigen::VectorXd read_cgal_heat(const fs::path& p, const Reference& ref) {
  return io::read_values(
      (p.parent_path() / (ref.stem + ".src" + ref.src_text + ".cgal-heat.txt")).string());
}

// Per mesh and source, the mean relative error of `ifem distance` (the library pipeline:
// prepare_surface + geodesic_distance, whose heat distance is clamped into path bounds,
// docs/decisions.md D-141) is at most CGAL's heat method's on the same reference: on every
// reference, no slack (the sliver meshes, where intrinsic Delaunay matters, and the clean ones).
// Relative to the baseline, not pinned at today's figures. conrod's reference lives on CGAL's
// cut surface (MANIFEST.md, "repaired"), where a nonmanifold-aware distance may be shorter.
TEST(SolversReference, HeatDistanceVsExact) {
  const bool run_large = std::getenv("IFEM_TEST_LARGE") != nullptr;
  std::printf("%-22s %6s %8s | %9s %9s | %9s %9s | %9s | %s\n", "mesh", "src", "V", "mean_rel",
              "max_rel", "cgal_mean", "cgal_max", "h=IDT", "note");
  int bundled = 0, shared = 0;
  for (const test::ReferenceCase& ref : test::reference_cases()) {
    const std::string& stem = ref.stem;
    const Index src = Index(ref.src);
    if (stem == "igea_268k" && !run_large) {
      std::printf("%-22s %6d   skipped (large; set IFEM_TEST_LARGE=1)\n", stem.c_str(), src);
      continue;
    }
    ASSERT_FALSE(ref.mesh.empty()) << ref.exact << ": no mesh " << stem;
    if (test::skip_in_quick_run(ref.mesh)) {
      std::printf("%-22s %6d   skipped (large; IFEM_TEST_QUICK)\n", stem.c_str(), src);
      continue;
    }
    const io::SurfaceInput in = io::read_mesh(ref.mesh.string());
    const Eigen::VectorXd exact = io::read_values(ref.exact.string());
    const Eigen::VectorXd cgal = io::read_values(ref.cgal_heat.string());
    ASSERT_EQ(cgal.size(), exact.size()) << ref.cgal_heat;
    ASSERT_EQ(exact.size(), in.positions.rows());
    const PreparedSurface s = prepare_surface(in);
    const intrinsic::IntrinsicTriangulation& tri = s.tri;
    const std::string note = s.path == intrinsic::SurfacePath::kTufted ? "tufted" : "";
    const Eigen::VectorXd d = geodesic_distance(s, {src});
    HeatDistanceOptions idt;
    idt.step_length = HeatDistanceOptions::StepLength::kIntrinsicDelaunay;
    idt.intrinsic_delaunay = false;
    idt.boundary_vertices = s.boundary_vertex;
    const Eigen::VectorXd d_idt = HeatDistanceSolver(tri, idt).compute_distance({src});
    const Rel r = relative_error(d, exact), rc = relative_error(cgal, exact),
              ri = relative_error(d_idt, exact);
    std::printf("%-22s %6d %8ld | %9.4f %9.3f | %9.4f %9.3f | %9.4f | %s\n", stem.c_str(), src,
                long(exact.size()), r.mean, r.max, rc.mean, rc.max, ri.mean, note.c_str());
    // unreachable in the reference ⇒ unreachable here (tufted meshes may reach more)
    for (Eigen::Index v = 0; v < exact.size(); ++v) {
      if (std::isfinite(exact[v])) {
        ASSERT_TRUE(std::isfinite(d[v])) << stem << " vertex " << v;
      }
    }
    EXPECT_LE(r.mean, rc.mean) << stem << " src " << src << ": above CGAL's heat method";
    ++(ref.bundled ? bundled : shared);
  }
  test::expect_references_checked(bundled, shared);
}

// With HeatDistanceOptions::Precision::kMixed the queries read the Poisson factor as floats: on
// every reference mesh (igea included: its heat decays below float's range, the case that
// keeps the heat factor double) the distances stay within 1e-5 relative of the double-precision
// path, and the error against the exact distances is the same to 1e-6.
TEST(SolversReference, MixedPrecisionMatchesDouble) {
  int bundled = 0, shared = 0;
  std::map<std::string, PreparedSurface> prepared;
  for (const test::ReferenceCase& c : test::reference_cases()) {
    const std::optional<Reference> ref = parse_reference(c.exact);
    ASSERT_TRUE(ref.has_value()) << c.exact;
    const fs::path& mesh = c.mesh;
    ASSERT_FALSE(mesh.empty()) << ref->stem;
    if (test::skip_in_quick_run(mesh)) continue;
    const Eigen::VectorXd exact = io::read_values(c.exact.string());
    // each mesh has references from several sources: prepared once
    auto found = prepared.find(mesh.string());
    if (found == prepared.end()) {
      found = prepared.emplace(mesh.string(), prepare_surface(io::read_mesh(mesh.string()))).first;
    }
    const PreparedSurface& s = found->second;
    DistanceOptions mixed;
    mixed.precision = HeatDistanceOptions::Precision::kMixed;
    const Eigen::VectorXd d = geodesic_distance(s, {ref->src}, mixed);
    const Eigen::VectorXd d2 = geodesic_distance(s, {ref->src});
    double diff = 0.0, dmax = 0.0;
    for (Eigen::Index v = 0; v < d.size(); ++v) {
      if (!std::isfinite(d2[v])) {
        EXPECT_EQ(d[v], d2[v]) << ref->stem << " vertex " << v;
        continue;
      }
      diff = std::max(diff, std::abs(d[v] - d2[v]));
      dmax = std::max(dmax, d2[v]);
    }
    std::printf("%-22s %6d: max |mixed − double| / max d = %.2e\n", ref->stem.c_str(), ref->src,
                diff / dmax);
    EXPECT_LT(diff, 1e-5 * dmax) << ref->stem << " src " << ref->src;
    EXPECT_NEAR(relative_error(d, exact).mean, relative_error(d2, exact).mean, 1e-6) << ref->stem;
    ++(c.bundled ? bundled : shared);
  }
  test::expect_references_checked(bundled, shared);
}

// Sweep of step-length rules (issue #3), all through build_surface like the CLI, and the reason
// the default (the input's mean edge) stays (docs/decisions.md, "Heat step length"): none of
// the other rules is at or below CGAL's error on every reference, each is above it somewhere.
// Not run by default (~80 s); run with --gtest_also_run_disabled_tests
// --gtest_filter=*StepLengthSweep*.
TEST(SolversReference, DISABLED_StepLengthSweep) {
  IFEM_REQUIRE_SHARED_DATA();
  const char* const rules[] = {"idt", "area", "median", "max", "sqrtio", "in*1.1"};
  bool above_cgal[std::size(rules)] = {};
  int checked = 0;
  std::printf("%-20s %6s | %7s | %7s %7s %7s %7s %7s %7s %7s | h_in h_idt h_area h_med\n", "mesh",
              "src", "cgal", "input", "idt", "area", "median", "max", "sqrtio", "in*1.1");
  for (const fs::path& p : test::shared_files("reference")) {
    const std::optional<Reference> ref = parse_reference(p);
    if (!ref) continue;
    const std::string& stem = ref->stem;
    const Index src = ref->src;
    if (stem == "igea_268k" && !std::getenv("IFEM_TEST_LARGE")) continue;
    const fs::path mesh = shared_mesh(stem);
    const io::SurfaceInput in = io::read_mesh(mesh.string());
    const Eigen::VectorXd exact = io::read_values(p.string());
    const Eigen::VectorXd cgal = read_cgal_heat(p, *ref);
    intrinsic::SurfaceTriangulation s = intrinsic::build_surface(in.triangles, in.positions);
    const double h_in = intrinsic::mean_side_length(in.triangles, in.positions);
    const double h_idt = mean_edge_length(s.tri);
    double area = 0;
    std::vector<double> el;
    for (const auto& t : in.triangles) {
      Eigen::Vector3d a = in.positions.row(t[0]), b = in.positions.row(t[1]),
                      c = in.positions.row(t[2]);
      area += 0.5 * (b - a).cross(c - a).norm();
      for (int i = 0; i < 3; ++i)
        el.push_back((in.positions.row(t[i]) - in.positions.row(t[(i + 1) % 3])).norm());
    }
    std::nth_element(el.begin(), el.begin() + el.size() / 2, el.end());
    const double h_med = el[el.size() / 2];
    const double h_area = std::sqrt(4.0 * area / (std::sqrt(3.0) * double(in.triangles.size())));
    auto run = [&](double h) {
      HeatDistanceOptions opt;
      opt.mean_edge_length = h;
      opt.intrinsic_delaunay = false;
      opt.boundary_vertices = s.boundary_vertex;
      return relative_error(HeatDistanceSolver(s.tri, opt).compute_distance({src}), exact).mean;
    };
    const double ec = relative_error(cgal, exact).mean;
    const double e[] = {run(h_idt),
                        run(h_area),
                        run(h_med),
                        run(std::max(h_in, h_idt)),
                        run(std::sqrt(h_in * h_idt)),
                        run(1.1 * h_in)};
    for (std::size_t r = 0; r < std::size(rules); ++r) above_cgal[r] |= e[r] > ec;
    std::printf(
        "%-20s %6d | %7.4f | %7.4f %7.4f %7.4f %7.4f %7.4f %7.4f %7.4f | %.4g %.4g %.4g %.4g %s\n",
        stem.c_str(), src, ec, run(h_in), e[0], e[1], e[2], e[3], e[4], e[5], h_in, h_idt, h_area,
        h_med, s.path_name());
    std::fflush(stdout);
    ++checked;
  }
  EXPECT_GT(checked, 0);
  for (std::size_t r = 0; r < std::size(rules); ++r) {
    EXPECT_TRUE(above_cgal[r]) << "step-length rule " << rules[r]
                               << " is at or below CGAL's error on every reference: the default "
                                  "step length (docs/decisions.md) is worth revisiting";
  }
}

// Boundary condition of the heat step (average vs Neumann) on the meshes with boundary, and the
// tufted vs manifold path, and why the default (the average of the two) stays
// (docs/decisions.md, "Heat step length"): Neumann alone trades one mesh for another, worse
// than the average on at least one of these. Not run by default.
TEST(SolversReference, DISABLED_BoundarySweep) {
  IFEM_REQUIRE_SHARED_DATA();
  bool neumann_worse = false;
  int checked = 0;
  for (auto [stem, src] : std::vector<std::pair<std::string, Index>>{{"stanford_bunny_scan", 11899},
                                                                     {"stanford_bunny_scan", 0},
                                                                     {"camelhead", 0},
                                                                     {"camelhead", 9741}}) {
    const fs::path mesh = shared_mesh(stem);
    const io::SurfaceInput in = io::read_mesh(mesh.string());
    fs::path ref = mesh.parent_path().parent_path() / "reference";
    const Eigen::VectorXd exact =
        io::read_values((ref / (stem + ".src" + std::to_string(src) + ".exact.txt")).string());
    intrinsic::SurfaceTriangulation s = intrinsic::build_surface(in.triangles, in.positions);
    auto tri = intrinsic::IntrinsicTriangulation::from_positions(in.triangles, in.positions);
    tri.mollify();
    tri.flip_to_delaunay();
    const double h_in = intrinsic::mean_side_length(in.triangles, in.positions);
    auto run = [&](const intrinsic::IntrinsicTriangulation& t, bool bnd,
                   HeatDistanceOptions::Boundary b) {
      HeatDistanceOptions opt;
      opt.mean_edge_length = h_in;
      opt.intrinsic_delaunay = false;
      if (bnd) opt.boundary_vertices = s.boundary_vertex;
      opt.boundary = b;
      return relative_error(HeatDistanceSolver(t, opt).compute_distance({src}), exact).mean;
    };
    using B = HeatDistanceOptions::Boundary;
    const double avg = run(s.tri, true, B::kAverage), neu = run(s.tri, true, B::kNeumann);
    neumann_worse |= neu > avg;
    std::printf(
        "%s %d path %s: tufted avg %.4f neu %.4f | tufted-nobnd %.4f | manifold avg %.4f neu %.4f "
        "negw %d\n",
        stem.c_str(), src, s.path_name(), avg, neu, run(s.tri, false, B::kAverage),
        run(tri, false, B::kAverage), run(tri, false, B::kNeumann),
        intrinsic::negative_boundary_weights(tri));
    ++checked;
  }
  EXPECT_EQ(checked, 4);
  EXPECT_TRUE(neumann_worse) << "Neumann alone is at least as good as the average on every mesh "
                                "with boundary: the default boundary rule is worth revisiting";
}

}  // namespace
}  // namespace ifem::solvers
