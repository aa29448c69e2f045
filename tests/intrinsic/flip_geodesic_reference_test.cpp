// FlipOut geodesics against the exact polyhedral geodesic distances of tests/data/reference
// (always) and ../shared/data/reference (MANIFEST.md; when present): every geodesic FlipOut returns
// is at least as long as the shortest one (to round-off: a geodesic is only locally shortest),
// equal to it for a fraction of the pairs that is printed per mesh, and on average within 1% of it.
// Where it is longer, the geodesic passes a saddle vertex (total angle > 2π, both wedges ≥ π) that
// the Dijkstra start path wrapped the other way round than the shortest geodesic does: a true
// geodesic, in another class. Floors below are from this measurement (BENCHMARKS.md, "FlipOut
// accuracy"), under the lowest value seen, so a regression in the shortening shows.
// Single-source geodesics (unfolded order, other starts for blocked and near-tie vertices,
// docs/decisions.md D-144) are the shortest on 97.4–100% of the vertices of every reference up to
// 12k vertices (mean excess ≤ 8.8e-6): asserted ≥ 95%, mean ≤ 2e-5, worst ≤ 1%. Above that
// (IFEM_TEST_LARGE) armadillo, igea and the bunny scan reach 94.6–98%, so 90% is asserted there,
// and rocketship (slivers: 40% and 77%) keeps the old floors.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <string>

#include "helpers.h"
#include "intrinsic/core/errors.h"
#include "intrinsic/geodesic/flip_geodesic.h"
#include "intrinsic/io/mesh_io.h"

namespace ifem::intrinsic {
namespace {

namespace fs = std::filesystem;

struct Tally {
  int checked = 0, equal = 0;
  double sum_excess = 0.0;
  double worst_excess = 0.0;   // max (length − exact) / exact
  double worst_deficit = 0.0;  // max (exact − length) / exact: must stay at round-off
  void add(double length, double exact) {
    ++checked;
    const double rel = (length - exact) / exact;
    if (std::abs(rel) <= 1e-6) ++equal;
    worst_excess = std::max(worst_excess, rel);
    sum_excess += std::max(rel, 0.0);
    worst_deficit = std::max(worst_deficit, -rel);
  }
  // nothing checked is no evidence: 0 (below every floor), and the test asserts checked > 0
  double fraction() const { return checked ? double(equal) / checked : 0.0; }
  double mean_excess() const { return checked ? sum_excess / checked : 1.0; }
};

// The exact files of meshes FlipOut accepts (edge-manifold, orientable), small enough for a
// quick run.
TEST(FlipGeodesicReference, LengthsAgainstExactGeodesics) {
  std::printf("%-24s %6s %6s | %-33s | %-33s\n", "mesh", "src", "V",
              "single-source: equal, mean, worst", "two-point: equal, mean, worst");
  int bundled = 0, shared = 0;
  for (const test::ReferenceCase& ref : test::reference_cases()) {
    ASSERT_FALSE(ref.mesh.empty()) << ref.exact << ": no mesh " << ref.stem;
    const std::string fname = ref.exact.filename().string();
    const io::SurfaceInput in = io::read_mesh(ref.mesh.string());
    if (in.positions.rows() > 12000 && std::getenv("IFEM_TEST_LARGE") == nullptr) {
      std::printf("%-24s %6s   skipped (large; set IFEM_TEST_LARGE=1)\n", ref.stem.c_str(),
                  ref.src_text.c_str());
      continue;
    }
    const Eigen::VectorXd exact = io::read_values(ref.exact.string());
    ASSERT_EQ(exact.size(), in.positions.rows()) << fname;
    const Index src = static_cast<Index>(ref.src);
    std::unique_ptr<SignpostTriangulation> st;
    try {
      st = std::make_unique<SignpostTriangulation>(in.triangles, in.positions, 0.0);
    } catch (const NonManifoldInput&) {
      std::printf("%-24s %6d   refused (nonmanifold / non-orientable): FlipOut needs a manifold\n",
                  ref.stem.c_str(), int(src));
      continue;
    }
    const SingleSourceGeodesics g = single_source_geodesics(*st, src);
    Tally ss, tp;
    const Index nv = static_cast<Index>(exact.size());
    for (Index v = 0; v < nv; ++v) {
      if (v == src || !std::isfinite(exact[v]) || exact[v] <= 0.0) continue;
      ss.add(g.length[v], exact[v]);
    }
    SignpostTriangulation fresh(in.triangles, in.positions, 0.0);
    for (Index k = 1; k <= 40; ++k) {  // two-point paths to 40 spread-out reachable vertices
      const Index v = (k * 7919) % nv;
      if (v == src || !std::isfinite(exact[v]) || exact[v] <= 0.0) continue;
      SignpostTriangulation s2 = fresh;
      EdgePath path = shortest_edge_path(s2, src, v);
      tp.add(shorten(s2, path).final_length, exact[v]);
    }
    std::printf("%-24s %6d %6d | %5.1f%% %8.1e %8.1e (%5d) | %5.1f%% %8.1e %8.1e (%3d)\n",
                ref.stem.c_str(), int(src), int(nv), 100 * ss.fraction(), ss.mean_excess(),
                ss.worst_excess, ss.checked, 100 * tp.fraction(), tp.mean_excess(), tp.worst_excess,
                tp.checked);
    EXPECT_GT(ss.checked, nv / 2) << fname;  // most vertices reachable on every reference mesh
    EXPECT_GE(tp.checked, 30) << fname;
    EXPECT_LE(ss.worst_deficit, 1e-9) << fname;  // never shorter than the shortest
    EXPECT_LE(tp.worst_deficit, 1e-9) << fname;
    EXPECT_LE(ss.mean_excess(), 0.01) << fname;
    EXPECT_LE(tp.mean_excess(), 0.01) << fname;
    const bool large = in.positions.rows() > 12000;
    const bool slivers = ref.stem == "rocketship";
    EXPECT_GE(ss.fraction(), slivers ? 0.35 : large ? 0.9 : 0.95) << fname;
    if (!slivers) {
      EXPECT_LE(ss.mean_excess(), 2e-5) << fname;
      EXPECT_LE(ss.worst_excess, 0.01) << fname;
    }
    EXPECT_GE(tp.fraction(), 0.3) << fname;
    ++(ref.bundled ? bundled : shared);
  }
  std::printf("%d bundled and %d shared reference files checked\n", bundled, shared);
  test::expect_references_checked(bundled, shared);
}

}  // namespace
}  // namespace ifem::intrinsic
