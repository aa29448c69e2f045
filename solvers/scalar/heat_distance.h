// Geodesic distance by the heat method (Crane, Weischedel, Wardetzky, "Geodesics in Heat",
// ACM TOG 2013; "The Heat Method for Distance Computation", CACM 2017) on the intrinsic
// Delaunay triangulation, with a multi-stage continuation where the heat underflows.
#pragma once

#include <Eigen/Core>
#include <memory>
#include <vector>

#include "intrinsic/core/geometry.h"
#include "intrinsic/core/progress.h"
#include "intrinsic/core/surface_point.h"
#include "intrinsic/core/triangulation.h"
#include "intrinsic/core/types.h"
#include "solvers/scalar/solver_choice.h"

namespace ifem::solvers {

class PoissonSolver;

/// A point on the surface (face + barycentric coordinates); for HeatDistanceSolver sources the
/// face is one of triangulation()'s.
using SurfacePoint = intrinsic::SurfacePoint;

/// Options of HeatDistanceSolver.
struct HeatDistanceOptions {
  /// m in t = m·h²: the heat time step relative to the squared mean edge length h² (m > 0,
  /// dimensionless; t is in squared length units).
  double time_factor = 1.0;
  /// Which triangulation's mean edge length (intrinsic::mean_edge_length) gives h when
  /// mean_edge_length is 0. Default kInput, the paper's h (why: docs/decisions.md, "Heat step
  /// length"; accuracy per mesh: BENCHMARKS.md, "Heat-method accuracy").
  enum class StepLength {
    kInput,              ///< the triangulation passed in (before the solver's Delaunay flips)
    kIntrinsicDelaunay,  ///< the intrinsic Delaunay triangulation (edges are longer)
  };
  StepLength step_length = StepLength::kInput;
  /// h itself, when > 0: absolute, in the triangulation's length unit (e.g. the input mesh's
  /// intrinsic::robust_side_length, as solvers::distance_options sets it, when the caller hands
  /// over a triangulation that is already intrinsic Delaunay or refined). 0: computed as
  /// step_length says. ≥ 0.
  double mean_edge_length = 0.0;
  /// Flip a copy of the triangulation to intrinsic Delaunay first (flips keep vertex ids).
  bool intrinsic_delaunay = true;
  /// Boundary condition of the heat step on meshes with boundary: the mean of the Neumann
  /// and the zero-Dirichlet solutions (the paper's recommendation), or Neumann only.
  enum class Boundary { kAverage, kNeumann };
  Boundary boundary = Boundary::kAverage;
  /// The boundary of the surface, as a #V mask, when it is not the triangulation's own: a
  /// tufted cover has no boundary (its boundary edges are glued front to back), so callers pass
  /// the input mesh's boundary vertices here (intrinsic::SurfaceTriangulation::boundary_vertex).
  /// Empty: the triangulation's boundary.
  std::vector<char> boundary_vertices;
  /// Continue where the heat underflows (see HeatDistanceSolver). Off: faces where the heat
  /// is not resolved get a zero vector field, and distances there are unreliable.
  bool resolve_underflow = true;
  /// A vertex's heat is resolved when u > resolved_heat × (max u in its component);
  /// vertices are trusted (final) at a stage when u ≥ trusted_heat × max. Both relative to
  /// that maximum: 0 < resolved_heat ≤ trusted_heat ≤ 1.
  double resolved_heat = 1e-270;
  double trusted_heat = 1e-180;
  /// Largest number of extra zero-distance constraints (several sources in one component)
  /// handled with the cached factorization (k back-substitutions); above it, vertex sources
  /// become Dirichlet conditions of a freshly factored Poisson problem. ≥ 0.
  Index max_constrained_sources = 64;
  /// Correction steps after the heat method: φ ← the solution of L φ = div(∇φ/|∇φ|) with the
  /// same source constraints, i.e. the method's second half applied to its own result (a
  /// fixed-point iteration of the eikonal normalization; cf. Belyaev & Fayolle, "On variational
  /// and PDE-based distance function approximations", CGF 2015). Each step costs a divergence
  /// and one back-substitution with the cached factor. It pays off with a small time step on a
  /// fine mesh (RefinedDistanceOptions), not at the paper's t = h² (docs/decisions.md,
  /// "Accurate distance mode"). ≥ 0; default 0 (the paper's method).
  int correction_steps = 0;
  /// Precision of the factor values the query's triangular solves read (factorizations and
  /// every other operation are double). kMixed: the Poisson factor (L) as floats, half its
  /// bytes per solve; the distances move by at most 3.2e-7 relative to kDouble's on every
  /// reference mesh. The heat factor (M + tL) stays double in both: its solution decays far
  /// below float's range (1e-38) on large meshes, where a float heat factor moved igea's
  /// distances by 3e-2. Default kDouble: on this project's machine a solve is not bound by
  /// memory bandwidth (one thread reads the factor at 7.7 of its 14 GB/s), and converting the
  /// float blocks cost more than the bytes saved (docs/decisions.md, "Heat queries: our
  /// supernodal solve kernel"); kMixed is for machines or workloads that are bandwidth-bound.
  enum class Precision { kDouble, kMixed };
  Precision precision = Precision::kDouble;
  /// Clamp every result into bounds that hold for the exact geodesic distance (solvers/scalar/
  /// path_bounds.h): at most the shortest path along the triangulation's edges and the flat
  /// diagonals of its convex diamonds (PathGraph; from a surface point, from its face's corners),
  /// and, for vertex sources, at least the straight-line distance to the nearest source when
  /// vertex_positions is given. A clamp into a true interval never increases any vertex's error;
  /// with it the default distance is at or below CGAL's heat method's mean error on every
  /// reference (docs/decisions.md D-141). Cost: a Dijkstra over ~12 arcs per vertex per query,
  /// and per column of compute_distances(), where it outweighs the block solves: set it off for
  /// throughput (figures: BENCHMARKS.md, "Path bounds"). Off: the heat method's values as they are.
  bool path_bounds = true;
  /// Positions (absolute, the triangulation's length unit) of vertices 0..rows−1 (rows ≤ #V,
  /// e.g. the input mesh's vertices before refinement inserted more) for the straight-line lower
  /// bound of path_bounds; empty: no lower bound. Used for queries of at most 64 vertex sources,
  /// all with a position. Only correct for positions of the surface the triangulation measures
  /// (solvers::distance_options passes the input mesh's).
  Positions vertex_positions;
  /// The linear solver of the heat and Poisson steps: the direct Cholesky factors (default) or
  /// multigrid-preconditioned CG (kMultigrid) on a hierarchy of the solver's triangulation
  /// (SolverChoice::provider(), called once on it); kAuto is the direct solver here at every size
  /// (docs/decisions.md D-233). An iterative heat solve is right only to its tolerance relative
  /// to the largest heat, so with multigrid the first stage's resolved_heat and trusted_heat are
  /// raised to at least 1e3 and 1e5 × solver.multigrid.tolerance (D-231), and each later stage
  /// solves its heat directly on a band around the frontier instead of on the whole surface:
  /// the vertices within a path length of 96·√t beyond it and 8·√t behind it (t: band_span),
  /// natural conditions at the band's edge, a vertex resolved / trusted where its heat also exceeds
  /// 1e3 / 1e5 × the largest heat on the band's far edge (the band doubles while it trusts
  /// nothing); resolved_heat and trusted_heat as given apply there (docs/decisions.md D-285). The
  /// distances then differ from the direct solver's by the order of the method's own error
  /// (the continuation's), not by the solver's tolerance. The shared heat factor constructor and
  /// heat_factor() stay direct.
  SolverChoice solver;
  /// The multigrid path's bands (above) reach at least band_span·√A beyond the frontier (A the
  /// largest area of a component with a source): where 96·√t is narrower, the bands' heat uses
  /// the time step t_b = (band_span·√A / 96)² instead of t (and 96·√t_b, 8·√t_b as their
  /// widths), so that the stage count stops growing as the mesh refines (docs/decisions.md
  /// D-355). The default 0.07 leaves meshes up to ~4M faces (t = h²) at their own t, bit for
  /// bit, and gives icosphere(707) (10M faces) √t_b = 1.5·√t and 18 stages (27 at t); 0: always
  /// t (D-285's bands). Larger values mean fewer, wider stages and (on the sphere) smaller
  /// errors, but a band's factorization costs more per vertex as it widens. Dimensionless, ≥ 0;
  /// unused by the direct solver.
  double band_span = 0.07;
  /// @throws InvalidInput naming the field: time_factor not > 0 and finite, mean_edge_length
  ///         negative or not finite, thresholds not 0 < resolved_heat ≤ trusted_heat ≤ 1,
  ///         negative max_constrained_sources or correction_steps, non-finite
  ///         vertex_positions, band_span negative or not finite
  void validate() const;
};

/// The accurate mode of `ifem distance --refine`: refine to edges of about ℓ = resolution·h (h =
/// the input's robust mean side length, intrinsic::robust_side_length; area bound
/// equilateral_area(ℓ), 25°), then the heat method on the refined triangulation with t =
/// time_factor·ℓ² and correction_steps correction steps. Its accuracy against exact geodesics and
/// CGAL's heat method: BENCHMARKS.md, "Intrinsic Delaunay refinement" (the one place for those
/// figures); how the constants were chosen: docs/decisions.md, "Accurate distance mode".
struct RefinedDistanceOptions {
  double resolution = 0.4;    ///< c in ℓ = c·h, relative to the input's h (> 0)
  double time_factor = 0.25;  ///< m in t = m·ℓ², relative to the target length ℓ (> 0)
  int correction_steps = 1;   ///< HeatDistanceOptions::correction_steps (≥ 0)
  /// The target edge length ℓ (absolute) for an input of mean side length h (absolute).
  double target_length(double h) const { return resolution * h; }
  /// Heat options for the refined (already intrinsic Delaunay) triangulation; validated by the
  /// HeatDistanceSolver they are given to.
  HeatDistanceOptions heat_options(double h) const {
    HeatDistanceOptions o;
    o.intrinsic_delaunay = false;
    o.mean_edge_length = target_length(h);
    o.time_factor = time_factor;
    o.correction_steps = correction_steps;
    return o;
  }
  /// @throws InvalidInput naming the field: resolution, time_factor not finite and > 0,
  ///         correction_steps < 0
  void validate() const;
};

/// What one distance query did.
struct HeatDistanceReport {
  int stages = 1;                 ///< 1 unless the heat underflowed somewhere
  Index unresolved_vertices = 0;  ///< reachable vertices whose first-stage heat was unresolved
  Index constraints = 0;          ///< zero-distance constraints beyond one per component
};

/// Stateful heat-method solver (the one-off form is heat_distance()): the constructor builds the
/// intrinsic Delaunay triangulation, L, M and factors (M + tL) (twice on meshes with boundary:
/// Neumann and Dirichlet) and the Poisson matrix L once; each compute_distance() then costs
/// back-substitutions.
///
/// Method, per query: (M + tL) u = δ (δ = 1 at each vertex source, barycentric weights for a
/// surface point); X = −∇u/|∇u| per face; L φ = div X (cached factor, pure Neumann); φ shifted
/// so the sources are at distance 0.
///
/// Several sources: the result approximates the distance to the nearest source. Every source
/// is forced to distance exactly 0 (per component: the differences φ(s_k) − φ(s_0) are
/// constrained to zero with Lagrange multipliers through the cached factor, or, beyond
/// max_constrained_sources, with Dirichlet conditions), so no source is biased by the others.
///
/// Underflow (far from the sources on large or long meshes u underflows to 0 and −∇u/|∇u| is
/// undefined): faces whose heat is below resolved_heat get X = 0 in the first stage; since the
/// resolved region is bounded by a level set of the distance, X is then still (nearly) the
/// gradient of min(d, D), so φ is right where u ≥ trusted_heat. Later stages re-run the heat
/// from the frontier of the trusted region (cached factor) and solve the Poisson problem on the
/// newly resolved region with Dirichlet values on that frontier (a small factorization per
/// stage), until every reachable vertex is trusted.
///
/// Conventions: the result has one value per vertex (#V, vertex ids of the input); +inf on
/// vertices that no source can reach (another connected component, unreferenced vertices);
/// values are clamped to ≥ 0, vertex sources are exactly 0. Face ids of SurfacePoint sources
/// refer to triangulation(), the solver's (flipped) copy: when the input is already intrinsic
/// Delaunay, no flip happens and they equal the input's face ids.
class HeatDistanceSolver {
 public:
  /// @throws InvalidInput on bad options or a triangulation without faces
  /// @throws SolverError if a factorization fails
  explicit HeatDistanceSolver(const intrinsic::IntrinsicTriangulation& tri,
                              const HeatDistanceOptions& options = {});
  /// The solver on a heat factor made by heat_factor() and shared, not copied: for a caller
  /// that runs heat steps of its own on the same triangulation with the same t
  /// (VectorHeatSolver), so that the two hold one factor of M + tL instead of two equal ones.
  /// Results are bitwise those of the first constructor. tri must already be the solver's
  /// triangulation: no flips happen (options.intrinsic_delaunay false, or tri intrinsic
  /// Delaunay) and h lies in [0.5, 1) in tri's length unit (so length_scale() is 1); the
  /// factor must be heat_factor(tri, time_step(), options.precision). On meshes with boundary
  /// and Boundary::kAverage the zero-Dirichlet heat factor is still the solver's own.
  /// @throws InvalidInput as the first constructor; if heat is null; if a flip would happen
  ///         or length_scale() would not be 1; if heat is not a factor of M + tL on tri with
  ///         natural boundary conditions (checked by one solve: relative residual above 1e-8)
  /// @throws SolverError if a factorization fails
  HeatDistanceSolver(const intrinsic::IntrinsicTriangulation& tri,
                     const HeatDistanceOptions& options, std::shared_ptr<const PoissonSolver> heat);
  /// The heat factor the constructors build: M + tL on tri as given (no flips, no rescaling),
  /// natural (Neumann) boundary conditions, t in squared units of tri's lengths, factored with
  /// the query options of `precision` — for the constructor above and for the caller's own
  /// heat solves (PoissonSolver::solve_weak etc.; const, callable from several threads).
  /// @throws InvalidInput on a triangulation without faces or t not > 0 and finite
  /// @throws SolverError if the factorization fails
  static std::shared_ptr<const PoissonSolver> heat_factor(
      const intrinsic::IntrinsicTriangulation& tri, double t,
      HeatDistanceOptions::Precision precision = HeatDistanceOptions::Precision::kDouble);
  ~HeatDistanceSolver();
  HeatDistanceSolver(HeatDistanceSolver&&) noexcept;
  HeatDistanceSolver& operator=(HeatDistanceSolver&&) noexcept;

  /// Distance to the nearest of the given vertices, #V (absolute, in the length unit).
  /// @param sources vertex ids in [0, #V), each referenced by a face
  /// @param[out] report optional: what the query did
  /// @throws InvalidInput on an empty set, an id out of range or an unreferenced vertex
  Eigen::VectorXd compute_distance(const std::vector<Index>& sources,
                                   HeatDistanceReport* report = nullptr) const;

  /// Distances from many sources, each on its own (a distance matrix: landmarks, descriptors,
  /// embeddings), #V×k: column j is compute_distance({sources[j]}), equal to it up to rounding
  /// (the block solves add in another order: ~1e-14 relative). The heat and Poisson solves of
  /// up to 32 sources at a time (fewer above 1M vertices: each #V×block matrix stays at 256 MB)
  /// go through each factor together, so a source in a block costs a fraction of a single query
  /// (figures: BENCHMARKS.md, "heat distance, 32-source batch"; why: docs/decisions.md D-055).
  /// Without boundary or correction steps, a block of two or more stays in one row-major layout
  /// through both solves and the divergence, and where every vertex is in one component, in the
  /// solves' own row order (no copies around each solve); below 40k vertices the first such
  /// block also builds our solve kernel over CHOLMOD's factors (a copy of their values; with the
  /// buffers, a fresh solver's first block of 32 on rocketship took ~0.03 s, later ones 0.009 s).
  /// Memory: the solver keeps two or three #V×block matrices between calls (two here, one in
  /// the solve kernel off the factor-order path; four on the column path), ~0.3 GB at 500k
  /// vertices, on huge pages where the system allows, so that later calls take no page faults;
  /// the returned matrix is new memory each call (see the overload below). A source whose heat
  /// underflows somewhere in its component (a long or very large mesh; the report's
  /// unresolved_vertices) is recomputed alone by compute_distance()'s multi-stage path.
  /// @param sources vertex ids in [0, #V), each referenced by a face; repeats give equal columns
  /// @param[out] reports optional: one per source, in order
  /// @param on_progress optional: stage "heat distances", sources done over sources asked, after
  ///        each block (a per-call argument: the solver is shared between threads)
  /// @throws InvalidInput on an empty list, or naming sources[j]: out of range or unreferenced
  Eigen::MatrixXd compute_distances(const std::vector<Index>& sources,
                                    std::vector<HeatDistanceReport>* reports = nullptr,
                                    const ProgressCallback& on_progress = {}) const;
  /// compute_distances() into `out`, resized to #V×k; an `out` of that size already is written
  /// in place (no allocation): for a caller computing many batches, e.g. a distance matrix in
  /// blocks. A fresh matrix's memory is zeroed by the system on first touch: at 1M faces the
  /// 256 MB of a block of 32 cost 35–55 ms of its ~0.4 s that way (BENCHMARKS.md).
  /// @throws as compute_distances() (out is then unspecified)
  void compute_distances(const std::vector<Index>& sources, Eigen::MatrixXd& out,
                         std::vector<HeatDistanceReport>* reports = nullptr,
                         const ProgressCallback& on_progress = {}) const;

  /// Distance to the nearest of the given surface points, #V.
  /// @param sources points whose faces are faces of triangulation()
  /// @param[out] report optional: what the query did
  /// @throws InvalidInput on an empty set, a face out of range or bad barycentric coordinates
  Eigen::VectorXd compute_distance_from_points(const std::vector<SurfacePoint>& sources,
                                               HeatDistanceReport* report = nullptr) const;

  /// The triangulation the solver works on (intrinsic Delaunay unless disabled), its lengths
  /// divided by length_scale(): the solver works in units of a power of two near h, so its
  /// masses, time step and factors stay in the double range at any input scale (1e-300..1e300)
  /// and its results are the same at every scale 2^k. Connectivity and face ids are the input's.
  const intrinsic::IntrinsicTriangulation& triangulation() const;
  /// The power of two that triangulation()'s lengths are divided by (distances are multiplied
  /// back by it).
  double length_scale() const;
  /// The heat time step t = m·h² (squared length units).
  double time_step() const;

  struct Impl;

 private:
  std::unique_ptr<Impl> impl_;
};

/// One-off: heat-method distance from vertex sources (builds a HeatDistanceSolver), #V.
/// @throws as HeatDistanceSolver's constructor and compute_distance()
Eigen::VectorXd heat_distance(const intrinsic::IntrinsicTriangulation& tri,
                              const std::vector<Index>& sources,
                              const HeatDistanceOptions& options = {});

/// Mean edge length of a triangulation: intrinsic::mean_edge_length (intrinsic/core/geometry.h,
/// next to mean_side_length), kept visible here for existing callers.
using intrinsic::mean_edge_length;

}  // namespace ifem::solvers
