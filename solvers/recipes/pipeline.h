// The pipeline from an input to results on its own vertices, the one way the CLI, the tests, the
// benchmark and library users go:
//
//   file / arrays ──► prepare_surface(): path (manifold | tufted | point cloud), mollify,
//                     intrinsic Delaunay flips, optional refinement (integer coordinates or
//                     signposts; the tufted cover)
//                 ──► recipes: geodesic_distance(), eigenmodes(), poisson()
//                 ──► results on the input's vertices, in the input's order (on_input_vertices)
//
// Input vertices keep their ids 0..#V_in−1 on every path; vertices inserted by refinement come
// after them, so restricting a result to the input is taking its first #V_in entries.
#pragma once

#include <Eigen/Core>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "intrinsic/core/triangulation.h"
#include "intrinsic/integer/correspondence.h"
#include "intrinsic/integer/normal_coordinates.h"
#include "intrinsic/io/mesh_io.h"
#include "intrinsic/refine/delaunay_refine.h"
#include "intrinsic/refine/signpost.h"
#include "intrinsic/surface/build_surface.h"
#include "pointcloud/pointcloud_laplacian.h"
#include "solvers/scalar/eigen.h"
#include "solvers/scalar/heat_distance.h"
#include "solvers/scalar/poisson.h"

namespace ifem::solvers {

/// Intrinsic Delaunay refinement as part of preparing a surface.
struct SurfaceRefineOptions {
  double min_angle_degrees = 25.0;  ///< smallest corner angle wanted, degrees, in (0, 30]
  /// Target edge length as a multiple of h, the input's mean side length: triangles larger than
  /// the equilateral one of side resolution·h are split. 0 = no size bound.
  double resolution = 0.0;
  double max_area = 0.0;        ///< also split triangles above this area (absolute); 0 = none
  Index max_insertions = -1;    ///< cap on inserted vertices; −1 = RefineOptions' default
  int relax_iterations = 0;     ///< ODT relaxation passes of the inserted vertices
  double relax_max_edge = 0.0;  ///< with relaxation: split edges longer than this (absolute)
  /// Require a correspondence with the input (integer coordinates or signposts, `correspondence`:
  /// inserted vertices' places on the input, needed to carry input data onto inserted vertices
  /// and for the common subdivision): refuse the tufted path instead of refining the cover
  /// without one. (The name predates integer coordinates.)
  bool need_signposts = false;
  /// Memory budget, bytes (RefineOptions::max_memory_bytes): a request whose estimate
  /// (intrinsic::estimate_refinement()) exceeds it is refused up front. 0: half the physical
  /// memory (or 80% of ulimit -v); +∞: none.
  double max_memory_bytes = 0.0;
  /// With constraints (curves): split curve and boundary edges whose cotan weight is negative
  /// after refinement (RefineOptions::conform), so the maximum principle holds.
  bool conform = true;
  /// How inserted vertices keep their places on the input (edge-manifold, orientable meshes;
  /// the tufted cover has neither): integer coordinates (normal coordinates: the overlay's
  /// combinatorics are exact integers, so the common subdivision partitions the input faces on
  /// every input tried; the default, docs/decisions.md D-330) or signposts (real directions,
  /// traced in floating point). Both give the same intrinsic triangulation (same insertions,
  /// same lengths; after relaxation, the same moves and lengths to rounding). Integer
  /// refinement fills PreparedSurface::integer, signposts PreparedSurface::signposts.
  intrinsic::Correspondence correspondence = intrinsic::Correspondence::kInteger;
  /// @throws InvalidInput naming the field and its allowed range
  void validate() const;
};

/// The refinement options for settings r with target edge length ℓ (absolute; 0: none): the
/// area bound is the smaller of r.max_area and equilateral_area(ℓ).
intrinsic::RefineOptions refine_options(const SurfaceRefineOptions& r, double target_length);

/// One line for people: what a refinement did (vertices, insertions, flips, angles, caps).
std::string describe(const intrinsic::RefineReport& r);

/// The accurate distance mode's refinement (RefinedDistanceOptions: edges of about 0.4·h).
SurfaceRefineOptions accurate_distance_refinement();

/// Options of prepare_surface().
struct PrepareOptions {
  /// Relative mollification margin (IntrinsicTriangulation::mollify), ≥ 0.
  double mollify_relative_epsilon = intrinsic::kDefaultMollifyEpsilon;
  bool intrinsic_delaunay = true;  ///< flip to intrinsic Delaunay (refinement always does)
  bool force_tufted = false;       ///< tufted cover even for an edge-manifold mesh
  bool force_pointcloud = false;   ///< treat a mesh's vertices as a point cloud
  int knn = 30;                    ///< neighbours per point on the point-cloud path, ≥ 2
  /// Point-cloud path: false keeps the cover free of self-edges (its Delaunay flips skip those
  /// that would join a point to itself: pointcloud::PointCloudOptions::self_edges), as
  /// simplification wants (`ifem simplify`, docs/decisions.md D-345).
  bool self_edges = true;
  std::optional<SurfaceRefineOptions> refine;  ///< refine after the flips when set
  /// Receives one progress line per stage ("read ...", "path: ...", "refined: ..."); none when
  /// empty.
  std::function<void(const std::string&)> progress;
  /// Progress of the long stages, as fractions (ProgressCallback): "read" (load_surface()) and
  /// "refine" (RefineOptions::on_progress). Empty: none.
  ProgressCallback on_progress;
  /// @throws InvalidInput naming the field and its allowed range
  void validate() const;
};

/// An input turned into an intrinsic triangulation, with everything chosen, repaired and
/// counted on the way.
struct PreparedSurface {
  io::SurfaceInput input;  ///< as read: positions (#V_in×3) and triangles, in file order
  intrinsic::IntrinsicTriangulation tri;  ///< #V ≥ #V_in vertices: the input's, then inserted
  intrinsic::SurfacePath path = intrinsic::SurfacePath::kManifold;
  intrinsic::PathReason reason = intrinsic::PathReason::kEdgeManifoldOrientable;
  std::string reason_detail;            ///< the reason in words, for people (decide on `reason`)
  intrinsic::FaceListStats stats;       ///< the input face list (empty for point clouds)
  intrinsic::BuildReport build;         ///< dropped / reoriented faces, unreferenced vertices
  intrinsic::TuftedCoverReport tufted;  ///< tufted path
  pointcloud::Report cloud;             ///< point-cloud path
  intrinsic::MollifyReport mollify;
  /// The relative margin it was mollified with (PrepareOptions::mollify_relative_epsilon): a
  /// SignpostTriangulation of the input with it has the same lengths as tri before the flips.
  double mollify_relative_epsilon = 0.0;
  intrinsic::FlipReport flips;
  /// #V mask of the input's boundary vertices when the triangulation's own boundary is not the
  /// surface's (the tufted cover has none); empty when the triangulation's boundary is right.
  std::vector<char> boundary_vertex;
  /// h: mean side length of the input's faces (heat step, refinement resolution); 0 without
  /// faces.
  double input_mean_edge_length = 0.0;
  bool refined = false;
  intrinsic::RefineReport refine_report;
  intrinsic::RelaxReport relax_report;
  /// ℓ = resolution·h when refinement had a size bound, else 0.
  double target_edge_length = 0.0;
  /// Refined with signposts: inserted vertices' places on the input (SignpostTriangulation).
  std::optional<intrinsic::SignpostTriangulation> signposts;
  /// Refined with integer coordinates (SurfaceRefineOptions::correspondence): the same, kept
  /// as normal coordinates. At most one of `signposts` and `integer` is set.
  std::optional<intrinsic::NormalCoordinateTriangulation> integer;
  double seconds_build = 0, seconds_flip = 0, seconds_refine = 0;

  /// #V_in: the input's vertex count (ids 0..#V_in−1 of tri are the input's vertices).
  Index n_input_vertices() const { return static_cast<Index>(input.positions.rows()); }
  /// True when signposts can be built (edge-manifold, orientable mesh; a mesh that took the
  /// tufted path only for negative boundary weights counts: refinement splits those edges).
  bool supports_signposts() const;
  /// The correspondence of a refined manifold surface (signposts or integer), or nullopt when
  /// it has none (not refined, or refined on the tufted cover).
  std::optional<intrinsic::CorrespondenceView> correspondence() const;
};

/// Builds the intrinsic triangulation of an input on the right path, then refines it if asked:
///  - point cloud when the input has no faces or force_pointcloud (kNN local triangulations
///    glued into a tufted cover, knn neighbours);
///  - otherwise intrinsic::build_surface(): manifold, or the tufted cover for nonmanifold /
///    non-orientable meshes and for boundary edges that would keep negative weights;
///  - refinement (options.refine): with signposts or integer coordinates
///    (SurfaceRefineOptions::correspondence) when supports_signposts(), else on the tufted
///    cover itself (neither; refused when need_signposts or relaxation asks for them).
/// @throws InvalidInput on bad options, on an input the path cannot use, on refinement of a
///         point cloud / of the tufted cover with need_signposts or relaxation
PreparedSurface prepare_surface(io::SurfaceInput input, const PrepareOptions& options = {});

/// Reads a file (io::read_surface) and prepares it.
/// @throws IoError on an unreadable or malformed file, and as prepare_surface()
PreparedSurface load_surface(const std::string& path, const PrepareOptions& options = {});

/// The first #V_in entries (rows) of a per-vertex result on s.tri: its values on the input's
/// vertices, in the input's order.
/// @throws InvalidInput if values has fewer than #V_in entries
Eigen::VectorXd on_input_vertices(const PreparedSurface& s, const Eigen::VectorXd& values);
Eigen::MatrixXd on_input_vertices(const PreparedSurface& s, const Eigen::MatrixXd& values);

/// Per-vertex data given on the input's vertices (#V_in) carried onto every vertex of s.tri:
/// copied on input vertices, interpolated linearly at inserted vertices (s.correspondence()).
/// @throws InvalidInput on a size mismatch, or if s has inserted vertices without a
///         correspondence (refined on the tufted cover)
Eigen::VectorXd from_input_vertices(const PreparedSurface& s, const Eigen::VectorXd& values);

/// Heat-method settings of geodesic_distance(); unset fields take the defaults of the surface:
/// the accurate mode's (RefinedDistanceOptions) when it was refined with a size bound, the
/// paper's (t = h², no correction step) otherwise.
struct DistanceOptions {
  std::optional<double> time_factor;    ///< m in t = m·h², > 0
  std::optional<int> correction_steps;  ///< ≥ 0
  /// Precision of the factors the queries read (HeatDistanceOptions::precision; default kDouble)
  std::optional<HeatDistanceOptions::Precision> precision;
  /// Clamp into the bounds every exact distance satisfies (HeatDistanceOptions::path_bounds);
  /// false: the heat method's values as solved
  bool path_bounds = true;
  /// The linear solver (HeatDistanceOptions::solver; default direct)
  SolverChoice solver;
  /// Progress of geodesic_distances() (HeatDistanceSolver::compute_distances()); empty: none
  ProgressCallback on_progress;
  /// @throws InvalidInput naming the field and its allowed range
  void validate() const;
};

/// The heat-method options geodesic_distance() uses on s: h from the input's faces (or ℓ when
/// refined with a size bound), the input's boundary and vertex positions (path bounds' straight-
/// line lower bound, HeatDistanceOptions::path_bounds), no further flips (s is already intrinsic
/// Delaunay). For many queries: GeodesicDistanceSolver(s) (geodesic_distance()'s stray-hub cut
/// too; HeatDistanceSolver(s.tri, distance_options(s)) has the same values where nothing is cut).
HeatDistanceOptions distance_options(const PreparedSurface& s,
                                     const DistanceOptions& settings = {});

/// Geodesic distance from input vertices (ids < #V_in) to every input vertex, #V_in; +inf where
/// no source reaches, 0 at every source.
///
/// Stray hubs (docs/decisions.md D-360): an input vertex all of whose sides (in the input's
/// faces) are longer than intrinsic::kOutlierClip × the 99th percentile of the input's side
/// lengths — the outliers robust_mean_length() leaves out — and than the bounding-box diagonal
/// of the vertices with a shorter side (a spike beyond the whole model, e.g. a vertex pulled far
/// off the surface; a cylinder's cap fan is not one) is cut loose when s is neither refined nor
/// a point cloud: the input's faces at it are
/// left out, the rest is prepared again as s was (same mollification margin, intrinsic Delaunay,
/// tufted if s is), and the heat method runs there with s's h and s's boundary (the hole's rim
/// gets natural conditions). Without this, its needle faces put a needle's area of mass on each
/// vertex of their short side (a heat sink) and the other vertices' distances moved by ~2 %.
/// A cut-loose vertex (and any vertex left without faces) gets the shortest way to it along
/// s.tri's edges from the others. Nothing is cut (s.tri as it is, bit for bit) when no vertex
/// qualifies — every reference mesh — or when a source would lose its faces. Cost where nothing
/// is cut: one pass over the input's sides (a copy and a partial sort). For many queries:
/// GeodesicDistanceSolver (the same cut); solvers built directly with
/// HeatDistanceSolver(s.tri, distance_options(s)) do not cut.
/// @throws InvalidInput on an empty source list or an id out of [0, #V_in)
/// @throws SolverError if a factorization fails
Eigen::VectorXd geodesic_distance(const PreparedSurface& s, const std::vector<Index>& sources,
                                  const DistanceOptions& settings = {},
                                  HeatDistanceReport* report = nullptr);

/// Geodesic distances from each of the given input vertices on its own (a distance matrix),
/// #V_in×k: column j is geodesic_distance(s, {sources[j]}) up to rounding, computed in blocks
/// of sources (HeatDistanceSolver::compute_distances); stray hubs cut loose as there (a column
/// whose source lost its faces is computed on s.tri uncut, the others on the cut surface).
/// @param[out] reports optional: one per source
/// @throws InvalidInput on an empty list or an id out of [0, #V_in) (naming its position)
/// @throws SolverError if a factorization fails
Eigen::MatrixXd geodesic_distances(const PreparedSurface& s, const std::vector<Index>& sources,
                                   const DistanceOptions& settings = {},
                                   std::vector<HeatDistanceReport>* reports = nullptr);

/// The stateful form of geodesic_distance(): the default heat distance on a prepared surface,
/// factored once, queried many times (Python's HeatDistanceSolver). Stray hubs are cut loose
/// as geodesic_distance() does (docs/decisions.md D-360, D-380): when s has one, the solver
/// runs on surface() — s prepared again without the hubs' input faces, the hole's rim with
/// natural conditions — and a query whose source lies on a cut star (a vertex or a point that
/// lost its faces) goes to a second solver on s.tri, built on the first such query. Without
/// stray hubs (every reference mesh), refined surfaces and point clouds, surface() is s and the
/// results are HeatDistanceSolver(s.tri, distance_options(s, settings))'s, bit for bit.
/// Results are on s.tri's vertices (#V; the input's are the first #V_in: on_input_vertices());
/// a cut-loose vertex gets the shortest way to it along s.tri's edges. The queries are const
/// and may run from several threads. s must outlive the solver.
class GeodesicDistanceSolver {
 public:
  /// @throws InvalidInput on bad settings or a surface without faces
  /// @throws SolverError if a factorization fails
  explicit GeodesicDistanceSolver(const PreparedSurface& s, const DistanceOptions& settings = {});
  ~GeodesicDistanceSolver();
  GeodesicDistanceSolver(GeodesicDistanceSolver&&) noexcept;
  GeodesicDistanceSolver& operator=(GeodesicDistanceSolver&&) noexcept;

  /// Distance to the nearest of the given vertices (ids of s.tri), #V.
  /// @throws InvalidInput as HeatDistanceSolver::compute_distance()
  Eigen::VectorXd compute_distance(const std::vector<Index>& sources,
                                   HeatDistanceReport* report = nullptr) const;
  /// One column per source, each on its own, #V×k (HeatDistanceSolver::compute_distances());
  /// column j equals compute_distance({sources[j]}) up to rounding.
  /// @throws InvalidInput as HeatDistanceSolver::compute_distances()
  Eigen::MatrixXd compute_distances(const std::vector<Index>& sources,
                                    std::vector<HeatDistanceReport>* reports = nullptr,
                                    const ProgressCallback& on_progress = {}) const;
  /// Distance to the nearest of the given points on surface().tri (faces of surface().tri), #V.
  /// Points on a cut star have no face there: compute_distance_from_points_uncut() takes them.
  /// @throws InvalidInput as HeatDistanceSolver::compute_distance_from_points()
  Eigen::VectorXd compute_distance_from_points(const std::vector<SurfacePoint>& points,
                                               HeatDistanceReport* report = nullptr) const;
  /// The same from points on s.tri (faces of s.tri), on s.tri itself without any cut: for a
  /// query with a point on a cut star (surface_face()). Equal to the above when nothing is cut.
  /// @throws InvalidInput as HeatDistanceSolver::compute_distance_from_points()
  Eigen::VectorXd compute_distance_from_points_uncut(const std::vector<SurfacePoint>& points,
                                                     HeatDistanceReport* report = nullptr) const;

  /// The surface the solver runs on: s, or s prepared again without the stray hubs' faces.
  const PreparedSurface& surface() const;
  /// True when stray hubs were cut loose (surface() is not s).
  bool cut() const;
  /// For each face of s.input.triangles, its index in surface().input.triangles, or
  /// kInvalidIndex where it was cut (a face at a cut-loose vertex); empty when nothing is cut.
  const std::vector<Index>& surface_face() const;
  /// The heat-method options on s (distance_options(s, settings)).
  const HeatDistanceOptions& options() const;
  /// The heat time step t (squared length units).
  double time_step() const;

  struct Impl;

 private:
  std::unique_ptr<Impl> impl_;
};

/// The k smallest eigenpairs of L φ = λ M φ on s.tri, eigenvectors restricted to the input's
/// vertices (#V_in×k; M-orthonormal on s.tri, the input's rows of them).
/// @throws InvalidInput if k < 1 or k ≥ #V; SolverError as eigenpairs()
EigenPairs eigenmodes(const PreparedSurface& s, Index k, const EigenOptions& options = {});

/// Solves (L + c·M) u = M f on s.tri with u fixed on Dirichlet input vertices; f is given on the
/// input's vertices (#V_in) and carried onto inserted vertices (from_input_vertices). Returns u
/// on the input's vertices, #V_in. Conventions as solve_poisson().
/// @throws InvalidInput on sizes, ids out of [0, #V_in) or inserted vertices without a
///         correspondence (refined on the tufted cover)
Eigen::VectorXd poisson(const PreparedSurface& s, const Eigen::VectorXd& f,
                        const std::vector<Index>& dirichlet_vertices,
                        const Eigen::VectorXd& dirichlet_values,
                        const PoissonOptions& options = {});

}  // namespace ifem::solvers
