// The precompute's shared symbolic analysis (CholeskyAnalysis, PoissonSolver with an analysis)
// and thread-count independence of the heat method (issue 15, item 3).
#include <gtest/gtest.h>
#include <sys/resource.h>

#include <Eigen/Core>
#include <atomic>
#include <chrono>
#include <functional>
#include <limits>
#include <memory>
#include <numeric>
#include <thread>
#include <vector>

#include "fem/operators.h"
#include "intrinsic/core/errors.h"
#include "solvers/linalg/cholesky.h"
#include "solvers/linalg/memory.h"
#include "solvers/linalg/parallel.h"
#include "solvers/scalar/components.h"
#include "solvers/scalar/heat_distance.h"
#include "solvers/scalar/heat_engine.h"
#include "solvers/scalar/poisson.h"
#include "test_util.h"

#if defined(_OPENMP)
#include <omp.h>
#endif

namespace ifem::solvers {
namespace {

fem::SparseMatrix mass_plus_laplacian(const intrinsic::IntrinsicTriangulation& tri, double t) {
  fem::SparseMatrix A = t * fem::cotan_laplacian(tri);
  const Eigen::VectorXd m = fem::lumped_mass(tri);
  for (Eigen::Index i = 0; i < A.rows(); ++i) A.coeffRef(i, i) += m[i];
  A.makeCompressed();
  return A;
}

// Two matrices of one pattern factored with one analysis equal their own factorizations
// bitwise (same ordering, same operations), also when built from two threads at once.
TEST(SolversSmallMesh, SharedAnalysisEqualsOwnAnalysis) {
  const auto tri = test::make_tri(intrinsic::icosphere(6));
  const fem::SparseMatrix A = mass_plus_laplacian(tri, 1.0);
  const fem::SparseMatrix B = mass_plus_laplacian(tri, 0.01);
  const CholeskyAnalysis analysis(A);
  EXPECT_EQ(analysis.size(), A.rows());
  std::vector<CholeskySolver> shared;
  shared.reserve(2);
  std::thread other([&] { shared.emplace_back(A, analysis); });
  other.join();
  shared.emplace_back(B, analysis);
  const CholeskySolver own_a(A), own_b(B);
  const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(A.rows(), -1.0, 3.0);
  EXPECT_EQ(shared[0].solve(b), own_a.solve(b));
  EXPECT_EQ(shared[1].solve(b), own_b.solve(b));
  EXPECT_STREQ(shared[0].ordering(), own_a.ordering());
  EXPECT_EQ(shared[1].factor_nonzeros(), own_b.factor_nonzeros());
  // refactor() keeps working on the shared pattern (simplicial numerics: equal to rounding)
  shared[0].refactor(B);
  const Eigen::VectorXd xb = own_b.solve(b);
  EXPECT_LT((shared[0].solve(b) - xb).cwiseAbs().maxCoeff(), 1e-12 * xb.cwiseAbs().maxCoeff());
  // another pattern is refused
  fem::SparseMatrix I(A.rows(), A.cols());
  I.setIdentity();
  EXPECT_THROW(CholeskySolver(I, analysis), InvalidInput);
  EXPECT_THROW(CholeskyAnalysis(fem::SparseMatrix(3, 4)), InvalidInput);
}

// simplicial_below_flops_per_entry: the factor is simplicial exactly when the analysis predicts
// fewer flops per entry than the threshold (own and shared analyses alike), with the same
// solutions as the supernodal factor; our supernodal kernel ignores it; bad values are refused.
TEST(SolversSmallMesh, SimplicialBelowFlopsPerEntry) {
  const auto tri = test::make_tri(intrinsic::icosphere(12));
  const fem::SparseMatrix A = mass_plus_laplacian(tri, 0.1);
  const CholeskySolver super(A);
  ASSERT_TRUE(super.supernodal());
  const double ratio = super.factor_flops() / double(super.factor_nonzeros());
  const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(A.rows(), -1.0, 2.0);
  const Eigen::VectorXd x = super.solve(b);
  for (const double threshold : {0.5 * ratio, 2.0 * ratio}) {
    CholeskyOptions o;
    o.simplicial_below_flops_per_entry = threshold;
    const bool simplicial = threshold > ratio;
    const CholeskySolver own(A, o);
    const CholeskyAnalysis analysis(A, o);
    const CholeskySolver shared(A, analysis);
    EXPECT_EQ(own.supernodal(), !simplicial) << threshold;
    EXPECT_EQ(shared.supernodal(), !simplicial) << threshold;
    EXPECT_LT((own.solve(b) - x).cwiseAbs().maxCoeff(), 1e-12 * x.cwiseAbs().maxCoeff());
    EXPECT_EQ(shared.solve(b), own.solve(b)) << threshold << " " << ratio;
    o.solve_kernel = CholeskyOptions::SolveKernel::kSupernodalDouble;
    EXPECT_TRUE(CholeskySolver(A, o).supernodal()) << threshold;
  }
  for (const double bad :
       {-1.0, std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity()}) {
    CholeskyOptions o;
    o.simplicial_below_flops_per_entry = bad;
    EXPECT_THROW(CholeskySolver(A, o), InvalidInput) << bad;
  }
}

// CholeskyOptions::ordering replaces AMD: AMD's own ordering given back gives the same factor,
// a poor one (the natural order) more fill; anything but a permutation of 0..n−1 is refused.
TEST(SolversSmallMesh, GivenOrderingIsUsed) {
  const auto tri = test::make_tri(test::jittered(intrinsic::grid(20, 20), 0.02));
  const fem::SparseMatrix A = mass_plus_laplacian(tri, 0.1);
  const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(A.rows(), -1.0, 2.0);
  const CholeskySolver amd(A);
  CholeskyOptions natural;
  natural.ordering.resize(A.rows());
  std::iota(natural.ordering.begin(), natural.ordering.end(), 0);
  const CholeskySolver own(A, natural);
  const CholeskySolver shared(A, CholeskyAnalysis(A, natural));
  EXPECT_GT(own.factor_nonzeros(), 1.2 * amd.factor_nonzeros());
  EXPECT_EQ(shared.factor_nonzeros(), own.factor_nonzeros());
  const Eigen::VectorXd x = amd.solve(b);
  EXPECT_LT((own.solve(b) - x).cwiseAbs().maxCoeff(), 1e-12 * x.cwiseAbs().maxCoeff());
  EXPECT_EQ(shared.solve(b), own.solve(b));
  std::vector<int> short_one(A.rows() - 1);
  std::iota(short_one.begin(), short_one.end(), 0);
  for (const std::vector<int>& bad : {short_one, std::vector<int>(A.rows(), 0)}) {
    CholeskyOptions o;
    o.ordering = bad;
    EXPECT_THROW(CholeskySolver(A, o), InvalidInput);
    EXPECT_THROW(CholeskyAnalysis(A, o), InvalidInput);
  }
}

// Compares every solve of a PoissonSolver with a shared analysis (constrained vertices kept as
// decoupled rows) with one that removes them, to rounding.
void expect_same_solves(const PoissonSolver& shared, const PoissonSolver& own, Index n) {
  const Eigen::Index nd = Eigen::Index(own.dirichlet_vertices().size());
  const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(n, -2.0, 1.0);
  const Eigen::VectorXd g = Eigen::VectorXd::LinSpaced(nd, 0.5, 1.5);
  const Eigen::VectorXd x = shared.solve_weak(b, g), y = own.solve_weak(b, g);
  EXPECT_LT((x - y).cwiseAbs().maxCoeff(), 1e-12 * y.cwiseAbs().maxCoeff());
  for (Eigen::Index d = 0; d < nd; ++d) EXPECT_EQ(x[own.dirichlet_vertices()[d]], g[d]);
  Eigen::MatrixXd B(n, 3);
  B << b, b.reverse(), Eigen::VectorXd::Ones(n);
  const Eigen::MatrixXd X = shared.solve_weak_homogeneous(B), Y = own.solve_weak_homogeneous(B);
  EXPECT_LT((X - Y).cwiseAbs().maxCoeff(), 1e-12 * Y.cwiseAbs().maxCoeff());
}

// PoissonSolver::analyze(tri) (the pattern and AMD's ordering from the edges, before L exists)
// gives analyze(L, components)'s fill and solves: on the referenced vertices only (unreferenced
// ones and a second component), and on a Δ-complex whose flipped tetrahedron has a doubled edge;
// with AMD left to CHOLMOD as well.
TEST(SolversSmallMesh, AnalysisFromTheTriangulationMatchesL) {
  intrinsic::TriangleMesh tet;
  tet.positions.resize(4, 3);
  tet.positions << 1, 1, 1, 1, -1, -1, -1, 1, -1, -1, -1, 1;  // regular: every diamond convex
  tet.faces = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  auto doubled = test::make_tri(tet, false);
  ASSERT_TRUE(doubled.flip_edge(0));
  CholeskyOptions cholmod_amd;
  cholmod_amd.force_amd = false;  // CHOLMOD's own choice (AMD on these sizes)
  for (const auto& tri :
       {test::make_tri(test::two_copies(test::jittered(intrinsic::grid(16, 12), 0.03), 3.0, 2)),
        doubled}) {
    const fem::SparseMatrix L = fem::cotan_laplacian(tri);
    const Eigen::VectorXd mass = fem::lumped_mass(tri);
    const Components comps = connected_components(tri);
    const CholeskyAnalysis own = PoissonSolver::analyze(L, comps);
    PoissonOptions screened;
    screened.screening = 1.0;
    const PoissonSolver b(L, mass, comps, {}, own, screened);
    for (const CholeskyOptions& o : {CholeskyOptions{}, cholmod_amd}) {
      const CholeskyAnalysis mine = PoissonSolver::analyze(tri, o);
      ASSERT_EQ(mine.size(), own.size());
      const PoissonSolver a(L, mass, comps, {}, mine, screened);
      EXPECT_EQ(a.factor_nonzeros(), b.factor_nonzeros()) << tri.n_vertices();
      expect_same_solves(a, b, tri.n_vertices());
    }
  }
  EXPECT_THROW(PoissonSolver::analyze(intrinsic::IntrinsicTriangulation()), InvalidInput);
  EXPECT_THROW(amd_ordering(2, {0, 1, 2}, {1, 2}), InvalidInput);  // index out of range
  EXPECT_THROW(amd_ordering(2, {0, 2, 1}, {1, 0}), InvalidInput);  // start decreasing
  EXPECT_EQ(amd_ordering(0, {0}, {}).size(), 0u);
}

TEST(SolversSmallMesh, PoissonSharedAnalysisMatchesSeparate) {
  // two components (Dirichlet on the first, pure Neumann = pinned on the second) and two
  // unreferenced vertices
  const auto m = test::two_copies(intrinsic::grid(8, 8), 3.0, 2);
  const auto tri = test::make_tri(m);
  const Index n = tri.n_vertices();
  const fem::SparseMatrix L = fem::cotan_laplacian(tri);
  const Eigen::VectorXd mass = fem::lumped_mass(tri);
  const Components comps = connected_components(tri);
  const CholeskyAnalysis analysis = PoissonSolver::analyze(L, comps);
  const std::vector<Index> bv = {0, 1, 2, 9, 18};
  const PoissonSolver shared(L, mass, comps, bv, analysis), own(L, mass, comps, bv);
  EXPECT_EQ(shared.n_unknowns(), own.n_unknowns() + Index(bv.size()) + 1);  // + pinned vertex
  expect_same_solves(shared, own, n);
  PoissonOptions screened;
  screened.screening = 1.0;
  const fem::SparseMatrix tL = 0.01 * L;
  expect_same_solves(PoissonSolver(tL, mass, comps, {}, analysis, screened),
                     PoissonSolver(tL, mass, comps, {}, screened), n);
  expect_same_solves(PoissonSolver(tL, mass, comps, bv, analysis, screened),
                     PoissonSolver(tL, mass, comps, bv, screened), n);
  // the analysis of other components or another pattern is refused
  const auto tri1 = test::make_tri(intrinsic::grid(8, 8));
  const fem::SparseMatrix L1 = fem::cotan_laplacian(tri1);
  EXPECT_THROW(PoissonSolver(L1, fem::lumped_mass(tri1), connected_components(tri1), {}, analysis),
               InvalidInput);
}

// Every vertex an unknown: the factored block is copied from L's sorted columns; an uncompressed L
// takes the general entry-by-entry loop. Both give the same bits, Dirichlet and pinned vertices
// (decoupled rows of a shared analysis) included.
TEST(SolversSmallMesh, PoissonBlockCopyEqualsEntryLoop) {
  const auto tri = test::make_tri(test::two_copies(intrinsic::grid(9, 7), 3.0, 0));
  const Index n = tri.n_vertices();
  const fem::SparseMatrix L = fem::cotan_laplacian(tri);
  fem::SparseMatrix loose = L;
  loose.uncompress();
  const Eigen::VectorXd mass = fem::lumped_mass(tri);
  const Components comps = connected_components(tri);
  const CholeskyAnalysis analysis = PoissonSolver::analyze(L, comps);
  const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(n, -2.0, 1.0);
  PoissonOptions screened;
  screened.screening = 0.5;
  for (const PoissonOptions& o : {PoissonOptions{}, screened}) {
    for (const std::vector<Index>& bv : {std::vector<Index>{}, std::vector<Index>{0, 5, 70}}) {
      const PoissonSolver copied(L, mass, comps, bv, analysis, o);
      const PoissonSolver looped(loose, mass, comps, bv, analysis, o);
      const Eigen::VectorXd g = Eigen::VectorXd::Constant(Eigen::Index(bv.size()), 0.25);
      const Eigen::VectorXd x = copied.solve_weak(b, g);
      EXPECT_TRUE(x == looped.solve_weak(b, g)) << o.screening << " " << bv.size();
      EXPECT_LT((x - PoissonSolver(L, mass, comps, bv, o).solve_weak(b, g)).cwiseAbs().maxCoeff(),
                1e-12 * x.cwiseAbs().maxCoeff());
    }
  }
}

// PoissonBlocks::solve_in_place() gives solve_weak_homogeneous()'s bits, over a block of a wider
// matrix (the columns beside it untouched): through its own storage when every vertex is an
// unknown (shared analysis: Dirichlet and pinned vertices as decoupled rows; one pure-Neumann
// component or two), through solve_many() otherwise (unreferenced vertices, or no analysis).
TEST(SolversSmallMesh, PoissonSolveInPlaceEqualsSolve) {
  const auto one = test::make_tri(intrinsic::grid(8, 8));
  for (const int unreferenced : {0, 2}) {
    const auto tri = test::make_tri(test::two_copies(intrinsic::grid(8, 8), 3.0, unreferenced));
    const fem::SparseMatrix L = fem::cotan_laplacian(tri);
    const Eigen::VectorXd mass = fem::lumped_mass(tri);
    const Components comps = connected_components(tri);
    const CholeskyAnalysis analysis = PoissonSolver::analyze(L, comps);
    const std::vector<Index> bv = {0, 1, 2, 9, 18};
    PoissonOptions screened;
    screened.screening = 1.0;
    const fem::SparseMatrix L1 = fem::cotan_laplacian(one);
    const Components comps1 = connected_components(one);
    std::vector<std::unique_ptr<PoissonSolver>> solvers;
    solvers.push_back(std::make_unique<PoissonSolver>(L, mass, comps, bv, analysis));
    solvers.push_back(
        std::make_unique<PoissonSolver>(L, mass, comps, std::vector<Index>{}, analysis));
    solvers.push_back(std::make_unique<PoissonSolver>(0.01 * L, mass, comps, std::vector<Index>{},
                                                      analysis, screened));
    solvers.push_back(std::make_unique<PoissonSolver>(L, mass, comps, bv));
    solvers.push_back(std::make_unique<PoissonSolver>(L1, fem::lumped_mass(one), comps1,
                                                      std::vector<Index>{},
                                                      PoissonSolver::analyze(L1, comps1)));
    for (std::size_t i = 0; i < solvers.size(); ++i) {
      const PoissonSolver& p = *solvers[i];
      const Index n = i == 4 ? one.n_vertices() : tri.n_vertices();
      std::srand(unsigned(7 + i));
      Eigen::MatrixXd wide = Eigen::MatrixXd::Random(n, 5);
      const Eigen::MatrixXd before = wide;
      const Eigen::MatrixXd expected = p.solve_weak_homogeneous(wide.leftCols(3));
      PoissonBlocks::solve_in_place(p, wide.leftCols(3));
      EXPECT_TRUE(wide.leftCols(3) == expected) << "solver " << i << ", " << unreferenced;
      EXPECT_TRUE(wide.rightCols(2) == before.rightCols(2)) << "solver " << i;
      Eigen::MatrixXd wrong(3, 2);
      EXPECT_THROW(PoissonBlocks::solve_in_place(p, wrong), InvalidInput);
    }
  }
}

// The row-major solve equals the column-major one to rounding, through our own row loops (one
// pure-Neumann component, every vertex an unknown) and through the column-major fallback (two
// components, Dirichlet vertices, unreferenced vertices); without the zero mean it differs by a
// constant per column on a pure-Neumann component.
TEST(SolversSmallMesh, PoissonRowsEqualColumns) {
  using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  const auto one = test::make_tri(intrinsic::icosphere(6));
  const auto two = test::make_tri(test::two_copies(intrinsic::grid(8, 8), 3.0, 2));
  for (const auto* tri : {&one, &two}) {
    const fem::SparseMatrix L = fem::cotan_laplacian(*tri);
    const Eigen::VectorXd mass = fem::lumped_mass(*tri);
    const Components comps = connected_components(*tri);
    const CholeskyAnalysis analysis = PoissonSolver::analyze(L, comps);
    std::vector<std::unique_ptr<PoissonSolver>> solvers;
    solvers.push_back(
        std::make_unique<PoissonSolver>(L, mass, comps, std::vector<Index>{}, analysis));
    solvers.push_back(std::make_unique<PoissonSolver>(L, mass, comps, std::vector<Index>{0, 5}));
    for (std::size_t i = 0; i < solvers.size(); ++i) {
      const PoissonSolver& p = *solvers[i];
      const Index n = tri->n_vertices();
      for (const int k : {1, 3, 9}) {
        std::srand(unsigned(11 + k));
        const Eigen::MatrixXd B = Eigen::MatrixXd::Random(n, k);
        const Eigen::MatrixXd expected = p.solve_weak_homogeneous(B);
        RowMajor X = B;
        PoissonBlocks::solve_rows_in_place(p, X.data(), k);
        const double scale = expected.cwiseAbs().maxCoeff();
        EXPECT_LT((Eigen::MatrixXd(X) - expected).cwiseAbs().maxCoeff(), 1e-12 * scale)
            << "solver " << i << ", k = " << k;
        RowMajor Y = B;
        PoissonBlocks::solve_rows_in_place(p, Y.data(), k, false);
        const bool floating = tri == &one && i == 0;  // one pure-Neumann component
        for (int j = 0; j < k; ++j) {
          const Eigen::VectorXd d = Y.col(j) - expected.col(j);
          const double spread = d.maxCoeff() - d.minCoeff();
          EXPECT_LT(spread, 1e-12 * scale) << "a constant per column";
          if (!floating) {
            EXPECT_LT(d.cwiseAbs().maxCoeff(), 1e-12 * scale) << "no shift to skip";
          }
        }
      }
      double x = 0.0;
      EXPECT_THROW(PoissonBlocks::solve_rows_in_place(p, &x, 0), InvalidInput);
    }
  }
}

// A block kept in the factor's order (block_order(): a pure-Neumann component with the shared
// analysis, its pinned vertex kept as a decoupled row) solves to the row-major solve's values,
// with and without the zero mean, with the compatibility sums taken by the solve or given by
// the caller; Dirichlet vertices or two components have no such order.
TEST(SolversSmallMesh, PoissonRowsInBlockOrder) {
  using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  const auto tri = test::make_tri(test::jittered(intrinsic::icosphere(8), 0.02));
  const fem::SparseMatrix L = fem::cotan_laplacian(tri);
  const Eigen::VectorXd mass = fem::lumped_mass(tri);
  const Components comps = connected_components(tri);
  const CholeskyAnalysis analysis = PoissonSolver::analyze(L, comps);
  const PoissonSolver p(L, mass, comps, std::vector<Index>{}, analysis);
  const std::vector<int>* order = PoissonBlocks::block_order(p);
  ASSERT_NE(order, nullptr);
  const Index n = tri.n_vertices();
  ASSERT_EQ(Index(order->size()), n);
  EXPECT_NE(*order, [&] {  // a fill-reducing order, not the identity
    std::vector<int> identity(static_cast<std::size_t>(n));
    std::iota(identity.begin(), identity.end(), 0);
    return identity;
  }());
  for (const int k : {2, 9}) {
    for (const bool zero_mean : {true, false}) {
      std::srand(unsigned(5 + k));
      const RowMajor B = Eigen::MatrixXd::Random(n, k);
      RowMajor expected = B;
      PoissonBlocks::solve_rows_in_place(p, expected.data(), k, zero_mean);
      RowMajor W(n, k);
      for (Index i = 0; i < n; ++i) W.row(i) = B.row((*order)[std::size_t(i)]);
      // the compatibility sums from the caller's own sweep, or taken by the solve
      const Eigen::VectorXd* a = PoissonBlocks::compatibility_weights(p);
      ASSERT_NE(a, nullptr);
      Eigen::RowVectorXd sums = Eigen::RowVectorXd::Zero(k);
      for (Index i = 0; i < n; ++i) sums += (*a)[(*order)[std::size_t(i)]] * W.row(i);
      RowMajor W2 = W;
      PoissonBlocks::solve_rows_in_order(p, W.data(), k, zero_mean);
      PoissonBlocks::solve_rows_in_order(p, W2.data(), k, zero_mean, nullptr, sums.data());
      RowMajor X(n, k), X2(n, k);
      for (Index i = 0; i < n; ++i) X.row((*order)[std::size_t(i)]) = W.row(i);
      for (Index i = 0; i < n; ++i) X2.row((*order)[std::size_t(i)]) = W2.row(i);
      const double scale = expected.cwiseAbs().maxCoeff();
      EXPECT_LT((X - expected).cwiseAbs().maxCoeff(), 1e-12 * scale)
          << "k = " << k << (zero_mean ? ", zero mean" : "");
      EXPECT_LT((X2 - expected).cwiseAbs().maxCoeff(), 1e-12 * scale) << "the caller's sums";
    }
  }
  double x = 0.0;
  EXPECT_THROW(PoissonBlocks::solve_rows_in_order(p, &x, 1), InvalidInput);
  const PoissonSolver dirichlet(L, mass, comps, std::vector<Index>{0, 5});
  EXPECT_EQ(PoissonBlocks::block_order(dirichlet), nullptr);
  EXPECT_EQ(PoissonBlocks::compatibility_weights(dirichlet), nullptr);
  EXPECT_THROW(PoissonBlocks::solve_rows_in_order(dirichlet, &x, 2), InvalidInput);
  const auto two = test::make_tri(test::two_copies(intrinsic::icosphere(4), 3.0, 0));
  const PoissonSolver p2(fem::cotan_laplacian(two), fem::lumped_mass(two),
                         connected_components(two), std::vector<Index>{});
  EXPECT_EQ(PoissonBlocks::block_order(p2), nullptr);
  EXPECT_EQ(PoissonBlocks::compatibility_weights(p2), nullptr);  // two pure-Neumann components
}

#if defined(_OPENMP)
// run_parallel() on OpenMP threads: every job runs once, two jobs really run side by side (each
// waits to see the other started), a job's exception comes back after all ran, jobs started
// from a job run on its thread (nested: the cores are taken), callers on several threads at once
// all get their work done, and with one OpenMP thread the jobs run on the caller's.
TEST(SolversSmallMesh, RunParallelOnOpenMpThreads) {
  if (std::thread::hardware_concurrency() < 2) GTEST_SKIP() << "one core";
  const int saved = omp_get_max_threads();
  omp_set_num_threads(2);
  for (int round = 0; round < 50; ++round) {
    std::atomic<int> started{0};
    std::atomic<bool> both{true};
    auto meet = [&] {
      ++started;
      const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(5);
      while (started.load() < 2 && std::chrono::steady_clock::now() < until) {
        std::this_thread::yield();
      }
      if (started.load() < 2) both = false;
    };
    run_parallel({meet, meet});
    ASSERT_TRUE(both.load()) << "round " << round << ": the two jobs did not run side by side";
  }
  std::vector<int> ran(5, 0);
  std::vector<std::function<void()>> jobs;
  for (int i = 0; i < 5; ++i) {
    jobs.emplace_back([&ran, i] {
      ++ran[std::size_t(i)];
      if (i == 2) throw InvalidInput("job 2");
    });
  }
  EXPECT_THROW(run_parallel(jobs), InvalidInput);
  EXPECT_EQ(ran, std::vector<int>(5, 1));
  std::thread::id outer, inner[2];
  run_parallel({[&] {
                  outer = std::this_thread::get_id();
                  run_parallel({[&] { inner[0] = std::this_thread::get_id(); },
                                [&] { inner[1] = std::this_thread::get_id(); }});
                },
                [] {}});
  EXPECT_EQ(inner[0], outer);
  EXPECT_EQ(inner[1], outer);
  std::atomic<long> total{0};
  std::vector<std::thread> callers;
  for (int c = 0; c < 3; ++c) {
    callers.emplace_back([&total] {
      for (int i = 0; i < 200; ++i) run_halves(true, [&total](int half) { total += half + 1; });
    });
  }
  for (std::thread& t : callers) t.join();
  EXPECT_EQ(total.load(), 3 * 200 * 3);
  omp_set_num_threads(1);
  std::thread::id ran_on[2];
  run_parallel({[&] { ran_on[0] = std::this_thread::get_id(); },
                [&] { ran_on[1] = std::this_thread::get_id(); }});
  EXPECT_EQ(ran_on[0], std::this_thread::get_id());
  EXPECT_EQ(ran_on[1], std::this_thread::get_id());
  omp_set_num_threads(saved);
}
#endif

// retain_freed_memory(): a 24 MB block freed and allocated again is not faulted in again (glibc
// maps a fresh block of that size from the kernel by default: ~6000 faults). ctest runs each
// test in a process of its own, where no earlier free raised glibc's own threshold.
#if defined(__SANITIZE_ADDRESS__)
#define IFEM_TEST_OWN_MALLOC 1  // AddressSanitizer's allocator replaces glibc's
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define IFEM_TEST_OWN_MALLOC 1
#endif
#endif
TEST(SolversSmallMesh, RetainedMemoryIsNotFaultedAgain) {
#if defined(__GLIBC__) && !defined(IFEM_TEST_OWN_MALLOC)
  retain_freed_memory();
  auto faults_to_fill = [] {
    rusage before{}, after{};
    getrusage(RUSAGE_SELF, &before);
    std::vector<char> block(std::size_t(24) << 20, 1);
    getrusage(RUSAGE_SELF, &after);
    EXPECT_EQ(block[12345], 1);
    return after.ru_minflt - before.ru_minflt;
  };
  const long first = faults_to_fill();
  EXPECT_GT(first, 1000);  // 6144 pages of 4 KB (fewer on huge pages)
  EXPECT_LT(faults_to_fill(), 100);
#else
  GTEST_SKIP() << "glibc's own malloc only";
#endif
}

#if defined(_OPENMP)
// The precompute and a query give the same bits with 1 and 2 OpenMP threads, on a mesh above
// every parallel loop's threshold (and on a small one, below them).
TEST(SolversSmallMesh, HeatDistanceIsThreadCountIndependent) {
  for (const int n : {8, 60}) {  // 1,280 and 72,000 faces
    const auto m = intrinsic::icosphere(n);
    const auto tri = intrinsic::IntrinsicTriangulation::from_positions(m.faces, m.positions);
    const int saved = omp_get_max_threads();
    std::vector<Eigen::VectorXd> d;
    for (const int threads : {1, 2}) {
      omp_set_num_threads(threads);
      const HeatDistanceSolver solver(tri);
      d.push_back(solver.compute_distance({0, 7}));
      d.push_back(solver.compute_distances({3, 11}).col(1));
    }
    omp_set_num_threads(saved);
    EXPECT_EQ(d[0], d[2]) << n;
    EXPECT_EQ(d[1], d[3]) << n;
  }
}
#endif

}  // namespace
}  // namespace ifem::solvers
