#include "solvers/scalar/heat_distance.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#ifdef _OPENMP
#include <omp.h>
#endif

#include "fem/gradient.h"
#include "intrinsic/core/errors.h"
#include "solvers/scalar/heat_engine.h"
#include "test_util.h"

namespace ifem::solvers {
namespace {

// Sets OpenMP's thread count (the library's only threads) for a scope.
class OpenMpThreads {
 public:
  explicit OpenMpThreads(int threads) {
#ifdef _OPENMP
    saved_ = omp_get_max_threads();
    omp_set_num_threads(threads);
#else
    (void)threads;
#endif
  }
  ~OpenMpThreads() {
#ifdef _OPENMP
    omp_set_num_threads(saved_);
#endif
  }
  OpenMpThreads(const OpenMpThreads&) = delete;
  OpenMpThreads& operator=(const OpenMpThreads&) = delete;

 private:
  int saved_ = 1;
};

struct ErrorStats {
  double mean_rel = 0, max_rel = 0, linf_over_max = 0;
};

// relative errors against an exact distance over finite, non-source vertices
ErrorStats compare(const Eigen::VectorXd& d, const Eigen::VectorXd& exact) {
  ErrorStats s;
  double sum = 0, maxd = 0, maxabs = 0;
  int n = 0;
  for (Eigen::Index v = 0; v < d.size(); ++v) {
    if (!std::isfinite(exact[v])) continue;
    maxd = std::max(maxd, exact[v]);
    maxabs = std::max(maxabs, std::abs(d[v] - exact[v]));
    if (exact[v] <= 0) continue;
    const double r = std::abs(d[v] - exact[v]) / exact[v];
    sum += r;
    s.max_rel = std::max(s.max_rel, r);
    ++n;
  }
  s.mean_rel = sum / std::max(n, 1);
  s.linf_over_max = maxabs / maxd;
  return s;
}

Eigen::VectorXd euclidean(const intrinsic::TriangleMesh& m, Index src) {
  Eigen::VectorXd d(m.positions.rows());
  for (Eigen::Index v = 0; v < d.size(); ++v)
    d[v] = (m.positions.row(v) - m.positions.row(src)).norm();
  return d;
}

TEST(SolversHeatDistance, FlatPlaneMatchesEuclidean) {
  const auto m = test::jittered(intrinsic::grid(60, 60), 0.004);
  const auto tri = test::make_tri(m, false);
  const Index src = 30 * 61 + 30;
  const Eigen::VectorXd d = heat_distance(tri, {src});
  const ErrorStats s = compare(d, euclidean(m, src));
  std::printf("plane: mean_rel %.4f max_rel %.4f linf/max %.4f\n", s.mean_rel, s.max_rel,
              s.linf_over_max);
  EXPECT_EQ(d[src], 0.0);
  EXPECT_LT(s.mean_rel, 0.02);
  EXPECT_LT(s.linf_over_max, 0.02);
}

// The correction step φ ← ∫ ∇φ/|∇φ| removes much of a small time step's error (t = h²/4, as
// `distance --refine` uses): against the exact Euclidean distance on a jittered flat grid,
// t = h²/4 plus one step must beat t = h²/4 alone clearly. (On a flat domain the heat kernel's
// gradient is exactly radial, so a larger t is better still there: measured 0.0067 at t = h²,
// 0.0037 at 2h²; the small t pays off on curved surfaces, refine_accuracy_test.cpp.) Sources
// stay exactly 0 with several of them.
TEST(SolversHeatDistance, CorrectionStepImprovesSmallTimeStep) {
  const auto m = test::jittered(intrinsic::grid(60, 60), 0.004);
  const auto tri = test::make_tri(m, false);
  const Index src = 30 * 61 + 30;
  const Eigen::VectorXd exact = euclidean(m, src);
  HeatDistanceOptions paper, small, corrected;
  small.time_factor = corrected.time_factor = 0.25;
  corrected.correction_steps = 1;
  const double e_paper = compare(heat_distance(tri, {src}, paper), exact).mean_rel;
  const double e_small = compare(heat_distance(tri, {src}, small), exact).mean_rel;
  const double e_corr = compare(heat_distance(tri, {src}, corrected), exact).mean_rel;
  std::printf("plane: mean_rel t=h² %.4f, t=h²/4 %.4f, t=h²/4 + 1 correction %.4f\n", e_paper,
              e_small, e_corr);
  EXPECT_LT(e_corr, 0.7 * e_small);
  EXPECT_LT(e_corr, 2.5 * e_paper);
  const std::vector<Index> several = {src, 10 * 61 + 10, 50 * 61 + 45};
  const Eigen::VectorXd d = heat_distance(tri, several, corrected);
  for (const Index v : several) EXPECT_EQ(d[v], 0.0);
  EXPECT_GE(d.minCoeff(), 0.0);
  HeatDistanceOptions bad;
  bad.correction_steps = -1;
  EXPECT_THROW(heat_distance(tri, {src}, bad), InvalidInput);
}

TEST(SolversHeatDistance, MultiSourceIsMinOfSingleSources) {
  const auto m = intrinsic::icosphere(12);
  const auto tri = test::make_tri(m);
  const HeatDistanceSolver solver(tri);
  const std::vector<Index> src = {0, 5, 400, 1000};
  Eigen::VectorXd mn = Eigen::VectorXd::Constant(tri.n_vertices(), 1e300);
  for (const Index s : src) mn = mn.cwiseMin(solver.compute_distance({s}));
  HeatDistanceReport rep;
  const Eigen::VectorXd d = solver.compute_distance(src, &rep);
  EXPECT_EQ(rep.constraints, 3);
  for (const Index s : src) EXPECT_EQ(d[s], 0.0);
  EXPECT_GE(d.minCoeff(), 0.0);
  // The multi-source heat field blends directions near the Voronoi boundaries, so the result
  // is not exactly the min (measured: mean 0.036, max 0.13 on this unit sphere, the same with
  // Dirichlet conditions at the sources); bound it well below the sphere's scale (π).
  EXPECT_LT((d - mn).cwiseAbs().maxCoeff(), 0.2);
  EXPECT_LT((d - mn).cwiseAbs().mean(), 0.05);
}

TEST(SolversHeatDistance, SurroundedSourceIsNotBiased) {
  // a source ring around a centre source on a flat plane: every source stays at 0 and the
  // centre's neighbourhood sees the distance to the centre, not a lifted value
  const auto m = intrinsic::grid(40, 40);
  const auto tri = test::make_tri(m);
  const Index centre = 20 * 41 + 20;
  std::vector<Index> src = {centre};
  for (int k = 0; k < 16; ++k) {
    const double a = 2 * 3.14159265 * k / 16;
    const int i = int(std::lround(20 + 12 * std::cos(a))),
              j = int(std::lround(20 + 12 * std::sin(a)));
    src.push_back(j * 41 + i);
  }
  const Eigen::VectorXd d = heat_distance(tri, src);
  for (const Index s : src) EXPECT_EQ(d[s], 0.0);
  const double h = 1.0 / 40;
  EXPECT_NEAR(d[centre + 2], 2 * h, 0.3 * h);
  EXPECT_NEAR(d[centre + 2 * 41], 2 * h, 0.3 * h);
}

TEST(SolversHeatDistance, OtherComponentAndUnreferencedAreInfinite) {
  const auto one = intrinsic::icosphere(6);
  const auto m = test::two_copies(one, 3.0, 1);
  const auto tri = test::make_tri(m);
  const Index n = Index(one.positions.rows());
  const Eigen::VectorXd d = heat_distance(tri, {3});
  for (Index v = 0; v < n; ++v) EXPECT_TRUE(std::isfinite(d[v]));
  for (Index v = n; v < 2 * n + 1; ++v) EXPECT_EQ(d[v], std::numeric_limits<double>::infinity());
  // a source in each component: both finite
  const Eigen::VectorXd d2 = heat_distance(tri, {3, n + 3});
  for (Index v = 0; v < 2 * n; ++v) EXPECT_TRUE(std::isfinite(d2[v]));
  EXPECT_NEAR(d2[n + 7], d[7], 1e-9);  // the copies are identical
}

TEST(SolversHeatDistance, SurfacePointSources) {
  const auto m = test::jittered(intrinsic::grid(40, 40), 0.002);
  const auto tri = test::make_tri(m, false);  // not flipped: face ids are the input's
  const HeatDistanceSolver solver(tri);
  // a point at the centroid of the face containing (0.5, 0.5)-ish
  const Index f = 2 * (20 * 40 + 20);
  SurfacePoint p;
  p.face = f;
  p.bary = Eigen::Vector3d(1.0 / 3, 1.0 / 3, 1.0 / 3);
  Eigen::RowVector3d x = Eigen::RowVector3d::Zero();
  for (int i = 0; i < 3; ++i) x += m.positions.row(solver.triangulation().tail(3 * f + i)) / 3.0;
  const Eigen::VectorXd d = solver.compute_distance_from_points(std::vector<SurfacePoint>{p});
  Eigen::VectorXd exact(tri.n_vertices());
  for (Index v = 0; v < tri.n_vertices(); ++v) exact[v] = (m.positions.row(v) - x).norm();
  const ErrorStats s = compare(d, exact);
  EXPECT_LT(s.mean_rel, 0.08);  // relative errors are large right next to the point
  EXPECT_LT(s.linf_over_max, 0.05);
  // unbiased far from the point: the blend of φ's corner values at the point is Σ wᵢ|cᵢ − p|,
  // not 0 (shifting it to 0 once made every distance about 0.5·h too small)
  const double h = 1.0 / 40;
  double bias = 0.0;
  int far = 0;
  for (Index v = 0; v < tri.n_vertices(); ++v) {
    if (exact[v] > 0.25) bias += d[v] - exact[v], ++far;
  }
  EXPECT_LT(std::abs(bias / far), 0.1 * h);
  SurfacePoint bad = p;
  bad.bary = Eigen::Vector3d(0.5, 0.6, -0.1);
  EXPECT_THROW(solver.compute_distance_from_points(std::vector<SurfacePoint>{bad}), InvalidInput);
  bad.face = tri.n_faces();
  EXPECT_THROW(solver.compute_distance_from_points(std::vector<SurfacePoint>{bad}), InvalidInput);
}

TEST(SolversHeatDistance, LongStripUnderflowIsResolved) {
  // 4000 cells along a 400-long strip: the heat from one end underflows after ~700 edges
  const auto m = intrinsic::grid(4000, 3, 400.0, 0.3);
  const auto tri = test::make_tri(m);
  const Eigen::VectorXd exact = euclidean(m, 0);
  HeatDistanceOptions single;
  single.resolve_underflow = false;
  HeatDistanceReport rep1;
  const Eigen::VectorXd d1 = HeatDistanceSolver(tri, single).compute_distance({0}, &rep1);
  EXPECT_GT(rep1.unresolved_vertices, 1000);
  const ErrorStats s1 = compare(d1, exact);
  HeatDistanceReport rep;
  const Eigen::VectorXd d = HeatDistanceSolver(tri).compute_distance({0}, &rep);
  const ErrorStats s = compare(d, exact);
  std::printf(
      "strip: single stage mean_rel %.3g max_rel %.3g; %d stages: mean_rel %.3g "
      "max_rel %.3g linf/max %.3g\n",
      s1.mean_rel, s1.max_rel, rep.stages, s.mean_rel, s.max_rel, s.linf_over_max);
  EXPECT_GT(s1.mean_rel, 0.3);  // single stage is garbage far away
  EXPECT_GT(rep.stages, 2);
  EXPECT_TRUE(d.allFinite());
  EXPECT_LT(s.mean_rel, 0.01);
  EXPECT_LT(s.linf_over_max, 0.01);
}

// compute_distances(): column j equals compute_distance({sources[j]}) on every kind of mesh
// the block path must handle: boundary (two heat factors), two components plus an unreferenced
// vertex, one closed component (the blocks in the factor's order), correction steps, more
// sources than one block (40 > 32), repeats.
void expect_batch_equals_single(const intrinsic::IntrinsicTriangulation& tri,
                                const HeatDistanceOptions& opt, const std::vector<Index>& src) {
  const HeatDistanceSolver solver(tri, opt);
  std::vector<HeatDistanceReport> reps;
  const Eigen::MatrixXd D = solver.compute_distances(src, &reps);
  ASSERT_EQ(D.rows(), tri.n_vertices());
  ASSERT_EQ(D.cols(), Eigen::Index(src.size()));
  ASSERT_EQ(reps.size(), src.size());
  for (std::size_t j = 0; j < src.size(); ++j) {
    HeatDistanceReport rep;
    const Eigen::VectorXd d = solver.compute_distance({src[j]}, &rep);
    EXPECT_EQ(reps[j].stages, rep.stages) << "source " << j;
    EXPECT_EQ(reps[j].unresolved_vertices, rep.unresolved_vertices) << "source " << j;
    const double scale = d.array().isFinite().select(d, 0.0).maxCoeff();
    ASSERT_GT(scale, 0.0);
    for (Index v = 0; v < tri.n_vertices(); ++v) {
      const auto col = Eigen::Index(j);
      if (!std::isfinite(d[v])) {
        EXPECT_EQ(D(v, col), d[v]) << "vertex " << v << ", source " << j;
      } else {
        EXPECT_NEAR(D(v, col), d[v], 1e-12 * scale) << "vertex " << v << ", source " << j;
      }
    }
    EXPECT_EQ(D(src[j], Eigen::Index(j)), 0.0);
  }
}

TEST(SolversHeatDistance, BatchEqualsSingleSources) {
  // boundary: the mean of the Neumann and Dirichlet heat; 40 sources = two blocks; a repeat
  const auto grid = test::make_tri(test::jittered(intrinsic::grid(24, 24), 0.01));
  std::vector<Index> src;
  for (Index k = 0; k < 40; ++k) src.push_back((k * 97) % grid.n_vertices());
  src.push_back(src[3]);
  expect_batch_equals_single(grid, {}, src);
  HeatDistanceOptions corrected;  // the accurate mode's correction step
  corrected.correction_steps = 2;
  corrected.time_factor = 0.25;
  expect_batch_equals_single(grid, corrected, {0, 300, 601});
  // two components and an unreferenced vertex: inf outside the source's component
  const auto one = intrinsic::icosphere(6);
  const Index n = Index(one.positions.rows());
  expect_batch_equals_single(test::make_tri(test::two_copies(one, 3.0, 1)), {}, {3, n + 3, 7});
  // one closed component: blocks stay in the solves' own row order from the deltas to φ
  const auto closed = test::make_tri(test::jittered(intrinsic::icosphere(10), 0.02));
  std::vector<Index> spread;
  for (Index k = 0; k < 35; ++k) spread.push_back((k * 29) % closed.n_vertices());
  expect_batch_equals_single(closed, {}, spread);
}

TEST(SolversHeatDistance, BatchRecomputesUnderflowingSourcesAlone) {
  // a strip 1200 cells long: from an end the heat underflows ~700 cells away (multi-stage),
  // from the middle it does not; both kinds in one batch
  const auto m = intrinsic::grid(1200, 2, 120.0, 0.2);
  const auto tri = test::make_tri(m);
  expect_batch_equals_single(tri, {}, {0, 600, 1200});
  std::vector<HeatDistanceReport> reps;
  const Eigen::MatrixXd D = HeatDistanceSolver(tri).compute_distances({0, 600}, &reps);
  EXPECT_GT(reps[0].stages, 1);
  EXPECT_EQ(reps[1].stages, 1);
  const Eigen::VectorXd exact = euclidean(m, 0);
  EXPECT_LT(compare(D.col(0), exact).linf_over_max, 0.01);
  // a closed spindle as long and thin as the strip (no boundary: the row-major block path),
  // its vertices numbered ring by ring from the north pole: the heat from the north pole
  // underflows only in the second half of the numbering, from the south pole only in the first;
  // the block scans the two halves apart and must see both
  intrinsic::TriangleMesh spindle = intrinsic::uv_sphere(1200, 3);
  spindle.positions.leftCols(2) *= 0.1;
  spindle.positions.col(2) *= 60.0;
  const auto tall = test::make_tri(spindle);
  const Index south = tall.n_vertices() - 1;
  expect_batch_equals_single(tall, {}, {0, south});
  std::vector<HeatDistanceReport> tall_reps;
  HeatDistanceSolver(tall).compute_distances({0, south}, &tall_reps);
  EXPECT_GT(tall_reps[0].stages, 1);
  EXPECT_GT(tall_reps[1].stages, 1);
}

// Results do not depend on the thread count (OpenMP's, omp_set_num_threads): bitwise, for both
// precisions, single and batched queries, on a sphere large enough for the solve kernel's
// two-thread split (factors of ≥ 2M entries) and on a disk with boundary (two heat factors
// solved side by side).
TEST(SolversHeatDistance, ThreadCountDoesNotChangeTheBits) {
  using Precision = HeatDistanceOptions::Precision;
  const auto sphere = test::make_tri(intrinsic::icosphere(50));
  const auto disk = test::make_tri(test::jittered(intrinsic::grid(120, 120), 0.01));
  for (const auto* tri : {&sphere, &disk}) {
    for (const Precision precision : {Precision::kDouble, Precision::kMixed}) {
      HeatDistanceOptions o;
      o.precision = precision;
      Eigen::VectorXd d[2];
      Eigen::MatrixXd D[2];
      for (const int threads : {1, 2}) {
        const OpenMpThreads team(threads);
        const HeatDistanceSolver solver(*tri, o);
        d[threads - 1] = solver.compute_distance({5});
        D[threads - 1] = solver.compute_distances({5, 900, 17});
      }
      EXPECT_TRUE(d[0] == d[1]) << tri->n_vertices() << " vertices";
      EXPECT_TRUE(D[0] == D[1]);
      EXPECT_LT((D[0].col(0) - d[0]).cwiseAbs().maxCoeff(), 1e-9 * d[0].maxCoeff());
    }
  }
}

TEST(SolversHeatDistance, BatchRefusesBadSources) {
  const auto tri = test::make_tri(intrinsic::icosphere(3));
  const HeatDistanceSolver solver(tri);
  EXPECT_THROW(solver.compute_distances({}), InvalidInput);
  try {
    solver.compute_distances({0, 1, tri.n_vertices()});
    ADD_FAILURE() << "no throw";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("sources[2]"), std::string::npos) << e.what();
  }
  EXPECT_THROW(solver.compute_distances({-1}), InvalidInput);
}

TEST(SolversHeatDistance, ErrorPaths) {
  const auto tri = test::make_tri(test::two_copies(intrinsic::grid(3, 3), 3.0, 1));
  const HeatDistanceSolver solver(tri);
  EXPECT_THROW(solver.compute_distance(std::vector<Index>{}), InvalidInput);
  EXPECT_THROW(solver.compute_distance(std::vector<Index>{-1}), InvalidInput);
  EXPECT_THROW(solver.compute_distance(std::vector<Index>{tri.n_vertices()}), InvalidInput);
  EXPECT_THROW(solver.compute_distance(std::vector<Index>{tri.n_vertices() - 1}), InvalidInput);
  EXPECT_THROW(heat_distance(tri, {}), InvalidInput);
  HeatDistanceOptions bad;
  bad.time_factor = 0.0;
  EXPECT_THROW(HeatDistanceSolver(tri, bad), InvalidInput);
  EXPECT_THROW(HeatDistanceSolver(intrinsic::IntrinsicTriangulation()), InvalidInput);
}

TEST(SolversHeatDistance, FusedUnitGradientDivergenceMatchesComposition) {
  const auto tri = test::make_tri(intrinsic::icosphere(6));
  Eigen::VectorXd u(tri.n_vertices());
  for (Index v = 0; v < tri.n_vertices(); ++v) u[v] = std::exp(-0.01 * v) * 1e-200 + 1e-210 * v;
  std::vector<char> use(tri.n_faces(), 1);
  for (Index f = 0; f < tri.n_faces(); f += 3) use[f] = 0;
  Eigen::MatrixX2d X = fem::gradient(tri, u);
  for (Index f = 0; f < tri.n_faces(); ++f) {
    const double n = std::hypot(X(f, 0), X(f, 1));
    if (!use[f] || !(n > 0.0)) {
      X.row(f).setZero();
    } else {
      X.row(f) /= -n;
    }
  }
  const Eigen::VectorXd ref = fem::divergence(tri, X);
  const Eigen::VectorXd fused = divergence_of_unit_gradient(tri, u, &use);
  EXPECT_LT((fused - ref).cwiseAbs().maxCoeff(), 1e-14 * ref.cwiseAbs().maxCoeff());
  EXPECT_THROW(divergence_of_unit_gradient(tri, Eigen::VectorXd(3)), InvalidInput);
}

// The per-face layouts computed once (UnitGradientDivergence) give, for k fields at once, each
// field's own divergence: on a mesh above the parallel threshold (two halves of the faces for
// one field, columns split between threads for several), with a different face mask per column,
// a field underflowing to 1e-200 and a constant one (|∇u| = 0: no contribution).
TEST(SolversHeatDistance, UnitGradientDivergenceColumnsMatchSingleFields) {
  const auto tri = test::make_tri(intrinsic::icosphere(40));  // 32,000 faces
  const Index nv = tri.n_vertices(), nf = tri.n_faces();
  const UnitGradientDivergence div(tri);
  Eigen::MatrixXd U(nv, 4);
  for (Index v = 0; v < nv; ++v) {
    U(v, 0) = std::exp(-0.001 * v);
    U(v, 1) = 1e-200 * std::exp(-0.002 * ((v * 7919) % nv));
    U(v, 2) = 3.0;
    U(v, 3) = std::sin(0.01 * v);
  }
  std::vector<std::vector<char>> masks(4, std::vector<char>(std::size_t(nf), 1));
  for (Index f = 0; f < nf; f += 5) masks[1][std::size_t(f)] = 0;
  for (Index f = 0; f < nf / 2; ++f) masks[3][std::size_t(f)] = 0;
  const Eigen::MatrixXd D = div.apply_columns(U, masks);
  ASSERT_EQ(D.rows(), nv);
  ASSERT_EQ(D.cols(), 4);
  for (Eigen::Index j = 0; j < 4; ++j) {
    const Eigen::VectorXd single = div.apply(Eigen::VectorXd(U.col(j)), &masks[std::size_t(j)]);
    const double scale = std::max(single.cwiseAbs().maxCoeff(), 1e-300);
    EXPECT_LT((D.col(j) - single).cwiseAbs().maxCoeff(), 1e-14 * scale) << "column " << j;
  }
  EXPECT_EQ(D.col(2).cwiseAbs().maxCoeff(), 0.0);   // constant field: no direction anywhere
  EXPECT_GT(D.col(1).cwiseAbs().maxCoeff(), 1e-3);  // a unit field whatever the heat's scale
  // without masks: the free function, which builds the layouts itself
  const Eigen::MatrixXd all = divergence_of_unit_gradients(tri, U, {});
  EXPECT_TRUE(all == div.apply_columns(U));
  EXPECT_THROW(div.apply_columns(Eigen::MatrixXd(3, 2)), InvalidInput);
}

// apply_rows(): the same divergence as apply_columns() on the row-major layout, for every chunk
// width of its vector loops (8, 4, 2, 1 columns), with an underflowing field, a constant one and
// a field with a NaN; on two OpenMP threads and on one (k < 16 never splits), to the same bits.
TEST(SolversHeatDistance, UnitGradientDivergenceRowsMatchColumns) {
  using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  const auto tri = test::make_tri(intrinsic::icosphere(40));  // 32,000 faces
  const Index nv = tri.n_vertices();
  const UnitGradientDivergence div(tri);
  for (const int k : {1, 3, 8, 15, 16, 32, 39}) {
    Eigen::MatrixXd U(nv, k);
    for (Index v = 0; v < nv; ++v) {
      for (int j = 0; j < k; ++j) U(v, j) = std::exp(-0.001 * double((v * (j + 1)) % nv));
    }
    if (k > 1) U.col(1) *= 1e-200;
    if (k > 2) U.col(2).setConstant(3.0);
    if (k > 3) U(17, 3) = std::numeric_limits<double>::quiet_NaN();
    // column 0 times 2⁻¹⁰⁴⁰ (subnormal values and gradients: still a unit field) and times 2¹⁰⁰⁰
    // (exactly: the same unit gradients as column 0; no overflow in the normalization)
    if (k > 4) U.col(4) = std::ldexp(1.0, -1040) * U.col(0);
    if (k > 5) U.col(5) = std::ldexp(1.0, 1000) * U.col(0);
    const Eigen::MatrixXd expected = div.apply_columns(U);
    const RowMajor rows = U;
    RowMajor out(nv, k), one_thread(nv, k);
    out.setConstant(7.0);  // overwritten
    div.apply_rows(rows.data(), k, out.data());
    {
      const OpenMpThreads team(1);
      div.apply_rows(rows.data(), k, one_thread.data());
    }
    EXPECT_TRUE(one_thread == out) << "k = " << k << ": one thread and the team differ";
    for (int j = 0; j < k; ++j) {
      const double scale = std::max(expected.col(j).cwiseAbs().maxCoeff(), 1e-300);
      EXPECT_LT((out.col(j) - expected.col(j)).cwiseAbs().maxCoeff(), 1e-13 * scale)
          << "k = " << k << ", column " << j;
    }
    if (k > 2) {
      EXPECT_EQ(out.col(2).cwiseAbs().maxCoeff(), 0.0);
    }
    for (int j : {1, 4, 5}) {
      if (k > j) {
        EXPECT_GT(out.col(j).cwiseAbs().maxCoeff(), 1e-3) << "column " << j;
      }
    }
    if (k > 5) {
      EXPECT_LT((out.col(5) - out.col(0)).cwiseAbs().maxCoeff(),
                1e-13 * out.col(0).cwiseAbs().maxCoeff());
    }
    if (k > 3) {
      EXPECT_TRUE(out.col(3).allFinite());  // the NaN's faces add nothing
    }
  }
  double x = 0.0;
  EXPECT_THROW(div.apply_rows(&x, 0, &x), InvalidInput);
  EXPECT_THROW(div.apply_rows(&x, 1, &x, 0, 2), InvalidInput);
  EXPECT_THROW(div.apply_rows(&x, 1, &x, 1, 0), InvalidInput);
}

// relabeled(): the same divergence on renumbered vertices (the heat method's blocks use a
// breadth-first order); apply_rows() through a row map u_row gives the unmapped bits;
// add_rows_part() splits the faces into parts that write disjoint rows;
// row for row to rounding (its faces are reordered, so the sums at a vertex run in another
// order); anything but a permutation is refused.
TEST(SolversHeatDistance, UnitGradientDivergenceRelabeled) {
  using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  const auto tri = test::make_tri(test::jittered(intrinsic::icosphere(12), 0.02));
  const Index nv = tri.n_vertices();
  const UnitGradientDivergence div(tri);
  std::vector<Index> new_index(static_cast<std::size_t>(nv));
  for (Index v = 0; v < nv; ++v) new_index[std::size_t(v)] = (v * 37 + 11) % nv;  // nv odd
  ASSERT_EQ(std::set<Index>(new_index.begin(), new_index.end()).size(), std::size_t(nv));
  const UnitGradientDivergence moved = div.relabeled(new_index);
  const int k = 19;
  RowMajor U(nv, k);
  for (Index v = 0; v < nv; ++v) {
    for (int j = 0; j < k; ++j) U(v, j) = std::exp(-0.01 * double((v * (j + 2)) % nv));
  }
  RowMajor U_moved(nv, k), expected(nv, k), out(nv, k);
  for (Index v = 0; v < nv; ++v) U_moved.row(new_index[std::size_t(v)]) = U.row(v);
  div.apply_rows(U.data(), k, expected.data());
  moved.apply_rows(U_moved.data(), k, out.data());
  const double scale = expected.cwiseAbs().maxCoeff();
  ASSERT_GT(scale, 0.0);
  for (Index v = 0; v < nv; ++v) {
    EXPECT_LT((out.row(new_index[std::size_t(v)]) - expected.row(v)).cwiseAbs().maxCoeff(),
              1e-13 * scale)
        << "vertex " << v;
  }
  // the same operator reading its fields through a row map (u_row: vertex v's values are row
  // u_row[v] of the block, as the heat method's blocks are read in the factor's order), and
  // writing through one too (d_row): the same arithmetic in the same face order, so the same
  // bits, for both column ranges
  const Eigen::Index mid = UnitGradientDivergence::column_split(k);
  RowMajor mapped(nv, k), mapped_out(nv, k);
  div.apply_rows(U_moved.data(), k, mapped.data(), 0, mid, new_index.data());
  div.apply_rows(U_moved.data(), k, mapped.data(), mid, k, new_index.data());
  EXPECT_EQ(mapped, expected);
  for (const Eigen::Index j0 : {Eigen::Index(0), mid}) {
    div.apply_rows(U_moved.data(), k, mapped_out.data(), j0, j0 == 0 ? mid : k, new_index.data(),
                   new_index.data());
  }
  for (Index v = 0; v < nv; ++v) {
    EXPECT_EQ(mapped_out.row(new_index[std::size_t(v)]), expected.row(v)) << "vertex " << v;
  }
  // add_rows_part(): part 0 writes only rows below ⌊#V/2⌋, part 1 only rows at or above it (so
  // two threads may take them side by side); zeroing, parts 0 and 1 on every column and part 2
  // in two column ranges give apply_rows()'s bits (the same faces in the same order at every
  // vertex); an operator that was not relabeled has every face in part 2
  const Index half = nv / 2;
  RowMajor part0 = RowMajor::Zero(nv, k), part1 = RowMajor::Zero(nv, k);
  moved.add_rows_part(U_moved.data(), k, part0.data(), 0, 0, k);
  moved.add_rows_part(U_moved.data(), k, part1.data(), 1, 0, k);
  EXPECT_GT(part0.topRows(half).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_EQ(part0.bottomRows(nv - half).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_GT(part1.bottomRows(nv - half).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_EQ(part1.topRows(half).cwiseAbs().maxCoeff(), 0.0);
  RowMajor parts = RowMajor::Zero(nv, k);
  moved.add_rows_part(U_moved.data(), k, parts.data(), 0, 0, k);
  moved.add_rows_part(U_moved.data(), k, parts.data(), 1, 0, k);
  moved.add_rows_part(U_moved.data(), k, parts.data(), 2, 0, mid);
  moved.add_rows_part(U_moved.data(), k, parts.data(), 2, mid, k);
  EXPECT_EQ(parts, out);
  RowMajor none = RowMajor::Zero(nv, k);
  div.add_rows_part(U.data(), k, none.data(), 0, 0, k);
  div.add_rows_part(U.data(), k, none.data(), 1, 0, k);
  EXPECT_EQ(none.cwiseAbs().maxCoeff(), 0.0);
  EXPECT_THROW(div.add_rows_part(U.data(), k, none.data(), 3, 0, k), InvalidInput);
  std::vector<Index> bad = new_index;
  bad[1] = bad[0];
  EXPECT_THROW(div.relabeled(bad), InvalidInput);
  bad.pop_back();
  EXPECT_THROW(div.relabeled(bad), InvalidInput);
}

// apply_rows() on column ranges (the caller's threads): two ranges split at column_split(k)
// give the bits of the whole call, and a range leaves the other columns alone.
TEST(SolversHeatDistance, UnitGradientDivergenceRowRanges) {
  using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  const auto tri = test::make_tri(intrinsic::icosphere(20));
  const Index nv = tri.n_vertices();
  const UnitGradientDivergence div(tri);
  EXPECT_EQ(UnitGradientDivergence::column_split(8), 8);
  EXPECT_EQ(UnitGradientDivergence::column_split(32), 16);
  EXPECT_EQ(UnitGradientDivergence::column_split(33), 16);
  EXPECT_EQ(UnitGradientDivergence::column_split(40), 24);
  for (const int k : {8, 16, 32, 33}) {
    RowMajor U(nv, k);
    for (Index v = 0; v < nv; ++v) {
      for (int j = 0; j < k; ++j) U(v, j) = std::exp(-0.002 * double((v * (j + 3)) % nv));
    }
    RowMajor whole(nv, k), parts(nv, k);
    div.apply_rows(U.data(), k, whole.data());
    parts.setConstant(7.0);
    const Eigen::Index mid = UnitGradientDivergence::column_split(k);
    div.apply_rows(U.data(), k, parts.data(), 0, mid);
    if (mid < k) {
      EXPECT_EQ(parts(0, mid), 7.0) << "k = " << k;  // not touched yet
    }
    div.apply_rows(U.data(), k, parts.data(), mid, k);
    EXPECT_TRUE(parts == whole) << "k = " << k;
    EXPECT_GT(whole.cwiseAbs().maxCoeff(), 0.0);
  }
}

// The row-major block path (our kernel solves: ≥ 40k vertices or mixed precision; no boundary,
// no correction steps) on closed meshes, over two blocks (37 > 32 sources), with a repeat: each
// column equals its single-source query. Two components go through the Poisson solve's
// column-major fallback.
TEST(SolversHeatDistance, RowBlocksEqualSingleSources) {
  const auto big = test::make_tri(intrinsic::icosphere(64));  // 40,962 vertices
  std::vector<Index> src;
  for (Index k = 0; k < 37; ++k) src.push_back((k * 1031) % big.n_vertices());
  src.push_back(src[5]);
  expect_batch_equals_single(big, {}, src);
  HeatDistanceOptions mixed;
  mixed.precision = HeatDistanceOptions::Precision::kMixed;
  expect_batch_equals_single(test::make_tri(intrinsic::icosphere(12)), mixed, {0, 77, 901, 77});
  const auto one = intrinsic::icosphere(6);
  const Index n = Index(one.positions.rows());
  expect_batch_equals_single(test::make_tri(test::two_copies(one, 3.0, 1)), mixed, {3, n + 3, 7});
}

}  // namespace
}  // namespace ifem::solvers
