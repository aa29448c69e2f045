#include "solvers/scalar/heat_distance.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <mutex>
#include <numeric>
#include <optional>
#include <queue>
#include <string>
#include <type_traits>
#include <utility>

#include "fem/gradient.h"
#include "fem/operators.h"
#include "intrinsic/core/errors.h"
#include "intrinsic/core/geometry.h"
#include "intrinsic/core/union_find.h"
#include "solvers/linalg/cholesky.h"
#include "solvers/linalg/huge_pages.h"
#include "solvers/linalg/parallel.h"
#include "solvers/linalg/row_kernels.h"
#include "solvers/scalar/components.h"
#include "solvers/scalar/heat_engine.h"
#include "solvers/scalar/path_bounds.h"
#include "solvers/scalar/poisson.h"

namespace ifem::solvers {

using intrinsic::IntrinsicTriangulation;

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
// A block of at least this many values is scanned and written by two threads (a thread start
// costs ~0.05 ms; a block of 28k vertices × 32 sources (rocketship, 7 MB) took 0.9 ms to scan
// and 0.9 ms to write on one).
constexpr std::int64_t kParallelBlockValues = 1 << 16;
constexpr double kAbsoluteHeatFloor = 1e-290;  // stay clear of subnormals
// The multigrid path's later stages (D-285): a band reaches kBandWidth·√t beyond the frontier
// and kBandBehind·√t behind it (the heat of one backward Euler step decays like e^(−d/√t)); a
// vertex is resolved / trusted when its heat exceeds 1e3 / 1e5 × the largest heat on the
// band's far edge (the edge's reflection then moves it by ~1e-6 / 1e-10 relative), so a stage
// advances ~80·√t.
constexpr double kBandWidth = 96.0;
constexpr double kBandBehind = 8.0;
constexpr double kBandResolvedRatio = 1e3;
constexpr double kBandTrustedRatio = 1e5;
// From this many vertices on, queries solve with our supernodal kernel (see the constructor;
// session 8: 28k vertices (rocketship) faster with CHOLMOD's simplicial solves, 50k
// (icosphere(71)) faster with ours; since the kernel's own small-supernode loops (session 9)
// rocketship measures the same either way, 0.0026–0.0028 s, and below this size CHOLMOD's path
// can also use a simplicial factorization, which the kernel cannot).
constexpr Index kOwnKernelVertices = 40000;
// Below that, the factors are simplicial when the analysis predicts fewer flops per factor entry
// (little fill: supernodes too small for BLAS; see CholeskyOptions).
constexpr double kSimplicialBelowFlopsPerEntry = 64.0;

// A source as weights on vertices (1 vertex, or the 3 corners of a face).
struct WeightedPoint {
  Index n = 0;
  Index vertex[3] = {0, 0, 0};
  double weight[3] = {0, 0, 0};
  double corner_distance[3] = {0, 0, 0};  // distance in the face layout to each corner
  bool is_vertex() const { return n == 1; }
  // What the weighted corner values of the distance are at this point: Σ wᵢ |cᵢ − p|, not 0.
  // Near a source the distance is a cone, and the linear blend of its corner values lies above
  // the cone's tip by this much; shifting φ so that the blend is 0 would make every distance
  // too small by it (about 0.5·h for a face centre). 0 for a vertex source.
  double blend_offset() const {
    double s = 0.0;
    for (Index i = 0; i < n; ++i) s += weight[i] * corner_distance[i];
    return s;
  }
};

// The factor options of the heat method's Poisson (heat = false) or heat (true) factor. Queries
// solve with our supernodal kernel (two threads on large factors, a point source's forward pass
// over its ancestors only): the heat factor in double (its solution decays far below float's
// range on large meshes), the Poisson factor as floats with kMixed (docs/decisions.md, "Heat
// queries: our supernodal solve kernel"). Below kOwnKernelVertices CHOLMOD solves, and the
// factors are simplicial when they have little fill (faster to factor: docs/decisions.md,
// "Simplicial factors below 64 flops per entry"). The heat factor tL + M is positive definite
// whenever every referenced vertex has mass, so it skips the numerical-singularity test (made
// for pinned Laplacians): a component of almost no area (a mollified zero-area piece of a soup,
// masses 1e-12 of the rest) gives pivots on its own scale, not a singular matrix (D-136).
PoissonOptions query_factor_options(HeatDistanceOptions::Precision precision, Index n_vertices,
                                    bool heat) {
  using Kernel = CholeskyOptions::SolveKernel;
  const bool mixed = precision == HeatDistanceOptions::Precision::kMixed;
  PoissonOptions o;
  if (mixed || n_vertices >= kOwnKernelVertices) {
    o.cholesky.solve_kernel =
        mixed && !heat ? Kernel::kSupernodalSingle : Kernel::kSupernodalDouble;
  } else {
    o.cholesky.simplicial_below_flops_per_entry = kSimplicialBelowFlopsPerEntry;
  }
  if (heat) o.cholesky.min_rcond = 0.0;
  return o;
}

// The boundary vertices of tri in increasing order: those flagged in `given` (inserted vertices
// beyond its size are interior) or, when it is empty, the ends of tri's boundary sides.
std::vector<Index> boundary_vertex_list(const IntrinsicTriangulation& tri,
                                        const std::vector<char>& given) {
  if (static_cast<Index>(given.size()) > tri.n_vertices()) {
    throw InvalidInput("HeatDistanceSolver: boundary_vertices has " + std::to_string(given.size()) +
                       " entries for " + std::to_string(tri.n_vertices()) + " vertices");
  }
  std::vector<char> on_boundary = given;
  if (given.empty()) {
    on_boundary.assign(tri.n_vertices(), 0);
    for (Index h = 0; h < tri.n_halfedges(); ++h) {
      if (tri.twin(h) == kInvalidIndex) on_boundary[tri.tail(h)] = on_boundary[tri.head(h)] = 1;
    }
  }
  std::vector<Index> list;
  for (Index v = 0; v < static_cast<Index>(on_boundary.size()); ++v) {
    if (on_boundary[v]) list.push_back(v);
  }
  return list;
}

// One halfedge's cotan term w (s × its cotan) in a region's Dirichlet system, its ends' unknown
// ids ui, uj (kInvalidIndex: a known value, phi_i / phi_j): on the counting pass (first) it is
// added to the diagonal and, where one end is known, moved to the right-hand side; on both
// passes the off-diagonal entry between two unknowns is emitted (lower triangle).
template <class Emit>
void region_term(double w, Index ui, Index uj, double phi_i, double phi_j, bool first,
                 Eigen::VectorXd& diag, Eigen::VectorXd& rhs, Emit& emit) {
  if (first) {
    if (ui != kInvalidIndex) {
      diag[ui] += w;
      if (uj == kInvalidIndex) rhs[ui] += w * phi_j;
    }
    if (uj != kInvalidIndex) {
      diag[uj] += w;
      if (ui == kInvalidIndex) rhs[uj] += w * phi_i;
    }
  }
  if (ui != kInvalidIndex && uj != kInvalidIndex) emit(std::max(ui, uj), std::min(ui, uj), -w);
}

// A band or region system's lower triangle straight into CSC, without triplets (D-365): the
// diagonal d (n values) and the strict lower entries that `visit(emit)` gives by
// emit(row, col, value) with row > col, duplicates allowed. visit is called twice (a counting
// pass, then a writing pass) and must emit the same entries both times; d is read after the
// first call, so that pass may sum it.
// Each column holds its diagonal first, then its rows in increasing order with duplicates
// summed in the order emitted (setFromTriplets()'s sums, bit for bit). The staging is the
// matrix's own arrays (12 bytes an emitted entry), trimmed after the merge.
template <class Visit>
fem::SparseMatrix lower_from_entries(const Eigen::VectorXd& d, Visit&& visit) {
  const Eigen::Index n = d.size();
  fem::SparseMatrix A(n, n);
  int* outer = A.outerIndexPtr();
  std::fill(outer, outer + n + 1, 1);
  outer[0] = 0;
  visit([outer](Index, Index col, double) { ++outer[col + 1]; });
  for (Eigen::Index j = 0; j < n; ++j) outer[j + 1] += outer[j];
  A.resizeNonZeros(outer[n]);
  int* inner = A.innerIndexPtr();
  double* value = A.valuePtr();
  std::vector<int> next(outer, outer + n);
  for (Eigen::Index j = 0; j < n; ++j) {
    inner[next[j]] = int(j);
    value[next[j]++] = d[j];
  }
  visit([&](Index row, Index col, double w) {
    const int k = next[std::size_t(col)]++;
    inner[k] = int(row);
    value[k] = w;
  });
  // per column: a stable sort by row, duplicates summed in order (the diagonal's row is the
  // column's smallest, so it stays first), then the columns made contiguous
  std::vector<int> count(static_cast<std::size_t>(n));
  for (Eigen::Index j = 0; j < n; ++j) {
    count[std::size_t(j)] =
        fem::sort_and_merge_column(inner + outer[j], value + outer[j], outer[j + 1] - outer[j]);
  }
  A.resizeNonZeros(fem::squeeze_columns(Index(n), count, outer, inner, value));
  A.data().squeeze();
  return A;
}

}  // namespace

void HeatDistanceOptions::validate() const {
  if (!(time_factor > 0.0) || !std::isfinite(time_factor)) {
    throw InvalidInput("HeatDistanceOptions: time_factor must be > 0, got " +
                       std::to_string(time_factor));
  }
  if (!(mean_edge_length >= 0.0) || !std::isfinite(mean_edge_length)) {
    throw InvalidInput("HeatDistanceOptions: mean_edge_length must be ≥ 0");
  }
  if (!(resolved_heat > 0.0 && resolved_heat <= 1.0 && trusted_heat >= resolved_heat &&
        trusted_heat <= 1.0)) {
    throw InvalidInput("HeatDistanceOptions: need 0 < resolved_heat ≤ trusted_heat ≤ 1");
  }
  solver.validate();
  if (max_constrained_sources < 0) {
    throw InvalidInput("HeatDistanceOptions: max_constrained_sources must be ≥ 0");
  }
  if (correction_steps < 0) {
    throw InvalidInput("HeatDistanceOptions: correction_steps must be ≥ 0, got " +
                       std::to_string(correction_steps));
  }
  if (!(band_span >= 0.0) || !std::isfinite(band_span)) {
    throw InvalidInput("HeatDistanceOptions: band_span must be ≥ 0 and finite, got " +
                       std::to_string(band_span));
  }
  if (!vertex_positions.allFinite()) {
    throw InvalidInput("HeatDistanceOptions: vertex_positions must be finite");
  }
}

void RefinedDistanceOptions::validate() const {
  if (!(resolution > 0.0 && std::isfinite(resolution))) {
    throw InvalidInput("RefinedDistanceOptions: resolution must be finite and > 0");
  }
  if (!(time_factor > 0.0 && std::isfinite(time_factor))) {
    throw InvalidInput("RefinedDistanceOptions: time_factor must be finite and > 0");
  }
  if (correction_steps < 0) {
    throw InvalidInput("RefinedDistanceOptions: correction_steps must be ≥ 0, got " +
                       std::to_string(correction_steps));
  }
}

struct HeatDistanceSolver::Impl {
  HeatDistanceOptions opt;
  IntrinsicTriangulation tri;
  Components comps;
  bool one_component = false;  // every vertex in component 0 (none unreferenced)
  fem::SparseMatrix L;         // empty on the multigrid path (build_multigrid)
  Eigen::VectorXd mass;
  double t = 0.0;      // time step, in units of scale²
  double scale = 1.0;  // tri's lengths are the input's divided by scale (a power of two)
  std::shared_ptr<const PoissonSolver> heat_neumann;  // (M + tL), Neumann (own or shared)
  std::optional<PoissonSolver> heat_dirichlet;        // (M + tL), u = 0 on the boundary
  std::optional<PoissonSolver> poisson;               // L, pure Neumann per component
  std::optional<UnitGradientDivergence> unit_div;     // div(−∇u/|∇u|) with tri's face layouts
  // options.path_bounds: upper bounds (tri's unit: × scale for absolute). The multigrid path
  // builds it on first use (clamp()), after a query's stages have freed their bands: its arcs
  // are not alive beside them at the query's peak.
  mutable PathGraph paths;
  bool paths_on_use = false;
  mutable std::once_flag paths_once;
  const PathGraph& path_graph() const {
    if (paths_on_use) std::call_once(paths_once, [this] { paths = PathGraph(tri); });
    return paths;
  }

  // options.path_bounds: d (absolute) clamped into [chord to the nearest vertex source, shortest
  // PathGraph path from the seeds (vertex, start length in tri's unit)].
  void clamp(Eigen::Ref<Eigen::VectorXd> d, const std::vector<std::pair<Index, double>>& seeds,
             const std::vector<Index>& vertex_sources) const {
    if (!opt.path_bounds) return;
    const Eigen::VectorXd upper = path_graph().shortest_paths(seeds) * scale;
    const Index rows = Index(opt.vertex_positions.rows());
    const bool chord =
        vertex_sources.size() <= 64 && std::all_of(vertex_sources.begin(), vertex_sources.end(),
                                                   [rows](Index v) { return v < rows; });
    clamp_to_bounds(d, upper, opt.vertex_positions, chord ? vertex_sources : std::vector<Index>{});
  }

  // (M + tL) u = δ for a vector or every column of a matrix (one pass over each factor): the
  // Neumann solution, or on meshes with boundary the mean of the Neumann and the zero-Dirichlet
  // ones, side by side on large meshes.
  template <class Values>
  Values heat(const Values& delta) const {
    auto solve = [&delta](const PoissonSolver& p) -> Values {
      if constexpr (std::is_same_v<Values, Eigen::VectorXd>) {
        const auto nd = Eigen::Index(p.dirichlet_vertices().size());
        return p.solve_weak(delta, Eigen::VectorXd::Zero(nd));
      } else {
        return p.solve_weak_homogeneous(delta);
      }
    };
    if (!heat_dirichlet) return solve(*heat_neumann);
    Values u, ud;
    std::vector<std::function<void()>> jobs = {[&] { u = solve(*heat_neumann); },
                                               [&] { ud = solve(*heat_dirichlet); }};
    if (tri.n_vertices() >= 20000) {
      run_parallel(jobs);
    } else {
      for (const auto& job : jobs) job();
    }
    u = 0.5 * (u + ud);
    return u;
  }

  // Per-component maximum heat (components with a source only; others 0).
  std::vector<double> component_max(const Eigen::VectorXd& u) const {
    std::vector<double> mx(comps.count, 0.0);
    for (Index v = 0; v < tri.n_vertices(); ++v) {
      const Index c = comps.label[v];
      if (c != kInvalidIndex && std::isfinite(u[v])) mx[c] = std::max(mx[c], u[v]);
    }
    return mx;
  }

  Eigen::VectorXd distance(const std::vector<WeightedPoint>& pts, HeatDistanceReport* rep) const;
  // Columns [first, first + k) of compute_distances(): single vertex sources through block
  // solves; a column whose heat underflows is recomputed by distance() (multi-stage).
  // The #V × block matrices of compute_distances(), kept between calls (a fresh one of more
  // than glibc's 32 MB mmap threshold page-faults on every call: at 1M faces blocks of 32 took
  // 1.54 s for 32 sources as fresh matrices, 1.00 s without the faults); the heat of a block, then
  // its divergences and distances.
  struct BlockScratch {
    Eigen::MatrixXd heat, phi;       // column-major blocks (distance_block)
    HugeVector heat_rows, phi_rows;  // row-major blocks (distance_block_rows)
  };
  // The solves' own row order, where the heat's and the Poisson factor's kernels share it (one
  // analysis: one fill-reducing order): a block kept in it through both solves needs no row
  // copies in and out of each (1M faces, k = 32: 256 MB a sweep). The divergence goes over
  // its faces in a breadth-first vertex order (on faces in the AMD order its accesses scatter;
  // docs/decisions.md, "Blocks of sources, session 12") and reads and writes each corner's
  // row where it is in the factor's order, through local_row ("... session 14").
  struct FactorOrder {
    std::vector<Index> vertex;     // row i of a block is vertex[i]
    std::vector<Index> row;        // vertex v is row row[v]
    std::vector<Index> local_row;  // the row of vertex number v of the breadth-first order
    std::optional<UnitGradientDivergence> div;  // unit_div in that order
  };
  mutable std::once_flag factor_order_once;
  mutable std::unique_ptr<FactorOrder> factor_order_;  // null: no shared order
  // The shared order, built on first use; null where the two orders differ or do not exist, or
  // where the vertices form several components (their labels would need the order too).
  const FactorOrder* factor_order() const;
  void distance_block_in_order(const FactorOrder& fo, const std::vector<Index>& sources,
                               Eigen::Index first, Eigen::Index k, Eigen::MatrixXd& out,
                               std::vector<HeatDistanceReport>& reps, BlockScratch& scratch) const;
  // The end of a row-major block (block column j: source src[j], output column out_col[j]):
  // columns whose heat underflowed somewhere (their minimum at or below the floor, or NaN) are
  // recomputed alone by distance() (multi-stage), the others get their reports and a 0 at the
  // source.
  void finish_block(const std::vector<Index>& src, const std::vector<Eigen::Index>& out_col,
                    const std::vector<double>& mx, const std::vector<double>& mn,
                    Eigen::MatrixXd& out, std::vector<HeatDistanceReport>& reps) const;
  mutable std::mutex block_mutex;  // guards block_scratch; a concurrent call uses its own
  mutable BlockScratch block_scratch;
  void distance_block(const std::vector<Index>& sources, Eigen::Index first, Eigen::Index k,
                      Eigen::MatrixXd& out, std::vector<HeatDistanceReport>& reps,
                      BlockScratch& scratch) const;
  // distance_block() in the solves' own row-major layout (k values per vertex contiguous): no
  // transposes between the heat solve, the divergence and the Poisson solve, and the k columns
  // of a corner or a row are one vector operation. Without boundary and correction steps, for
  // blocks of `block` sources; where CHOLMOD holds the factors (below kOwnKernelVertices), for
  // two or more (CholeskySolver::solve_rows then runs our kernel over its factor; one column
  // would be CHOLMOD's solve, with nothing for the rows to gain); writes scaled distances.
  bool rows_path(Eigen::Index block) const {
    const bool own_kernel = opt.precision == HeatDistanceOptions::Precision::kMixed ||
                            tri.n_vertices() >= kOwnKernelVertices;
    return (own_kernel || block >= 2) && !heat_dirichlet && opt.correction_steps == 0;
  }
  // Per column j of a row-major heat block H (#V × k): its largest finite value (mx) and its
  // smallest, NaN if any is NaN (mn), over the vertices of component comp[j]; two fixed halves
  // of the rows (on two threads when two_threads), merged.
  void heat_extremes(const double* H, Eigen::Index k, const std::vector<Index>& comp,
                     bool two_threads, std::vector<double>& mx, std::vector<double>& mn) const;
  void distance_block_rows(const std::vector<Index>& sources, Eigen::Index first, Eigen::Index k,
                           Eigen::MatrixXd& out, std::vector<HeatDistanceReport>& reps,
                           BlockScratch& scratch) const;
  // (M + tL) U = Δ for every column of U, written over it (no #V × k temporary without boundary)
  void heat_in_place(Eigen::Ref<Eigen::MatrixXd> U) const {
    if (heat_dirichlet) {
      U = heat(Eigen::MatrixXd(U));
    } else {
      PoissonBlocks::solve_in_place(*heat_neumann, U);
    }
  }
  // φ_j with L φ_j = div(−∇u_j/|∇u_j|) for the columns of U (on use_face[j] when not empty),
  // shifted so that φ_j(src[j]) = 0, into phi (#V × U.cols()): the first stage of distance() for
  // single vertex sources.
  void integrate_block(const Eigen::Ref<const Eigen::MatrixXd>& U, const std::vector<Index>& src,
                       const std::vector<std::vector<char>>& use_face,
                       Eigen::Ref<Eigen::MatrixXd> phi) const;
  Eigen::MatrixXd integrate_block(const Eigen::MatrixXd& U, const std::vector<Index>& src,
                                  const std::vector<std::vector<char>>& use_face) const {
    Eigen::MatrixXd phi(U.rows(), U.cols());
    integrate_block(U, src, use_face, phi);
    return phi;
  }
  // The sources' constraints on φ, set up once per query (the first stage and every correction
  // step use them): the first point of each component is shifted to 0, and φ(p_k) = φ(p_first)
  // for the others, by Lagrange multipliers through the cached pure-Neumann factor, or, for
  // many vertex sources, by a Dirichlet factorization.
  struct SourceConstraints {
    std::vector<Index> first;  // per component: its first point, or kInvalidIndex
    Index count = 0;           // constraints beyond the first point of each component
    Eigen::MatrixXd C, W;      // Lagrange: constraint columns and P C (P = the solution map)
    Eigen::VectorXd r;         // Cᵀφ = r: blend offsets of point k minus those of its first
    Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd> S;  // of Cᵀ P C
    std::optional<PoissonSolver> direct;  // Dirichlet: zero on every vertex source
  };
  SourceConstraints constraints(const std::vector<WeightedPoint>& pts) const;
  // φ with L φ = div(−∇u/|∇u|) on the faces use_face marks, under the constraints
  Eigen::VectorXd integrate_unit_field(const std::vector<WeightedPoint>& pts,
                                       const SourceConstraints& sc, const Eigen::VectorXd& u,
                                       const std::vector<char>& use_face) const;
  void later_stages(const std::vector<WeightedPoint>& pts, const std::vector<char>& src_comp,
                    Eigen::VectorXd& phi, std::vector<char>& known, HeatDistanceReport& rep) const;

  // One later stage's heat thresholds, per vertex of a component with a source (others 0), and
  // per component whether every unknown vertex in it is resolved.
  struct StageHeat {
    std::vector<char> resolved, trusted, comp_done;
  };
  // One later stage's region: resolved faces with an unknown vertex, in pieces that touch the
  // known region, and its unknown vertices numbered in face order.
  struct StageRegion {
    std::vector<char> use_face;
    std::vector<Index> unknown_id;  // vertex → unknown, or kInvalidIndex
    std::vector<Index> unknown_vertex;
  };
  // Vertices of components with a source whose distance is not known yet.
  Index count_unknown(const std::vector<char>& src_comp, const std::vector<char>& known) const;
  // Unit heat on the known vertices of faces that straddle the known region's frontier.
  Eigen::VectorXd frontier_delta(const std::vector<char>& known) const;
  // Resolved / trusted marks of the heat u and the components it resolves completely.
  StageHeat classify_heat(const Eigen::VectorXd& u, const std::vector<char>& src_comp,
                          const std::vector<char>& known) const;
  // The region of a later stage (faces all resolved, not all known, connected to a known vertex).
  StageRegion stage_region(const std::vector<char>& resolved, const std::vector<char>& known) const;
  // φ on the region's unknowns: L φ = div(−∇u/|∇u|) over its faces, known φ as Dirichlet values.
  Eigen::VectorXd solve_region(const StageRegion& region, const Eigen::VectorXd& u,
                               const Eigen::VectorXd& phi) const;

  // The multigrid path's later stages (docs/decisions.md D-285): each stage's heat is solved
  // directly on a band around the frontier (vertices within a path length of it) instead of by a
  // global PCG solve; the first stage and every Poisson solve on the whole surface stay multigrid.
  bool band_stages = false;
  double band_resolved_heat = 0.0;  // the options' thresholds before build_multigrid raised them
  double band_trusted_heat = 0.0;
  std::vector<char> on_boundary;  // #V: the surface's boundary (zero-Dirichlet heat), or empty
  std::vector<double> comp_area;  // per component, Σ mass (band_time(): the bands' step)
  std::vector<Index> vf_offset;   // vertex → incident faces (CSR, each face once per vertex)
  std::vector<Index> vf_face;
  struct Band {
    std::vector<Index> vertex;  // band vertices, in the order Dijkstra settled them
    std::vector<char> edge;     // per band vertex: on a face that is not in the band
    std::vector<Index> face;    // faces with every corner in the band
  };
  // One query's #V arrays for its band stages, made once and kept between the stages; each stage
  // resets only what its band touched, so that a stage's work is proportional to its band, not
  // to #V (D-355).
  struct BandScratch {
    std::vector<Index> local;       // vertex → position in the current band, or kInvalidIndex
    std::vector<double> dist;       // Dijkstra's path lengths: kInf outside the current band
    std::vector<char> is_frontier;  // known vertices on a face with an unknown corner
    std::vector<Index> frontier;    // the vertices is_frontier marks
    std::vector<Index> unknown;     // per component with a source: its unknown vertices
  };
  // A later stage's heat on its band: values and marks per band position (band.vertex), and per
  // component whether every unknown vertex in it is resolved.
  struct BandHeat {
    Band band;
    Eigen::VectorXd u;
    std::vector<char> resolved, trusted, comp_done;
  };
  // stage_region() on a band: its faces by increasing index, its unknowns numbered in that order
  struct BandRegion {
    std::vector<Index> face;
    std::vector<Index> unknown_id;  // per band position: the unknown's number, or kInvalidIndex
    std::vector<Index> unknown_vertex;
  };
  // The bands' factorizations (and their regions'): one solve each, so the supernodal factor is
  // solved as it is, not converted to simplicial form first.
  static CholeskyOptions band_cholesky() {
    CholeskyOptions o;
    o.simplicial_solves = false;
    return o;
  }
  // The bands' time step and its root (D-355): the query's t, or where kBandWidth·√t is narrower
  // than options.band_span × the square root of the largest area of a component with a source,
  // the step whose band is that wide (at icosphere(224), 1M faces and t = h², kBandWidth·√t is
  // 0.146·√area; widening the band in units of √t instead costs accuracy: 0.29 → 0.32 % there
  // at 3× the width, while a larger step gains it). The bands reach kBandWidth·root beyond the
  // frontier.
  struct BandTime {
    double t = 0.0, root = 0.0;
  };
  BandTime band_time(const std::vector<char>& src_comp) const;
  // Vertices within path length `width` of the frontier beyond it (unknown) and `behind` behind
  // it (known), their faces and edge; fills scratch.local and scratch.dist on the band only.
  Band make_band(const std::vector<char>& known, double width, double behind,
                 BandScratch& scratch) const;
  // Resets what make_band() wrote into the scratch.
  static void clear_band(const Band& band, BandScratch& scratch);
  // (M + tL) u = δ on the band's faces (δ = 1 on the frontier), natural conditions at the band's
  // edge; with Boundary::kAverage on a surface with boundary, the mean with the solution that is
  // zero on its boundary vertices; t = time_step. Per band position.
  Eigen::VectorXd band_solve(const Band& band, double time_step, const BandScratch& scratch) const;
  // A later stage's heat on a band: thresholds as classify_heat(), and the band's truncation
  // bounded by asking the heat to exceed kBand*Ratio × its largest value at the band's far edge;
  // the band doubles while that trusts no unknown vertex. The returned band stays in scratch.
  BandHeat band_heat(const std::vector<char>& src_comp, const std::vector<char>& known,
                     const BandTime& bt, BandScratch& scratch) const;
  // stage_region() and solve_region() on a band's faces only
  BandRegion band_region(const BandHeat& bh, const std::vector<char>& known,
                         const BandScratch& scratch) const;
  Eigen::VectorXd solve_band_region(const BandRegion& region, const BandHeat& bh,
                                    const Eigen::VectorXd& phi, const BandScratch& scratch) const;
  // After a stage made `added` known: the frontier's list and marks in scratch, from the old
  // frontier and the added vertices only.
  void advance_frontier(const std::vector<Index>& added, const std::vector<char>& known,
                        BandScratch& scratch) const;
  // later_stages() on bands
  void band_stages_loop(const std::vector<char>& src_comp, Eigen::VectorXd& phi,
                        std::vector<char>& known, HeatDistanceReport& rep) const;
};

namespace {

// Throws InvalidInput unless `heat` factors M + tL of im's triangulation with natural
// conditions: its unknowns, and the residual of one solve through im's own L and M.
void check_heat_factor(const HeatDistanceSolver::Impl& im, const PoissonSolver& heat) {
  // one solve: (M + tL) u = b with b varying per vertex, the residual through our own L, M
  const Index nv = im.tri.n_vertices();
  const auto referenced = Index(std::count_if(im.comps.label.begin(), im.comps.label.end(),
                                              [](Index c) { return c != kInvalidIndex; }));
  if (heat.n_unknowns() != referenced || !heat.dirichlet_vertices().empty()) {
    throw InvalidInput(
        "HeatDistanceSolver: the shared heat factor is not one of this triangulation "
        "(unknowns or Dirichlet vertices differ)");
  }
  Eigen::VectorXd b(nv);
  for (Index v = 0; v < nv; ++v) b[v] = im.mass[v] * double(1 + v % 7);
  const Eigen::VectorXd u = heat.solve_weak(b, Eigen::VectorXd());
  const Eigen::VectorXd Lu = im.L * u;
  const Eigen::VectorXd r = im.t * Lu + im.mass.cwiseProduct(u) - b;
  if (!(r.norm() <= 1e-8 * b.norm())) {
    throw InvalidInput(
        "HeatDistanceSolver: the shared heat factor is not M + tL of this triangulation "
        "and time step (relative residual " +
        std::to_string(r.norm() / b.norm()) + ")");
  }
}

// build_solver()'s multigrid path (SolverChoice): the heat and Poisson solvers run PCG with
// V-cycles on one hierarchy of im.tri from the provider; no shared analysis. The heat thresholds
// are raised to what an iterative heat solve resolves (D-231).
void build_multigrid(HeatDistanceSolver::Impl& im, const HeatDistanceOptions& options) {
  const double tol = options.solver.multigrid.tolerance;
  im.opt.resolved_heat = std::min(1.0, std::max(im.opt.resolved_heat, 1e3 * tol));
  im.opt.trusted_heat = std::min(1.0, std::max(im.opt.trusted_heat, 1e5 * tol));
  PoissonOptions poisson_opt;
  poisson_opt.solver = options.solver;
  poisson_opt.solver.kind = LinearSolverKind::kMultigrid;
  poisson_opt.prolongations =
      std::make_shared<const std::vector<SparseMatrix>>(options.solver.provider()(im.tri));
  PoissonOptions heat_opt = poisson_opt;
  heat_opt.screening = 1.0;  // tL + 1·M
  // positive definite by its masses, as the direct heat factor (query_factor_options): with zero
  // values on the boundary, a coarse vertex whose support lies almost all on it has a tiny
  // diagonal, not a singular one
  heat_opt.solver.multigrid.coarsest.min_rcond = 0.0;
  const std::vector<Index> boundary = boundary_vertex_list(im.tri, options.boundary_vertices);
  im.comps = connected_components(im.tri);
  // L is not kept: each multigrid solver holds its own operator (constraints() assembles it
  // again in the rare case that needs it), and tL lives only while the heat solvers are built
  fem::SparseMatrix L = fem::cotan_laplacian(im.tri);
  im.mass = fem::lumped_mass(im.tri);
  std::optional<fem::SparseMatrix> tL(im.t * L);
  im.unit_div.emplace(im.tri);
  im.paths_on_use = options.path_bounds;
  im.one_component =
      std::all_of(im.comps.label.begin(), im.comps.label.end(), [](Index c) { return c == 0; });
  im.heat_neumann =
      std::make_shared<const PoissonSolver>(*tL, im.mass, im.comps, std::vector<Index>{}, heat_opt);
  if (options.boundary == HeatDistanceOptions::Boundary::kAverage && !boundary.empty()) {
    im.heat_dirichlet.emplace(*tL, im.mass, im.comps, boundary, heat_opt);
  }
  tL.reset();
  // L's lower triangle has the pattern of M + tL's (the pinned rows kept as decoupled rows):
  // one set of index arrays for both (D-365)
  poisson_opt.multigrid_pattern = im.heat_neumann->multigrid_pattern();
  im.poisson.emplace(L, im.mass, im.comps, std::vector<Index>{}, poisson_opt);
  L = fem::SparseMatrix();
  // later stages on bands (D-285): the options' own thresholds, the boundary and the faces of
  // each vertex
  im.band_stages = true;
  im.comp_area.assign(std::size_t(im.comps.count), 0.0);
  for (Index v = 0; v < im.tri.n_vertices(); ++v) {
    const Index c = im.comps.label[v];
    if (c != kInvalidIndex) im.comp_area[std::size_t(c)] += im.mass[v];
  }
  im.band_resolved_heat = options.resolved_heat;
  im.band_trusted_heat = options.trusted_heat;
  if (im.heat_dirichlet) {
    im.on_boundary.assign(im.tri.n_vertices(), 0);
    for (const Index v : boundary) im.on_boundary[v] = 1;
  }
  const Index nv = im.tri.n_vertices(), nf = im.tri.n_faces();
  const auto& tail = im.tri.tails();
  auto corners = [&](Index f, auto&& visit) {  // each distinct corner of f once
    for (int c = 0; c < 3; ++c) {
      const Index v = tail[3 * f + c];
      if ((c > 0 && v == tail[3 * f]) || (c == 2 && v == tail[3 * f + 1])) continue;
      visit(v);
    }
  };
  im.vf_offset.assign(nv + 1, 0);
  for (Index f = 0; f < nf; ++f) corners(f, [&](Index v) { ++im.vf_offset[v + 1]; });
  for (Index v = 0; v < nv; ++v) im.vf_offset[v + 1] += im.vf_offset[v];
  im.vf_face.resize(std::size_t(im.vf_offset[nv]));
  std::vector<Index> fill(im.vf_offset.begin(), im.vf_offset.end() - 1);
  for (Index f = 0; f < nf; ++f) corners(f, [&](Index v) { im.vf_face[fill[v]++] = f; });
}

// The constructors: `heat` null builds the Neumann heat factor beside the others, else uses it
// (after checking that it is M + tL on the solver's triangulation).
// Long function: the set-up's order (checks, flips, scale, assembly beside the analysis, the
// factorizations side by side) reads best in one place.
void build_solver(HeatDistanceSolver::Impl& im, const IntrinsicTriangulation& tri_in,
                  const HeatDistanceOptions& options, std::shared_ptr<const PoissonSolver> heat) {
  options.validate();
  if (tri_in.n_faces() == 0) throw InvalidInput("HeatDistanceSolver: triangulation has no faces");
  if (options.vertex_positions.rows() > tri_in.n_vertices()) {
    throw InvalidInput("HeatDistanceOptions: vertex_positions has more rows than vertices");
  }
  const bool given_heat = heat != nullptr;
  im.opt = options;
  const double h_input = mean_edge_length(tri_in);
  im.tri = tri_in;
  if (options.intrinsic_delaunay) {
    const auto flips = im.tri.flip_to_delaunay();
    if (given_heat && flips.flips > 0) {
      throw InvalidInput(
          "HeatDistanceSolver: a shared heat factor needs a triangulation that is already "
          "intrinsic Delaunay (or intrinsic_delaunay = false)");
    }
  }
  double h = options.mean_edge_length;
  if (h == 0.0) {
    h = options.step_length == HeatDistanceOptions::StepLength::kInput ? h_input
                                                                       : mean_edge_length(im.tri);
  }
  if (!(h > 0.0)) throw InvalidInput("HeatDistanceSolver: mean edge length is 0");
  // Work in units of a power of two near h (exact): masses h², time steps and factors stay in
  // the double range for inputs from 1e-300 to 1e300, and the result is the same at every scale.
  im.scale = intrinsic::power_of_two_scale(h);
  if (given_heat && im.scale != 1.0) {
    throw InvalidInput(
        "HeatDistanceSolver: a shared heat factor needs h in [0.5, 1) in the triangulation's "
        "length unit, got h = " +
        std::to_string(h));
  }
  for (Index e = 0; e < im.tri.n_edges(); ++e) im.tri.set_length(e, im.tri.length(e) / im.scale);
  h /= im.scale;
  im.t = options.time_factor * h * h;
  // Two factorizations (three with boundary), each exactly once, side by side, from one
  // symbolic analysis: M + tL, its Dirichlet form and the pinned L keep L's pattern (constrained
  // vertices as decoupled rows). The analysis needs only the triangulation's edges, so it runs
  // beside the components, L, M, tL and the face layouts of the queries' divergence
  // (docs/decisions.md, "Small meshes: the analysis beside the assembly").
  // kAuto stays direct here: the iterative heat needs many more continuation stages (D-233)
  if (!given_heat && options.solver.kind == LinearSolverKind::kMultigrid &&
      options.solver.use_multigrid(im.tri.n_vertices())) {
    build_multigrid(im, options);
    return;
  }
  const PoissonOptions poisson_opt =
      query_factor_options(options.precision, im.tri.n_vertices(), false);
  PoissonOptions heat_opt = query_factor_options(options.precision, im.tri.n_vertices(), true);
  heat_opt.screening = 1.0;  // tL + 1·M
  const std::vector<Index> boundary = boundary_vertex_list(im.tri, options.boundary_vertices);
  const bool dirichlet_heat =
      options.boundary == HeatDistanceOptions::Boundary::kAverage && !boundary.empty();
  std::optional<CholeskyAnalysis> shared;
  fem::SparseMatrix tL;  // only for the heat factors built here
  run_parallel({[&] { shared.emplace(PoissonSolver::analyze(im.tri, poisson_opt.cholesky)); },
                [&] {
                  im.comps = connected_components(im.tri);
                  im.L = fem::cotan_laplacian(im.tri);
                  im.mass = fem::lumped_mass(im.tri);
                  if (!given_heat || dirichlet_heat) tL = im.t * im.L;
                  im.unit_div.emplace(im.tri);
                  if (options.path_bounds) im.paths = PathGraph(im.tri);
                }});
  const CholeskyAnalysis& analysis = *shared;
  im.one_component =
      std::all_of(im.comps.label.begin(), im.comps.label.end(), [](Index c) { return c == 0; });
  if (given_heat) {
    check_heat_factor(im, *heat);
    im.heat_neumann = std::move(heat);
  }
  std::vector<std::function<void()>> jobs;
  std::optional<PoissonSolver> own_heat;
  if (!given_heat) {
    jobs.emplace_back(
        [&] { own_heat.emplace(tL, im.mass, im.comps, std::vector<Index>{}, analysis, heat_opt); });
  }
  if (dirichlet_heat) {
    jobs.emplace_back(
        [&] { im.heat_dirichlet.emplace(tL, im.mass, im.comps, boundary, analysis, heat_opt); });
  }
  jobs.emplace_back([&] {
    im.poisson.emplace(im.L, im.mass, im.comps, std::vector<Index>{}, analysis, poisson_opt);
  });
  run_parallel(jobs);
  if (own_heat) im.heat_neumann = std::make_shared<const PoissonSolver>(std::move(*own_heat));
}

}  // namespace

HeatDistanceSolver::HeatDistanceSolver(const IntrinsicTriangulation& tri_in,
                                       const HeatDistanceOptions& options)
    : impl_(std::make_unique<Impl>()) {
  build_solver(*impl_, tri_in, options, nullptr);
}

HeatDistanceSolver::HeatDistanceSolver(const IntrinsicTriangulation& tri_in,
                                       const HeatDistanceOptions& options,
                                       std::shared_ptr<const PoissonSolver> heat)
    : impl_(std::make_unique<Impl>()) {
  if (!heat) throw InvalidInput("HeatDistanceSolver: the shared heat factor is null");
  build_solver(*impl_, tri_in, options, std::move(heat));
}

std::shared_ptr<const PoissonSolver> HeatDistanceSolver::heat_factor(
    const IntrinsicTriangulation& tri, double t, HeatDistanceOptions::Precision precision) {
  if (tri.n_faces() == 0) throw InvalidInput("HeatDistanceSolver::heat_factor: no faces");
  if (!(t > 0.0) || !std::isfinite(t)) {
    throw InvalidInput("HeatDistanceSolver::heat_factor: t must be > 0 and finite, got " +
                       std::to_string(t));
  }
  // as the constructor: the Poisson factor's analysis (shared there), the heat factor's options
  const PoissonOptions poisson_opt = query_factor_options(precision, tri.n_vertices(), false);
  PoissonOptions heat_opt = query_factor_options(precision, tri.n_vertices(), true);
  heat_opt.screening = 1.0;
  std::optional<CholeskyAnalysis> analysis;
  Components comps;
  fem::SparseMatrix tL;
  Eigen::VectorXd mass;
  run_parallel({[&] { analysis.emplace(PoissonSolver::analyze(tri, poisson_opt.cholesky)); },
                [&] {
                  comps = connected_components(tri);
                  mass = fem::lumped_mass(tri);
                  tL = t * fem::cotan_laplacian(tri);
                }});
  return std::make_shared<const PoissonSolver>(tL, mass, comps, std::vector<Index>{}, *analysis,
                                               heat_opt);
}

HeatDistanceSolver::~HeatDistanceSolver() = default;
HeatDistanceSolver::HeatDistanceSolver(HeatDistanceSolver&&) noexcept = default;
HeatDistanceSolver& HeatDistanceSolver::operator=(HeatDistanceSolver&&) noexcept = default;

const IntrinsicTriangulation& HeatDistanceSolver::triangulation() const { return impl_->tri; }
double HeatDistanceSolver::length_scale() const { return impl_->scale; }
double HeatDistanceSolver::time_step() const { return impl_->t * impl_->scale * impl_->scale; }

Eigen::VectorXd HeatDistanceSolver::compute_distance(const std::vector<Index>& sources,
                                                     HeatDistanceReport* report) const {
  if (sources.empty()) throw InvalidInput("heat distance: the source set is empty");
  const Impl& im = *impl_;
  std::vector<Index> s = sources;
  std::sort(s.begin(), s.end());
  s.erase(std::unique(s.begin(), s.end()), s.end());
  std::vector<WeightedPoint> pts;
  for (const Index v : s) {
    if (v < 0 || v >= im.tri.n_vertices()) {
      throw InvalidInput("heat distance: source vertex " + std::to_string(v) +
                         " out of range [0, " + std::to_string(im.tri.n_vertices()) + ")");
    }
    if (im.comps.label[v] == kInvalidIndex) {
      throw InvalidInput("heat distance: source vertex " + std::to_string(v) +
                         " is not referenced by any face");
    }
    WeightedPoint p;
    p.n = 1;
    p.vertex[0] = v;
    p.weight[0] = 1.0;
    pts.push_back(p);
  }
  Eigen::VectorXd d = im.distance(pts, report) * im.scale;
  std::vector<std::pair<Index, double>> seeds;
  for (const Index v : s) seeds.push_back({v, 0.0});
  im.clamp(d, seeds, s);
  return d;
}

Eigen::VectorXd HeatDistanceSolver::compute_distance_from_points(
    const std::vector<SurfacePoint>& sources, HeatDistanceReport* report) const {
  if (sources.empty()) throw InvalidInput("heat distance: the source set is empty");
  const Impl& im = *impl_;
  std::vector<WeightedPoint> pts;
  for (const SurfacePoint& sp : sources) {
    if (sp.face < 0 || sp.face >= im.tri.n_faces()) {
      throw InvalidInput("heat distance: source face " + std::to_string(sp.face) +
                         " out of range [0, " + std::to_string(im.tri.n_faces()) + ")");
    }
    if (!sp.bary.allFinite() || sp.bary.minCoeff() < -1e-12 ||
        std::abs(sp.bary.sum() - 1.0) > 1e-9) {
      throw InvalidInput("heat distance: barycentric coordinates of a source on face " +
                         std::to_string(sp.face) + " must be ≥ 0 and sum to 1");
    }
    // corner distances from the face's 2D layout
    const Eigen::Vector2d c[3] = {
        {0.0, 0.0}, {im.tri.halfedge_length(3 * sp.face), 0.0}, fem::face_corner2(im.tri, sp.face)};
    const Eigen::Vector2d x = sp.bary[0] * c[0] + sp.bary[1] * c[1] + sp.bary[2] * c[2];
    WeightedPoint p;
    p.n = 3;
    for (int i = 0; i < 3; ++i) {
      p.vertex[i] = im.tri.tail(3 * sp.face + i);
      p.weight[i] = std::max(0.0, sp.bary[i]);
      p.corner_distance[i] = (x - c[i]).norm();
    }
    pts.push_back(p);
  }
  Eigen::VectorXd d = im.distance(pts, report) * im.scale;
  std::vector<std::pair<Index, double>> seeds;
  for (const WeightedPoint& p : pts) {
    for (int i = 0; i < p.n; ++i) seeds.push_back({p.vertex[i], p.corner_distance[i]});
  }
  // the straight-line lower bound needs every source at a vertex (a point at a face's corner is
  // that vertex: the same distances as the vertex source)
  std::vector<Index> at_vertices;
  for (const SurfacePoint& sp : sources) {
    for (int i = 0; i < 3; ++i) {
      if (sp.bary[i] == 1.0) at_vertices.push_back(im.tri.tail(3 * sp.face + i));
    }
  }
  if (at_vertices.size() != sources.size()) at_vertices.clear();
  im.clamp(d, seeds, at_vertices);
  return d;
}

Eigen::MatrixXd HeatDistanceSolver::compute_distances(const std::vector<Index>& sources,
                                                      std::vector<HeatDistanceReport>* reports,
                                                      const ProgressCallback& on_progress) const {
  Eigen::MatrixXd out;
  compute_distances(sources, out, reports, on_progress);
  return out;
}

void HeatDistanceSolver::compute_distances(const std::vector<Index>& sources, Eigen::MatrixXd& out,
                                           std::vector<HeatDistanceReport>* reports,
                                           const ProgressCallback& on_progress) const {
  if (sources.empty()) throw InvalidInput("heat distance: the source list is empty");
  const Impl& im = *impl_;
  const Index nv = im.tri.n_vertices();
  for (std::size_t j = 0; j < sources.size(); ++j) {
    const Index v = sources[j];
    const std::string name = "heat distance: sources[" + std::to_string(j) + "] = ";
    if (v < 0 || v >= nv) {
      throw InvalidInput(name + std::to_string(v) + " out of range [0, " + std::to_string(nv) +
                         ")");
    }
    if (im.comps.label[v] == kInvalidIndex) {
      throw InvalidInput(name + std::to_string(v) + " is not referenced by any face");
    }
  }
  const auto k = Eigen::Index(sources.size());
  // Blocks of up to 32 columns; the block's matrices (its heat and distances here, the solve
  // kernel's two copies) stay at 256 MB each, 32M/#V columns.
  const auto by_memory = Eigen::Index(3.2e7 / double(std::max<Index>(nv, 1)));
  const Eigen::Index block = std::min<Eigen::Index>(std::clamp<Eigen::Index>(by_memory, 4, 32), k);
  std::unique_lock<std::mutex> lock(im.block_mutex, std::try_to_lock);
  Impl::BlockScratch own;
  Impl::BlockScratch& scratch = lock.owns_lock() ? im.block_scratch : own;
  if (out.rows() != nv || out.cols() != k) {
    out.resize(nv, k);
    advise_huge_pages(out.data(), sizeof(double) * std::size_t(out.size()));  // not yet touched
  }
  std::vector<HeatDistanceReport> reps(sources.size());
  // the path bounds cost about as much as the solves (BENCHMARKS.md "Path bounds"): half the bar
  ProgressMeter meter(on_progress, "heat distances", double(im.opt.path_bounds ? 2 * k : k));
  if (im.rows_path(block)) {
    for (HugeVector* m : {&scratch.heat_rows, &scratch.phi_rows}) {
      if (m->size() < std::size_t(nv) * std::size_t(block)) m->resize(std::size_t(nv) * block);
    }
    for (Eigen::Index first = 0; first < k; first += block) {
      im.distance_block_rows(sources, first, std::min(block, k - first), out, reps, scratch);
      meter.update(double(std::min(first + block, k)));
    }
  } else {
    for (Eigen::MatrixXd* m : {&scratch.heat, &scratch.phi}) {
      if (m->rows() != nv || m->cols() < block) m->resize(nv, block);
    }
    for (Eigen::Index first = 0; first < k; first += block) {
      im.distance_block(sources, first, std::min(block, k - first), out, reps, scratch);
      meter.update(double(std::min(first + block, k)));
    }
    out *= im.scale;
  }
  if (im.opt.path_bounds) {
    for (Eigen::Index j = 0; j < k; ++j) {
      const Index v = sources[std::size_t(j)];
      im.clamp(out.col(j), {{v, 0.0}}, {v});
      meter.update(double(k + j + 1));
    }
  }
  meter.finish();
  if (reports) *reports = std::move(reps);
}

void HeatDistanceSolver::Impl::distance_block(const std::vector<Index>& sources, Eigen::Index first,
                                              Eigen::Index k, Eigen::MatrixXd& out,
                                              std::vector<HeatDistanceReport>& reps,
                                              BlockScratch& scratch) const {
  const Index nv = tri.n_vertices();
  auto u = scratch.heat.leftCols(k);  // the deltas, then their heat
  u.setZero();
  for (Eigen::Index j = 0; j < k; ++j) u(sources[std::size_t(first + j)], j) = 1.0;
  heat_in_place(u);
  std::vector<Index> batch, alone;  // columns by block solve / by distance()
  for (Eigen::Index j = 0; j < k; ++j) {
    const Index s = sources[std::size_t(first + j)];
    const Index c = comps.label[s];
    double mx = 0.0;
    for (Index v = 0; v < nv; ++v) {
      if (comps.label[v] == c && std::isfinite(u(v, j))) mx = std::max(mx, u(v, j));
    }
    const double floor = std::max(opt.resolved_heat * mx, kAbsoluteHeatFloor);
    bool resolved = true;
    for (Index v = 0; v < nv && resolved; ++v) resolved = comps.label[v] != c || u(v, j) > floor;
    (resolved ? batch : alone).push_back(Index(j));
  }
  for (const Index j : alone) {  // multi-stage continuation, one source at a time
    WeightedPoint p;
    p.n = 1;
    p.vertex[0] = sources[std::size_t(first + j)];
    p.weight[0] = 1.0;
    out.col(first + j) = distance({p}, &reps[std::size_t(first + j)]);
  }
  if (batch.empty()) return;
  std::vector<Index> src;
  for (const Index j : batch) src.push_back(sources[std::size_t(first + j)]);
  auto phi = scratch.phi.leftCols(Eigen::Index(batch.size()));
  if (Eigen::Index(batch.size()) == k) {
    integrate_block(u, src, {}, phi);
  } else {
    Eigen::MatrixXd ub(nv, Eigen::Index(batch.size()));
    for (std::size_t b = 0; b < batch.size(); ++b) ub.col(Eigen::Index(b)) = u.col(batch[b]);
    integrate_block(ub, src, {}, phi);
  }
  for (int step = 0; step < opt.correction_steps; ++step) {
    // as distance(): integrate ∇φ/|∇φ| again over the faces where φ is finite
    std::vector<std::vector<char>> finite_face(src.size());
    Eigen::MatrixXd minus_phi = -phi;
    for (std::size_t b = 0; b < src.size(); ++b) {
      auto col = minus_phi.col(Eigen::Index(b));
      for (Index v = 0; v < nv; ++v) {
        if (!std::isfinite(col[v])) col[v] = 0.0;
      }
      finite_face[b].assign(std::size_t(tri.n_faces()), 1);
      for (Index f = 0; f < tri.n_faces(); ++f) {
        for (int c = 0; c < 3; ++c) {
          if (!std::isfinite(phi(tri.tail(3 * f + c), Eigen::Index(b)))) finite_face[b][f] = 0;
        }
      }
    }
    const Eigen::MatrixXd next = integrate_block(minus_phi, src, finite_face);
    phi = (phi.array().isFinite()).select(next, phi);
  }
  for (std::size_t b = 0; b < src.size(); ++b) {
    auto col = phi.col(Eigen::Index(b));
    col = col.cwiseMax(0.0);
    col[src[b]] = 0.0;
    out.col(first + batch[b]) = col;
    reps[std::size_t(first + batch[b])] = HeatDistanceReport{};
  }
}

namespace {

// The vertices in breadth-first order over the faces, from the lowest-numbered vertex of each
// component: vertex v becomes number order[v] (unreferenced vertices last). Neighbours get
// nearby numbers (igea: a face's corners 8428 apart on average in file order, 502 here).
std::vector<Index> breadth_first_order(const IntrinsicTriangulation& tri) {
  const Index nv = tri.n_vertices(), nf = tri.n_faces();
  std::vector<Index> start(static_cast<std::size_t>(nv) + 1, 0), next(3 * std::size_t(nf));
  for (Index c = 0; c < 3 * nf; ++c) ++start[std::size_t(tri.tail(c)) + 1];
  std::partial_sum(start.begin(), start.end(), start.begin());
  std::vector<Index> fill(start.begin(), start.end() - 1);
  for (Index c = 0; c < 3 * nf; ++c) {  // each corner: the next corner of its face
    next[std::size_t(fill[std::size_t(tri.tail(c))]++)] = tri.tail(c - c % 3 + (c % 3 + 1) % 3);
  }
  std::vector<Index> order(static_cast<std::size_t>(nv), kInvalidIndex), queue;
  queue.reserve(std::size_t(nv));
  Index count = 0;
  for (Index s = 0; s < nv; ++s) {
    if (order[std::size_t(s)] != kInvalidIndex ||
        start[std::size_t(s)] == start[std::size_t(s) + 1]) {
      continue;
    }
    order[std::size_t(s)] = count++;
    queue.push_back(s);
    for (std::size_t q = queue.size() - 1; q < queue.size(); ++q) {
      const Index v = queue[q];
      for (Index e = start[std::size_t(v)]; e < start[std::size_t(v) + 1]; ++e) {
        const Index w = next[std::size_t(e)];
        if (order[std::size_t(w)] == kInvalidIndex) {
          order[std::size_t(w)] = count++;
          queue.push_back(w);
        }
      }
    }
  }
  for (Index& o : order) {
    if (o == kInvalidIndex) o = count++;
  }
  return order;
}

// Calls tile(t0, t1) on the vertices [0, nv) in tiles of 64 (a block's rows to the output's
// columns: the tile's rows stay in cache while each column is written), two halves of the
// vertices on two threads when two_threads.
void over_vertex_tiles(Index nv, bool two_threads, const std::function<void(Index, Index)>& tile) {
  constexpr Index kTile = 64;
  run_halves(two_threads, [&](int half) {
    const Index v1 = nv * (half + 1) / 2;
    for (Index t0 = nv * half / 2; t0 < v1; t0 += kTile) tile(t0, std::min(v1, t0 + kTile));
  });
}

}  // namespace

void HeatDistanceSolver::Impl::heat_extremes(const double* H, Eigen::Index k,
                                             const std::vector<Index>& comp, bool two_threads,
                                             std::vector<double>& mx,
                                             std::vector<double>& mn) const {
  const Index nv = tri.n_vertices();
  const auto kk = std::size_t(k);
  const bool one_source_component =
      std::all_of(comp.begin(), comp.end(), [&](Index c) { return c == comp[0]; });
  std::vector<double> half_mx[2], half_mn[2];
  run_halves(two_threads, [&](int half) {
    std::vector<double>& hx = half_mx[half];
    std::vector<double>& hn = half_mn[half];
    const Index v0 = nv * half / 2, v1 = nv * (half + 1) / 2;
    if (one_source_component) {
      // the sources in one component (the common case): the rows of that component
      hx.assign(kk, 0.0);
      hn.assign(kk, kInf);
      const Index* label = one_component ? nullptr : comps.label.data();
      extremes_of_rows(H, v0, v1, k, label, comp[0], hx.data(), hn.data());
      return;
    }
    // sources in several components: column by column (one pass over the rows per column)
    hx.resize(kk);
    hn.resize(kk);
    for (std::size_t j = 0; j < kk; ++j) {
      double x_max = 0.0, x_min = kInf;
      for (Index v = v0; v < v1; ++v) {
        if (comps.label[v] != comp[j]) continue;
        const double x = H[v * k + Index(j)];
        x_max = x > x_max && x <= std::numeric_limits<double>::max() ? x : x_max;
        x_min = x < x_min || x != x ? x : x_min;
      }
      hx[j] = x_max;
      hn[j] = x_min;
    }
  });
  mx.resize(kk);
  mn.resize(kk);
  for (std::size_t j = 0; j < kk; ++j) {
    const double a = half_mn[0][j], b = half_mn[1][j];
    mx[j] = std::max(half_mx[0][j], half_mx[1][j]);
    mn[j] = a != a ? a : b != b || b < a ? b : a;  // a NaN in either half stays
  }
}

void HeatDistanceSolver::Impl::finish_block(const std::vector<Index>& src,
                                            const std::vector<Eigen::Index>& out_col,
                                            const std::vector<double>& mx,
                                            const std::vector<double>& mn, Eigen::MatrixXd& out,
                                            std::vector<HeatDistanceReport>& reps) const {
  for (std::size_t j = 0; j < src.size(); ++j) {
    const double floor = std::max(opt.resolved_heat * mx[j], kAbsoluteHeatFloor);
    HeatDistanceReport& rep = reps[std::size_t(out_col[j])];
    rep = HeatDistanceReport{};
    out(src[j], out_col[j]) = 0.0;
    if (mn[j] > floor) continue;
    // underflowing heat: the multi-stage continuation of distance(), one source at a time
    WeightedPoint p;
    p.n = 1;
    p.vertex[0] = src[j];
    p.weight[0] = 1.0;
    out.col(out_col[j]) = distance({p}, &rep) * scale;
  }
}

const HeatDistanceSolver::Impl::FactorOrder* HeatDistanceSolver::Impl::factor_order() const {
  std::call_once(factor_order_once, [this] {
    const std::vector<int>* heat_order = PoissonBlocks::block_order(*heat_neumann);
    const std::vector<int>* poisson_order = PoissonBlocks::block_order(*poisson);
    if (!one_component || !heat_order || !poisson_order || *heat_order != *poisson_order) return;
    auto fo = std::make_unique<FactorOrder>();
    fo->vertex.assign(heat_order->begin(), heat_order->end());
    fo->row.resize(fo->vertex.size());
    for (std::size_t i = 0; i < fo->vertex.size(); ++i) {
      fo->row[std::size_t(fo->vertex[i])] = Index(i);
    }
    const std::vector<Index> near = breadth_first_order(tri);
    fo->local_row.resize(fo->vertex.size());
    for (std::size_t i = 0; i < fo->vertex.size(); ++i) {
      fo->local_row[std::size_t(near[std::size_t(fo->vertex[i])])] = Index(i);
    }
    fo->div.emplace(unit_div->relabeled(near));
    factor_order_ = std::move(fo);
  });
  return factor_order_.get();
}

void HeatDistanceSolver::Impl::distance_block_in_order(
    const FactorOrder& fo, const std::vector<Index>& sources, Eigen::Index first, Eigen::Index k,
    Eigen::MatrixXd& out, std::vector<HeatDistanceReport>& reps, BlockScratch& scratch) const {
  const Index nv = tri.n_vertices();
  double* H = scratch.heat_rows.data();  // deltas, then heat (fo's order)
  double* P = scratch.phi_rows.data();   // divergences, then φ (fo's order)
  const bool two_threads = std::int64_t(nv) * k >= kParallelBlockValues;
  run_halves(two_threads,
             [&](int half) { std::fill(H + nv * half / 2 * k, H + nv * (half + 1) / 2 * k, 0.0); });
  // the block's columns in the order of their sources' rows: the sources of a subtree of the
  // factor adjacent, so that the heat's forward pass runs each supernode on the few columns
  // whose source lies below it (block column j is output column out_col[j])
  const auto kk = static_cast<std::size_t>(k);
  std::vector<Eigen::Index> out_col(kk);
  std::iota(out_col.begin(), out_col.end(), first);
  auto row_of = [&](Eigen::Index c) { return fo.row[std::size_t(sources[std::size_t(c)])]; };
  std::stable_sort(out_col.begin(), out_col.end(),
                   [&](Eigen::Index a, Eigen::Index b) { return row_of(a) < row_of(b); });
  std::vector<Index> src(kk), comp(kk, 0), source_row(kk);
  for (std::size_t j = 0; j < kk; ++j) {
    src[j] = sources[std::size_t(out_col[j])];
    source_row[j] = row_of(out_col[j]);
    H[source_row[j] * k + Index(j)] = 1.0;
  }
  PoissonBlocks::solve_rows_in_order(*heat_neumann, H, k, true, source_row.data());
  // the heat's extremes (one component: over every row)
  std::vector<double> mx, mn;
  heat_extremes(H, k, comp, two_threads, mx, mn);
  // the divergence (fo.div: faces in a breadth-first order, for locality) reading and writing
  // each corner's rows where they are in the factor's order (fo.local_row), into P: no copies
  // to its order and back (1M faces, a block of 32: 13 and 12 ms; docs/decisions.md, "Blocks of
  // sources, session 14")
  // Its faces in three parts (add_rows_part()): the two halves of the order side by side on every
  // column (a face's 32 columns at once: 1M faces 41.6 -> 33.5 ms against two column halves over
  // every face), then the band between them by column halves.
  const Eigen::Index mid = UnitGradientDivergence::column_split(k);
  const Index* at_row = fo.local_row.data();
  run_halves(two_threads,
             [&](int half) { std::fill(P + nv * half / 2 * k, P + nv * (half + 1) / 2 * k, 0.0); });
  run_halves(two_threads,
             [&](int half) { fo.div->add_rows_part(H, k, P, half, 0, k, at_row, at_row); });
  run_halves(two_threads && mid < k, [&](int half) {
    fo.div->add_rows_part(H, k, P, 2, half == 0 ? 0 : mid, half == 0 ? mid : k, at_row, at_row);
  });
  // the Poisson solve's compatibility sums aᵀ·div (two halves of the rows, summed as it would)
  const Eigen::VectorXd* a = PoissonBlocks::compatibility_weights(*poisson);
  std::vector<double> half_sum[2];
  if (a) {
    run_halves(two_threads, [&](int half) {
      half_sum[half].assign(kk, 0.0);
      double* __restrict sum = half_sum[half].data();
      const Index i1 = nv * (half + 1) / 2;
      for (Index i = nv * half / 2; i < i1; ++i) {
        const double* __restrict p = P + i * k;
        const double av = (*a)[fo.vertex[std::size_t(i)]];
        for (Eigen::Index j = 0; j < k; ++j) sum[j] += av * p[j];
      }
    });
    for (std::size_t j = 0; j < kk; ++j) half_sum[0][j] += half_sum[1][j];
  }
  // φ − φ(source) below
  PoissonBlocks::solve_rows_in_order(*poisson, P, k, false, nullptr,
                                     a ? half_sum[0].data() : nullptr);
  std::vector<double> shift(static_cast<std::size_t>(k));
  for (Eigen::Index j = 0; j < k; ++j) {
    shift[std::size_t(j)] = P[fo.row[std::size_t(src[std::size_t(j)])] * k + j];
  }
  // out = max(φ − φ(source), 0)·scale: rows (in fo's order) to columns (vertex order)
  std::vector<double*> out_cols(kk);
  for (std::size_t j = 0; j < kk; ++j) out_cols[j] = out.col(out_col[j]).data();
  over_vertex_tiles(nv, two_threads, [&](Index t0, Index t1) {
    rows_to_output(P, fo.row.data(), t0, t1, k, shift.data(), scale, out_cols.data());
  });
  finish_block(src, out_col, mx, mn, out, reps);
}

void HeatDistanceSolver::Impl::distance_block_rows(const std::vector<Index>& sources,
                                                   Eigen::Index first, Eigen::Index k,
                                                   Eigen::MatrixXd& out,
                                                   std::vector<HeatDistanceReport>& reps,
                                                   BlockScratch& scratch) const {
  if (k >= 2) {
    if (const FactorOrder* fo = factor_order()) {
      distance_block_in_order(*fo, sources, first, k, out, reps, scratch);
      return;
    }
  }
  const Index nv = tri.n_vertices();
  double* H = scratch.heat_rows.data();  // the deltas, then their heat
  double* P = scratch.phi_rows.data();   // the divergences, then φ
  const bool two_threads = std::int64_t(nv) * k >= kParallelBlockValues;
  run_halves(two_threads,
             [&](int half) { std::fill(H + nv * half / 2 * k, H + nv * (half + 1) / 2 * k, 0.0); });
  std::vector<Index> src(static_cast<std::size_t>(k)), comp(static_cast<std::size_t>(k));
  for (Eigen::Index j = 0; j < k; ++j) {
    src[std::size_t(j)] = sources[std::size_t(first + j)];
    comp[std::size_t(j)] = comps.label[src[std::size_t(j)]];
    H[src[std::size_t(j)] * k + j] = 1.0;
  }
  PoissonBlocks::solve_rows_in_place(*heat_neumann, H, k);
  // resolved: every vertex of the source's component above the floor, i.e. its minimum (NaN
  // kept) above resolved_heat × its largest finite value
  std::vector<double> mx, mn;
  heat_extremes(H, k, comp, two_threads, mx, mn);
  // the divergence: two ranges of columns on two threads (run_halves(), as every step of the
  // block)
  const Eigen::Index mid = UnitGradientDivergence::column_split(k);
  run_halves(two_threads && mid < k, [&](int half) {
    unit_div->apply_rows(H, k, P, half == 0 ? 0 : mid, half == 0 ? mid : k);
  });
  PoissonBlocks::solve_rows_in_place(*poisson, P, k, false);  // φ − φ(source) below
  std::vector<double> shift(static_cast<std::size_t>(k));
  for (Eigen::Index j = 0; j < k; ++j) shift[std::size_t(j)] = P[src[std::size_t(j)] * k + j];
  // out = max(φ − φ(source), 0)·scale on the source's component, ∞ elsewhere: rows to columns
  over_vertex_tiles(nv, two_threads, [&](Index t0, Index t1) {
    for (Eigen::Index j = 0; j < k; ++j) {
      double* o = out.col(first + j).data();
      const Index c = comp[std::size_t(j)];
      const double sh = shift[std::size_t(j)];
      for (Index v = t0; v < t1; ++v) {
        o[v] = comps.label[v] == c ? std::max(P[v * k + j] - sh, 0.0) * scale : kInf;
      }
    }
  });
  std::vector<Eigen::Index> out_col(static_cast<std::size_t>(k));
  std::iota(out_col.begin(), out_col.end(), first);
  finish_block(src, out_col, mx, mn, out, reps);
}

void HeatDistanceSolver::Impl::integrate_block(const Eigen::Ref<const Eigen::MatrixXd>& U,
                                               const std::vector<Index>& src,
                                               const std::vector<std::vector<char>>& use_face,
                                               Eigen::Ref<Eigen::MatrixXd> phi) const {
  const Index nv = tri.n_vertices();
  unit_div->apply_columns(U, use_face, phi);
  PoissonBlocks::solve_in_place(*poisson, phi);
  for (Eigen::Index j = 0; j < U.cols(); ++j) {
    const Index c = comps.label[src[std::size_t(j)]];
    const double shift = phi(src[std::size_t(j)], j);
    for (Index v = 0; v < nv; ++v) {
      phi(v, j) = comps.label[v] == c ? phi(v, j) - shift : kInf;
    }
  }
}

Eigen::VectorXd HeatDistanceSolver::Impl::distance(const std::vector<WeightedPoint>& pts,
                                                   HeatDistanceReport* report) const {
  HeatDistanceReport rep;
  const Index nv = tri.n_vertices();
  Eigen::VectorXd delta = Eigen::VectorXd::Zero(nv);
  std::vector<char> src_comp(comps.count, 0);
  for (const WeightedPoint& p : pts) {
    for (Index i = 0; i < p.n; ++i) delta[p.vertex[i]] += p.weight[i];
    src_comp[comps.label[p.vertex[0]]] = 1;
  }
  const Eigen::VectorXd u = heat(delta);
  // resolved vertices / faces
  const std::vector<double> mx = component_max(u);
  std::vector<char> resolved(nv, 0);
  for (Index v = 0; v < nv; ++v) {
    const Index c = comps.label[v];
    if (c == kInvalidIndex || !src_comp[c]) continue;
    const double floor = std::max(opt.resolved_heat * mx[c], kAbsoluteHeatFloor);
    resolved[v] = u[v] > floor ? 1 : 0;
    if (!resolved[v]) ++rep.unresolved_vertices;
  }
  std::vector<char> use_face(tri.n_faces(), 1);
  if (rep.unresolved_vertices > 0) {
    for (Index f = 0; f < tri.n_faces(); ++f) {
      use_face[f] = resolved[tri.tail(3 * f)] && resolved[tri.tail(3 * f + 1)] &&
                    resolved[tri.tail(3 * f + 2)];
    }
  }
  const SourceConstraints sc = constraints(pts);
  rep.constraints = sc.count;
  Eigen::VectorXd phi = integrate_unit_field(pts, sc, u, use_face);
  std::vector<char> known(nv, 0);
  for (Index v = 0; v < nv; ++v) {
    const Index c = comps.label[v];
    if (c == kInvalidIndex || !src_comp[c]) {
      phi[v] = kInf;
      continue;
    }
    if (rep.unresolved_vertices == 0 || !opt.resolve_underflow) {
      known[v] = 1;
    } else {
      const double trust = std::max(opt.trusted_heat * mx[c], kAbsoluteHeatFloor);
      known[v] = u[v] >= trust ? 1 : 0;
    }
  }
  // sources are always known
  for (const WeightedPoint& p : pts) {
    if (p.is_vertex()) known[p.vertex[0]] = 1;
  }
  if (rep.unresolved_vertices > 0 && opt.resolve_underflow) {
    for (Index v = 0; v < nv; ++v) {
      if (!known[v] && std::isfinite(phi[v])) phi[v] = kInf;
    }
    later_stages(pts, src_comp, phi, known, rep);
  }
  for (int step = 0; step < opt.correction_steps; ++step) {
    // φ ← the integral of ∇φ/|∇φ| (the heat method's second half applied to φ itself, on
    // the faces where φ is finite, with the same source constraints)
    Eigen::VectorXd minus_phi(nv);
    for (Index v = 0; v < nv; ++v) minus_phi[v] = std::isfinite(phi[v]) ? -phi[v] : 0.0;
    std::vector<char> finite_face(tri.n_faces(), 1);
    for (Index f = 0; f < tri.n_faces(); ++f) {
      for (int k = 0; k < 3; ++k) {
        if (!std::isfinite(phi[tri.tail(3 * f + k)])) finite_face[f] = 0;
      }
    }
    const Eigen::VectorXd next = integrate_unit_field(pts, sc, minus_phi, finite_face);
    for (Index v = 0; v < nv; ++v) {
      if (std::isfinite(phi[v])) phi[v] = next[v];
    }
  }
  for (Index v = 0; v < nv; ++v) {
    if (phi[v] < 0.0) phi[v] = 0.0;
  }
  for (const WeightedPoint& p : pts) {
    if (p.is_vertex()) phi[p.vertex[0]] = 0.0;
  }
  if (report) *report = rep;
  return phi;
}

HeatDistanceSolver::Impl::SourceConstraints HeatDistanceSolver::Impl::constraints(
    const std::vector<WeightedPoint>& pts) const {
  const Index nv = tri.n_vertices();
  SourceConstraints sc;
  // first source of each component, and the extra constraints φ(p_k) − φ(p_first) = 0
  sc.first.assign(comps.count, kInvalidIndex);
  std::vector<std::pair<Index, Index>> extra;  // (point k, first point of its component)
  for (Index k = 0; k < Index(pts.size()); ++k) {
    const Index c = comps.label[pts[k].vertex[0]];
    if (sc.first[c] == kInvalidIndex) {
      sc.first[c] = k;
    } else {
      extra.emplace_back(k, sc.first[c]);
    }
  }
  sc.count = Index(extra.size());
  if (extra.empty()) return sc;
  const Index m = sc.count;
  // dense n×m right-hand sides: keep them below ~160 MB
  const Index by_memory = Index(std::max<double>(1.0, 2e7 / double(std::max<Index>(nv, 1))));
  const bool all_vertices =
      std::all_of(pts.begin(), pts.end(), [](const WeightedPoint& p) { return p.is_vertex(); });
  if (m <= std::min(opt.max_constrained_sources, by_memory) || !all_vertices) {
    // Lagrange multipliers through the cached pure-Neumann factor: with P the solution map,
    // C the constraint columns, φ = P b − P C λ and Cᵀφ = 0.
    sc.C = Eigen::MatrixXd::Zero(nv, m);
    sc.r = Eigen::VectorXd::Zero(m);
    for (Index j = 0; j < m; ++j) {
      const WeightedPoint& pk = pts[extra[j].first];
      const WeightedPoint& p0 = pts[extra[j].second];
      sc.r[j] = pk.blend_offset() - p0.blend_offset();
      for (Index i = 0; i < pk.n; ++i) sc.C(pk.vertex[i], j) += pk.weight[i];
      for (Index i = 0; i < p0.n; ++i) sc.C(p0.vertex[i], j) -= p0.weight[i];
    }
    sc.W = poisson->solve_weak_homogeneous(sc.C);
    sc.S.compute(sc.C.transpose() * sc.W);
  } else {
    // many vertex sources: zero Dirichlet values on all of them (one new factorization)
    std::vector<Index> dv;
    for (const WeightedPoint& p : pts) dv.push_back(p.vertex[0]);
    fem::SparseMatrix assembled;  // the multigrid path keeps no L: assembled again here
    const fem::SparseMatrix& lap = L.nonZeros() > 0 ? L : (assembled = fem::cotan_laplacian(tri));
    sc.direct.emplace(lap, mass, comps, dv, PoissonOptions{});
  }
  return sc;
}

Eigen::VectorXd HeatDistanceSolver::Impl::integrate_unit_field(
    const std::vector<WeightedPoint>& pts, const SourceConstraints& sc, const Eigen::VectorXd& u,
    const std::vector<char>& use_face) const {
  const Index nv = tri.n_vertices();
  const Eigen::VectorXd b = unit_div->apply(u, &use_face);
  Eigen::VectorXd phi;
  if (sc.direct) {
    const auto n_dirichlet = Eigen::Index(sc.direct->dirichlet_vertices().size());
    phi = sc.direct->solve_weak(b, Eigen::VectorXd::Zero(n_dirichlet));
  } else {
    phi = poisson->solve_weak(b, Eigen::VectorXd());
    if (sc.count > 0) phi -= sc.W * sc.S.solve(sc.C.transpose() * phi - sc.r);
  }
  // shift each component so that its first source is at 0
  auto value_at = [&](const Eigen::VectorXd& f, const WeightedPoint& p) {
    double s = 0.0;
    for (Index i = 0; i < p.n; ++i) s += p.weight[i] * f[p.vertex[i]];
    return s;
  };
  std::vector<double> shift(comps.count, 0.0);
  for (Index c = 0; c < comps.count; ++c) {
    if (sc.first[c] == kInvalidIndex) continue;
    const WeightedPoint& p = pts[sc.first[c]];
    shift[c] = value_at(phi, p) - p.blend_offset();
  }
  for (Index v = 0; v < nv; ++v) {
    const Index c = comps.label[v];
    if (c != kInvalidIndex) phi[v] -= shift[c];
  }
  return phi;
}

Index HeatDistanceSolver::Impl::count_unknown(const std::vector<char>& src_comp,
                                              const std::vector<char>& known) const {
  Index r = 0;
  for (Index v = 0; v < tri.n_vertices(); ++v) {
    const Index c = comps.label[v];
    if (c != kInvalidIndex && src_comp[c] && !known[v]) ++r;
  }
  return r;
}

Eigen::VectorXd HeatDistanceSolver::Impl::frontier_delta(const std::vector<char>& known) const {
  const auto& tail = tri.tails();
  Eigen::VectorXd delta = Eigen::VectorXd::Zero(tri.n_vertices());
  for (Index f = 0; f < tri.n_faces(); ++f) {
    const Index a = tail[3 * f], b = tail[3 * f + 1], c = tail[3 * f + 2];
    const int k = known[a] + known[b] + known[c];
    if (k == 0 || k == 3) continue;
    if (known[a]) delta[a] = 1.0;
    if (known[b]) delta[b] = 1.0;
    if (known[c]) delta[c] = 1.0;
  }
  return delta;
}

HeatDistanceSolver::Impl::StageHeat HeatDistanceSolver::Impl::classify_heat(
    const Eigen::VectorXd& u, const std::vector<char>& src_comp,
    const std::vector<char>& known) const {
  const Index nv = tri.n_vertices();
  const std::vector<double> mx = component_max(u);
  StageHeat sh;
  sh.resolved.assign(nv, 0);
  sh.trusted.assign(nv, 0);
  sh.comp_done.assign(comps.count, 1);
  for (Index v = 0; v < nv; ++v) {
    const Index c = comps.label[v];
    if (c == kInvalidIndex || !src_comp[c]) continue;
    sh.resolved[v] = u[v] > std::max(opt.resolved_heat * mx[c], kAbsoluteHeatFloor);
    sh.trusted[v] = u[v] >= std::max(opt.trusted_heat * mx[c], kAbsoluteHeatFloor);
    if (!known[v] && !sh.resolved[v]) sh.comp_done[c] = 0;
  }
  return sh;
}

HeatDistanceSolver::Impl::StageRegion HeatDistanceSolver::Impl::stage_region(
    const std::vector<char>& resolved, const std::vector<char>& known) const {
  const Index nv = tri.n_vertices();
  const Index nf = tri.n_faces();
  const auto& tail = tri.tails();
  // resolved faces with an unknown vertex; drop pieces without a known vertex
  StageRegion region;
  std::vector<char>& use_face = region.use_face;
  use_face.assign(nf, 0);
  UnionFind pieces(nv);
  for (Index f = 0; f < nf; ++f) {
    const Index a = tail[3 * f], b = tail[3 * f + 1], c = tail[3 * f + 2];
    if (!(resolved[a] && resolved[b] && resolved[c])) continue;
    if (known[a] && known[b] && known[c]) continue;
    use_face[f] = 1;
    pieces.unite(a, b);
    pieces.unite(a, c);
  }
  std::vector<char> piece_known(nv, 0);
  for (Index f = 0; f < nf; ++f) {
    if (!use_face[f]) continue;
    for (int i = 0; i < 3; ++i) {
      if (known[tail[3 * f + i]]) piece_known[pieces.find(tail[3 * f + i])] = 1;
    }
  }
  region.unknown_id.assign(nv, kInvalidIndex);
  for (Index f = 0; f < nf; ++f) {
    if (!use_face[f]) continue;
    if (!piece_known[pieces.find(tail[3 * f])]) {
      use_face[f] = 0;
      continue;
    }
    for (int i = 0; i < 3; ++i) {
      const Index v = tail[3 * f + i];
      if (!known[v] && region.unknown_id[v] == kInvalidIndex) {
        region.unknown_id[v] = Index(region.unknown_vertex.size());
        region.unknown_vertex.push_back(v);
      }
    }
  }
  return region;
}

Eigen::VectorXd HeatDistanceSolver::Impl::solve_region(const StageRegion& region,
                                                       const Eigen::VectorXd& u,
                                                       const Eigen::VectorXd& phi) const {
  // stiffness from the region's faces, Dirichlet = known values
  const Eigen::VectorXd div = unit_div->apply(u, &region.use_face);
  const Index nu = Index(region.unknown_vertex.size());
  Eigen::VectorXd rhs(nu);
  for (Index i = 0; i < nu; ++i) rhs[i] = div[region.unknown_vertex[i]];
  const double s = 0.5 / tri.multiplicity();
  // the lower triangle only (the factorization reads no more), straight into CSC: the diagonal
  // and the right-hand side in the counting pass, the off-diagonal entries in both
  Eigen::VectorXd diag = Eigen::VectorXd::Zero(nu);
  bool first_pass = true;
  const fem::SparseMatrix A = lower_from_entries(diag, [&](auto&& emit) {
    for (Index f = 0; f < tri.n_faces(); ++f) {
      if (!region.use_face[f]) continue;
      for (int k = 0; k < 3; ++k) {
        const Index h = 3 * f + k;
        const Index i = tri.tail(h), j = tri.head(h);
        if (i == j) continue;
        const Index ui = region.unknown_id[i], uj = region.unknown_id[j];
        if (ui == kInvalidIndex && uj == kInvalidIndex) continue;
        region_term(s * intrinsic::halfedge_cotan(tri, h), ui, uj, phi[i], phi[j], first_pass, diag,
                    rhs, emit);
      }
    }
    first_pass = false;
  });
  const CholeskySolver chol(A, CholeskyOptions{});
  return chol.solve(rhs);
}

HeatDistanceSolver::Impl::BandTime HeatDistanceSolver::Impl::band_time(
    const std::vector<char>& src_comp) const {
  double largest = 0.0;
  for (Index c = 0; c < comps.count; ++c) {
    if (src_comp[c]) largest = std::max(largest, comp_area[std::size_t(c)]);
  }
  const double root = opt.band_span * std::sqrt(largest) / kBandWidth;
  if (!(root > std::sqrt(t))) return {t, std::sqrt(t)};  // the query's own step, bit for bit
  return {root * root, root};
}

HeatDistanceSolver::Impl::Band HeatDistanceSolver::Impl::make_band(const std::vector<char>& known,
                                                                   double width, double behind,
                                                                   BandScratch& scratch) const {
  const auto& tail = tri.tails();
  Band band;
  std::vector<Index>& local = scratch.local;
  std::vector<double>& dist = scratch.dist;
  // Dijkstra along the edges from the frontier, known vertices up to `behind` (every vertex it
  // reaches is settled, so the band's vertices are all that dist and local hold afterwards)
  using Item = std::pair<double, Index>;
  std::priority_queue<Item, std::vector<Item>, std::greater<>> queue;
  for (const Index v : scratch.frontier) {
    dist[v] = 0.0;
    queue.push({0.0, v});
  }
  while (!queue.empty()) {
    const auto [d, v] = queue.top();
    queue.pop();
    if (d > dist[v] || local[v] != kInvalidIndex) continue;
    local[v] = Index(band.vertex.size());
    band.vertex.push_back(v);
    for (Index k = vf_offset[v]; k < vf_offset[v + 1]; ++k) {
      const Index f = vf_face[k];
      for (int c = 0; c < 3; ++c) {
        const Index a = tail[3 * f + c], b = tail[3 * f + (c + 1) % 3];
        if (a == b || (a != v && b != v)) continue;
        const Index w = a == v ? b : a;
        const double nd = d + tri.halfedge_length(3 * f + c);
        if (nd <= (known[w] ? behind : width) && nd < dist[w]) {
          dist[w] = nd;
          queue.push({nd, w});
        }
      }
    }
  }
  // faces with every corner in the band (listed at their first corner), and the band's edge
  band.edge.assign(band.vertex.size(), 0);
  for (Index i = 0; i < Index(band.vertex.size()); ++i) {
    const Index v = band.vertex[i];
    for (Index k = vf_offset[v]; k < vf_offset[v + 1]; ++k) {
      const Index f = vf_face[k];
      const bool inside = local[tail[3 * f]] != kInvalidIndex &&
                          local[tail[3 * f + 1]] != kInvalidIndex &&
                          local[tail[3 * f + 2]] != kInvalidIndex;
      if (!inside) {
        band.edge[i] = 1;
      } else if (tail[3 * f] == v) {
        band.face.push_back(f);
      }
    }
  }
  return band;
}

void HeatDistanceSolver::Impl::clear_band(const Band& band, BandScratch& scratch) {
  for (const Index v : band.vertex) {
    scratch.local[v] = kInvalidIndex;
    scratch.dist[v] = kInf;
  }
}

Eigen::VectorXd HeatDistanceSolver::Impl::band_solve(const Band& band, double time_step,
                                                     const BandScratch& scratch) const {
  const Index n = Index(band.vertex.size());
  const double s = time_step * 0.5 / tri.multiplicity();
  // one system per boundary condition: `fixed` vertices are zero (the surface's boundary)
  auto solve = [&](bool dirichlet) {
    std::vector<Index> id(std::size_t(n), kInvalidIndex);
    Index m = 0;
    for (Index i = 0; i < n; ++i) {
      if (!(dirichlet && on_boundary[band.vertex[i]])) id[i] = m++;
    }
    Eigen::VectorXd u = Eigen::VectorXd::Zero(n);
    if (m == 0) return u;
    Eigen::VectorXd rhs = Eigen::VectorXd::Zero(m);
    Eigen::VectorXd diag(m);
    for (Index i = 0; i < n; ++i) {
      if (id[i] == kInvalidIndex) continue;
      diag[id[i]] = mass[band.vertex[i]];
      if (scratch.is_frontier[band.vertex[i]]) rhs[id[i]] = 1.0;
    }
    // lower triangle (all CHOLMOD reads), straight into CSC; the diagonal in the counting pass
    bool first_pass = true;
    const fem::SparseMatrix A = lower_from_entries(diag, [&](auto&& emit) {
      for (const Index f : band.face) {
        for (int k = 0; k < 3; ++k) {
          const Index h = 3 * f + k;
          if (tri.tail(h) == tri.head(h)) continue;
          const Index i = id[scratch.local[tri.tail(h)]], j = id[scratch.local[tri.head(h)]];
          if (i == kInvalidIndex && j == kInvalidIndex) continue;
          const double w = s * intrinsic::halfedge_cotan(tri, h);
          if (first_pass) {
            if (i != kInvalidIndex) diag[i] += w;
            if (j != kInvalidIndex) diag[j] += w;
          }
          if (i != kInvalidIndex && j != kInvalidIndex) emit(std::max(i, j), std::min(i, j), -w);
        }
      }
      first_pass = false;
    });
    CholeskyOptions chol = band_cholesky();
    chol.min_rcond = 0.0;  // positive definite (masses), as the global heat factor
    const Eigen::VectorXd x = CholeskySolver(A, chol).solve(rhs);
    for (Index i = 0; i < n; ++i) {
      if (id[i] != kInvalidIndex) u[i] = x[id[i]];
    }
    return u;
  };
  Eigen::VectorXd u = solve(false);
  if (!on_boundary.empty()) u = 0.5 * (u + solve(true));
  return u;
}

HeatDistanceSolver::Impl::BandHeat HeatDistanceSolver::Impl::band_heat(
    const std::vector<char>& src_comp, const std::vector<char>& known, const BandTime& bt,
    BandScratch& scratch) const {
  std::size_t last_size = 0;
  for (double width = kBandWidth * bt.root;; width *= 2.0) {
    BandHeat bh;
    bh.band = make_band(known, width, kBandBehind * bt.root, scratch);
    const Band& band = bh.band;
    const Index n = Index(band.vertex.size());
    bh.u = band_solve(band, bt.t, scratch);
    const Eigen::VectorXd& u = bh.u;
    // per component: the largest heat, and the largest on an unknown vertex of the band's edge
    std::vector<double> mx(comps.count, 0.0), edge_mx(comps.count, 0.0);
    for (Index i = 0; i < n; ++i) {
      const Index v = band.vertex[i];
      const Index c = comps.label[v];
      mx[c] = std::max(mx[c], u[i]);
      if (band.edge[i] && !known[v]) edge_mx[c] = std::max(edge_mx[c], u[i]);
    }
    bh.resolved.assign(std::size_t(n), 0);
    bh.trusted.assign(std::size_t(n), 0);
    // a component is done when the band resolves all its unknown vertices (none outside it is)
    std::vector<Index> resolved_unknown(comps.count, 0);
    for (Index i = 0; i < n; ++i) {
      const Index v = band.vertex[i];
      const Index c = comps.label[v];
      const double floor = std::max(
          {band_resolved_heat * mx[c], kAbsoluteHeatFloor, kBandResolvedRatio * edge_mx[c]});
      const double trust =
          std::max({band_trusted_heat * mx[c], kAbsoluteHeatFloor, kBandTrustedRatio * edge_mx[c]});
      bh.resolved[i] = u[i] > floor;
      bh.trusted[i] = u[i] >= trust;
      if (bh.resolved[i] && !known[v]) ++resolved_unknown[c];
    }
    bh.comp_done.assign(comps.count, 1);
    for (Index c = 0; c < comps.count; ++c) {
      if (src_comp[c] && resolved_unknown[c] < scratch.unknown[c]) bh.comp_done[c] = 0;
    }
    bool progress = false;
    for (Index i = 0; i < n && !progress; ++i) {
      const Index v = band.vertex[i];
      progress = !known[v] && (bh.trusted[i] || bh.comp_done[comps.label[v]]);
    }
    // grow the band while it trusts nothing (and still grows)
    if (progress || band.vertex.size() == last_size) return bh;
    last_size = band.vertex.size();
    clear_band(band, scratch);
  }
}

HeatDistanceSolver::Impl::BandRegion HeatDistanceSolver::Impl::band_region(
    const BandHeat& bh, const std::vector<char>& known, const BandScratch& scratch) const {
  const Index n = Index(bh.band.vertex.size());
  const auto& tail = tri.tails();
  const std::vector<Index>& local = scratch.local;
  // resolved faces with an unknown vertex (in face order, as stage_region()); drop pieces
  // without a known vertex
  std::vector<Index> faces = bh.band.face;
  std::sort(faces.begin(), faces.end());
  std::vector<Index> use;
  UnionFind pieces(n);
  for (const Index f : faces) {
    const Index a = tail[3 * f], b = tail[3 * f + 1], c = tail[3 * f + 2];
    const Index la = local[a], lb = local[b], lc = local[c];
    if (!(bh.resolved[la] && bh.resolved[lb] && bh.resolved[lc])) continue;
    if (known[a] && known[b] && known[c]) continue;
    use.push_back(f);
    pieces.unite(la, lb);
    pieces.unite(la, lc);
  }
  std::vector<char> piece_known(std::size_t(n), 0);
  for (const Index f : use) {
    for (int i = 0; i < 3; ++i) {
      const Index v = tail[3 * f + i];
      if (known[v]) piece_known[pieces.find(local[v])] = 1;
    }
  }
  BandRegion region;
  region.unknown_id.assign(std::size_t(n), kInvalidIndex);
  for (const Index f : use) {
    if (!piece_known[pieces.find(local[tail[3 * f]])]) continue;
    region.face.push_back(f);
    for (int i = 0; i < 3; ++i) {
      const Index v = tail[3 * f + i];
      if (!known[v] && region.unknown_id[local[v]] == kInvalidIndex) {
        region.unknown_id[local[v]] = Index(region.unknown_vertex.size());
        region.unknown_vertex.push_back(v);
      }
    }
  }
  return region;
}

Eigen::VectorXd HeatDistanceSolver::Impl::solve_band_region(const BandRegion& region,
                                                            const BandHeat& bh,
                                                            const Eigen::VectorXd& phi,
                                                            const BandScratch& scratch) const {
  const Index n = Index(bh.band.vertex.size());
  const std::vector<Index>& local = scratch.local;
  // the divergence on the region's faces, summed as UnitGradientDivergence::apply() sums them
  const auto split =
      std::lower_bound(region.face.begin(), region.face.end(), unit_div->face_split());
  const auto below = Index(split - region.face.begin());
  Eigen::VectorXd div = Eigen::VectorXd::Zero(n);
  unit_div->add_faces(region.face.data(), below, bh.u.data(), local.data(), div.data());
  if (split != region.face.end()) {
    Eigen::VectorXd upper = Eigen::VectorXd::Zero(n);
    unit_div->add_faces(region.face.data() + below, Index(region.face.size()) - below, bh.u.data(),
                        local.data(), upper.data());
    div += upper;
  }
  // stiffness from the region's faces, Dirichlet = known values (as solve_region())
  const Index nu = Index(region.unknown_vertex.size());
  Eigen::VectorXd rhs(nu);
  for (Index i = 0; i < nu; ++i) rhs[i] = div[local[region.unknown_vertex[i]]];
  const double s = 0.5 / tri.multiplicity();
  Eigen::VectorXd diag = Eigen::VectorXd::Zero(nu);
  bool first_pass = true;  // the diagonal and the right-hand side in the counting pass
  const fem::SparseMatrix A = lower_from_entries(diag, [&](auto&& emit) {
    for (const Index f : region.face) {
      for (int k = 0; k < 3; ++k) {
        const Index h = 3 * f + k;
        const Index i = tri.tail(h), j = tri.head(h);
        if (i == j) continue;
        const Index ui = region.unknown_id[local[i]], uj = region.unknown_id[local[j]];
        if (ui == kInvalidIndex && uj == kInvalidIndex) continue;
        region_term(s * intrinsic::halfedge_cotan(tri, h), ui, uj, phi[i], phi[j], first_pass, diag,
                    rhs, emit);
      }
    }
    first_pass = false;
  });
  return CholeskySolver(A, band_cholesky()).solve(rhs);
}

void HeatDistanceSolver::Impl::band_stages_loop(const std::vector<char>& src_comp,
                                                Eigen::VectorXd& phi, std::vector<char>& known,
                                                HeatDistanceReport& rep) const {
  const Index nv = tri.n_vertices();
  BandScratch scratch;
  scratch.local.assign(nv, kInvalidIndex);
  scratch.dist.assign(nv, kInf);
  scratch.is_frontier.assign(nv, 0);
  scratch.unknown.assign(comps.count, 0);
  // the only passes over every vertex: the unknowns per component and the first frontier
  Index left = 0;
  for (Index v = 0; v < nv; ++v) {
    const Index c = comps.label[v];
    if (c != kInvalidIndex && src_comp[c] && !known[v]) {
      ++scratch.unknown[c];
      ++left;
    }
  }
  {
    const Eigen::VectorXd delta = frontier_delta(known);
    for (Index v = 0; v < nv; ++v) {
      if (delta[v] != 0.0) {
        scratch.frontier.push_back(v);
        scratch.is_frontier[v] = 1;
      }
    }
  }
  const BandTime bt = band_time(src_comp);
  std::vector<Index> added;
  while (left > 0) {
    ++rep.stages;
    const BandHeat bh = band_heat(src_comp, known, bt, scratch);
    const BandRegion region = band_region(bh, known, scratch);
    if (region.unknown_vertex.empty()) {
      throw SolverError("heat distance: the heat does not reach " + std::to_string(left) +
                        " vertices beyond stage " + std::to_string(rep.stages - 1) +
                        " (no resolved face next to the known region)");
    }
    // Poisson on the region; keep the trusted values (all, where the component is resolved)
    const Eigen::VectorXd y = solve_band_region(region, bh, phi, scratch);
    added.clear();
    for (Index i = 0; i < Index(region.unknown_vertex.size()); ++i) {
      const Index v = region.unknown_vertex[i];
      const Index c = comps.label[v];
      if (bh.trusted[scratch.local[v]] || bh.comp_done[c]) {
        known[v] = 1;
        phi[v] = y[i];
        added.push_back(v);
        --scratch.unknown[c];
      }
    }
    if (added.empty()) {
      throw SolverError("heat distance: no progress at stage " + std::to_string(rep.stages) + " (" +
                        std::to_string(left) + " vertices left)");
    }
    left -= Index(added.size());
    clear_band(bh.band, scratch);
    advance_frontier(added, known, scratch);
  }
}

void HeatDistanceSolver::Impl::advance_frontier(const std::vector<Index>& added,
                                                const std::vector<char>& known,
                                                BandScratch& scratch) const {
  const auto& tail = tri.tails();
  // a known vertex is on the frontier while one of its faces has an unknown corner
  auto on_frontier = [&](Index v) {
    for (Index k = vf_offset[v]; k < vf_offset[v + 1]; ++k) {
      const Index f = vf_face[k];
      if (!known[tail[3 * f]] || !known[tail[3 * f + 1]] || !known[tail[3 * f + 2]]) return true;
    }
    return false;
  };
  // the old frontier's vertices that still border an unknown one, and the new known vertices
  // that do (no other vertex can join it: the unknown set only shrinks)
  std::vector<Index> next;
  for (const Index v : scratch.frontier) {
    if (on_frontier(v)) {
      next.push_back(v);
    } else {
      scratch.is_frontier[v] = 0;
    }
  }
  for (const Index v : added) {
    if (on_frontier(v)) {
      next.push_back(v);
      scratch.is_frontier[v] = 1;
    }
  }
  scratch.frontier = std::move(next);
}

void HeatDistanceSolver::Impl::later_stages(const std::vector<WeightedPoint>& pts,
                                            const std::vector<char>& src_comp, Eigen::VectorXd& phi,
                                            std::vector<char>& known,
                                            HeatDistanceReport& rep) const {
  (void)pts;
  if (band_stages) {
    band_stages_loop(src_comp, phi, known, rep);
    return;
  }
  Index left = count_unknown(src_comp, known);
  while (left > 0) {
    ++rep.stages;
    // heat from the frontier of the known region on the whole surface (cached factors)
    const Eigen::VectorXd u = heat(frontier_delta(known));
    const StageHeat sh = classify_heat(u, src_comp, known);
    const StageRegion region = stage_region(sh.resolved, known);
    if (region.unknown_vertex.empty()) {
      throw SolverError("heat distance: the heat does not reach " + std::to_string(left) +
                        " vertices beyond stage " + std::to_string(rep.stages - 1) +
                        " (no resolved face next to the known region)");
    }
    // Poisson on the region; keep the trusted values (all, where the component is resolved)
    const Eigen::VectorXd y = solve_region(region, u, phi);
    Index added = 0;
    for (Index i = 0; i < Index(region.unknown_vertex.size()); ++i) {
      const Index v = region.unknown_vertex[i];
      if (sh.trusted[v] || sh.comp_done[comps.label[v]]) {
        known[v] = 1;
        phi[v] = y[i];
        ++added;
      }
    }
    if (added == 0) {
      throw SolverError("heat distance: no progress at stage " + std::to_string(rep.stages) + " (" +
                        std::to_string(left) + " vertices left)");
    }
    left = count_unknown(src_comp, known);
  }
}

Eigen::VectorXd heat_distance(const IntrinsicTriangulation& tri, const std::vector<Index>& sources,
                              const HeatDistanceOptions& options) {
  if (sources.empty()) throw InvalidInput("heat_distance: the source set is empty");
  const HeatDistanceSolver solver(tri, options);
  return solver.compute_distance(sources);
}

}  // namespace ifem::solvers
