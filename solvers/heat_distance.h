// Geodesic distance by the heat method (Crane, Weischedel, Wardetzky, "Geodesics in Heat",
// ACM TOG 2013; "The Heat Method for Distance Computation", CACM 2017) on the intrinsic
// Delaunay triangulation, with a multi-stage continuation where the heat underflows.
#pragma once

#include <Eigen/Core>
#include <memory>
#include <vector>

#include "intrinsic/core/triangulation.h"

namespace ifem::solvers {

/// A point on the surface: a face of the solver's triangulation and barycentric coordinates
/// (weights of corners 0, 1, 2 of that face, i.e. of tail(3f), tail(3f+1), tail(3f+2);
/// non-negative, summing to 1).
struct SurfacePoint {
  Index face = 0;
  Eigen::Vector3d bary = Eigen::Vector3d(1.0, 0.0, 0.0);
};

/// Options of HeatDistanceSolver.
struct HeatDistanceOptions {
  /// m in t = m·h²: the heat time step relative to the squared mean edge length (m > 0).
  double time_factor = 1.0;
  /// Which mesh gives h when mean_edge_length is 0.
  ///
  /// Default: the input's mean edge length (the paper's h; Sharp, Soliman & Crane 2019 also keep
  /// the input's h on a modified triangulation). Against exact geodesics on the 13 reference
  /// meshes (tests/solvers/reference_test.cpp, 2 sources each) it is within ~4% of CGAL's heat
  /// method (which effectively uses the intrinsic Delaunay mesh's h) everywhere and far below it
  /// where the input has slivers (rocketship: 0.165 vs 0.202 mean relative error; conrod). The
  /// other rules measured — IDT mean edge, h² = 4A/(√3F) from the mean face area, median edge,
  /// max(input, IDT), √(input·IDT), 1.1·input, Galerkin instead of lumped mass in the heat step,
  /// Neumann-only boundary — each trade one mesh for another (e.g. the median edge wins on
  /// armadillo, 0.0139 vs CGAL 0.0148, and loses rocketship and terrain8k; Galerkin mass halves
  /// armadillo src0 and loses block and armadillo src8403): none is at or below CGAL on every
  /// mesh, so the default stays the input's h (issue #3 keeps the remaining gaps open).
  enum class StepLength {
    kInput,              ///< the triangulation passed in (before the solver's Delaunay flips)
    kIntrinsicDelaunay,  ///< the intrinsic Delaunay triangulation (edges are longer)
  };
  StepLength step_length = StepLength::kInput;
  /// h itself, when > 0 (e.g. the input mesh's mean edge length when the caller hands over a
  /// triangulation that is already intrinsic Delaunay).
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
  /// vertices are trusted (final) at a stage when u ≥ trusted_heat × max.
  double resolved_heat = 1e-270;
  double trusted_heat = 1e-180;
  /// Largest number of extra zero-distance constraints (several sources in one component)
  /// handled with the cached factorization (k back-substitutions); above it, vertex sources
  /// become Dirichlet conditions of a freshly factored Poisson problem.
  Index max_constrained_sources = 64;
  /// Correction steps after the heat method: φ ← the solution of L φ = div(∇φ/|∇φ|) with the
  /// same source constraints, i.e. the method's second half applied to its own result (a
  /// fixed-point iteration of the eikonal normalization; cf. Belyaev & Fayolle, "On variational
  /// and PDE-based distance function approximations", CGF 2015). Each step costs a divergence
  /// and one back-substitution with the cached factor. One step pays off with a small time
  /// step on a fine mesh: `ifem distance --refine` refines to a target edge length ℓ and uses
  /// t = ℓ²/4 with one step (tests/solvers/refine_accuracy_test.cpp has the figures); with the
  /// paper's t = h² it does not help. Default 0 (the paper's method).
  int correction_steps = 0;
  /// @throws InvalidInput on a non-positive time factor, thresholds out of (0, 1] or negative
  ///         correction steps
  void validate() const;
};

/// The accurate mode of `ifem distance --refine`: refine to edges of about ℓ = resolution·h (h =
/// the input's mean edge length; area bound equilateral_area(ℓ), 25°), then the heat method on
/// the refined triangulation with t = time_factor·ℓ² and correction_steps correction steps. At
/// most half of CGAL's heat-method error on every sliver reference mesh; the sweep it was chosen
/// from is in tests/solvers/refine_accuracy_test.cpp (IFEM_REFINE_SWEEP=1).
struct RefinedDistanceSettings {
  double resolution = 0.4;
  double time_factor = 0.25;
  int correction_steps = 1;
  /// The target edge length ℓ for an input of mean edge length h.
  double target_length(double h) const { return resolution * h; }
  /// Heat options for the refined (already intrinsic Delaunay) triangulation.
  HeatDistanceOptions heat_options(double h) const {
    HeatDistanceOptions o;
    o.intrinsic_delaunay = false;
    o.mean_edge_length = target_length(h);
    o.time_factor = time_factor;
    o.correction_steps = correction_steps;
    return o;
  }
};

/// What one distance query did.
struct HeatDistanceReport {
  int stages = 1;                 ///< 1 unless the heat underflowed somewhere
  Index unresolved_vertices = 0;  ///< reachable vertices whose first-stage heat was unresolved
  Index constraints = 0;          ///< zero-distance constraints beyond one per component
};

/// Stateful heat-method solver: the constructor builds the intrinsic Delaunay triangulation,
/// L, M and factors (M + tL) (twice on meshes with boundary: Neumann and Dirichlet) and the
/// Poisson matrix L once; each compute_distance() then costs back-substitutions.
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
  ~HeatDistanceSolver();
  HeatDistanceSolver(HeatDistanceSolver&&) noexcept;
  HeatDistanceSolver& operator=(HeatDistanceSolver&&) noexcept;

  /// Distance to the nearest of the given vertices, #V.
  /// @throws InvalidInput on an empty set, an id out of range or an unreferenced vertex
  Eigen::VectorXd compute_distance(const std::vector<Index>& sources,
                                   HeatDistanceReport* report = nullptr) const;

  /// Distance to the nearest of the given surface points, #V.
  /// @throws InvalidInput on an empty set, a face out of range or bad barycentric coordinates
  Eigen::VectorXd compute_distance_from_points(const std::vector<SurfacePoint>& sources,
                                               HeatDistanceReport* report = nullptr) const;

  /// The triangulation the solver works on (intrinsic Delaunay unless disabled).
  const intrinsic::IntrinsicTriangulation& triangulation() const;
  /// The heat time step t = m·h².
  double time_step() const;

  struct Impl;

 private:
  std::unique_ptr<Impl> impl_;
};

/// One-off: heat-method distance from vertex sources (builds a HeatDistanceSolver).
Eigen::VectorXd heat_distance(const intrinsic::IntrinsicTriangulation& tri,
                              const std::vector<Index>& sources,
                              const HeatDistanceOptions& options = {});

/// Mean edge length of a triangulation.
double mean_edge_length(const intrinsic::IntrinsicTriangulation& tri);

}  // namespace ifem::solvers
