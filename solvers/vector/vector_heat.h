// The Vector Heat Method (Sharp, Soliman, Crane, "The Vector Heat Method", ACM TOG 2019) on an
// intrinsic triangulation: parallel transport of tangent vectors from sources, closest-point
// extension of scalar data, and the logarithmic map. Tangent vectors are complex numbers in the
// vertices' angular coordinates (fem/connection.h: angle 0 along tri.vertex_halfedge(v),
// counter-clockwise with the faces' orientation, corner angles scaled to fill 2π at interior
// vertices, true angles at boundary vertices whose angle sum is at most 2π), or, on the
// frame path (tufted covers, point clouds), in per-vertex 3D frames (fem/frame_connection.h).
// solvers/vector/tangent_basis.h turns them into 3D vectors on the input's vertices.
#pragma once

#include <Eigen/Core>
#include <complex>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "fem/connection.h"
#include "intrinsic/core/triangulation.h"
#include "intrinsic/core/types.h"
#include "intrinsic/io/mesh_io.h"
#include "solvers/vector/tangent_basis.h"

namespace ifem::solvers {

/// Options of VectorHeatSolver.
struct VectorHeatOptions {
  /// m in t = m·h²: the heat time step relative to the squared mean edge length h² (m > 0,
  /// dimensionless). The paper's (and geometry-central's) default is 1.
  double time_factor = 1.0;
  /// h, absolute (the triangulation's length unit), when > 0; 0: the mean edge length of the
  /// triangulation passed in, before the solver's Delaunay flips (HeatDistanceOptions'
  /// StepLength::kInput, the paper's h). ≥ 0.
  double mean_edge_length = 0.0;
  /// Flip a copy of the triangulation to intrinsic Delaunay first (flips keep vertex ids, but
  /// change vertex_halfedge() and so the angular coordinates: results and sources are in the
  /// coordinates of triangulation(), see frames()). On the IDT every connection-Laplacian weight
  /// is ≥ 0 (maximum principle).
  bool intrinsic_delaunay = true;
  /// The surface's boundary as a #V mask, for log_map()'s distance when the triangulation's own
  /// boundary is not the surface's (tufted cover): HeatDistanceOptions::boundary_vertices. The
  /// vector and scalar heat steps use natural (Neumann) conditions, as in the paper.
  std::vector<char> boundary_vertices;
  /// @throws InvalidInput naming the field: time_factor not > 0 and finite, mean_edge_length
  ///         negative or not finite
  void validate() const;
};

/// A transport source: a vertex and a tangent vector there, in the vertex's angular coordinate
/// of VectorHeatSolver::triangulation() (nonzero, finite).
struct VectorSource {
  Index vertex = kInvalidIndex;
  std::complex<double> vector;
};

/// An extension source: a vertex and a finite value.
struct ScalarSource {
  Index vertex = kInvalidIndex;
  double value = 0.0;
};

/// How VectorHeatSolver::log_map() finds each vertex's coordinates.
enum class LogMapMethod {
  /// The Vector Heat Method's log map: the heat-method distance and its gradient against the
  /// transported frame; builds a HeatDistanceSolver on first use.
  kVectorHeat,
  /// The affine heat method (Soliman, Sharp, "The Affine Heat Method", 2025): one scalar and
  /// one two-column vector heat solve, no distance solver; exact on a flat domain.
  kAffine,
  /// Both, per vertex: the affine value where it agrees with the vector heat value, the vector
  /// heat value where it does not, a smooth step between (the rule below). One scalar, one
  /// two-column vector heat solve and one heat distance; builds a HeatDistanceSolver on first
  /// use. Exact on a flat domain only where the vector heat value is within the rule's margin.
  kBlend,
};

/// A readable name: "vector-heat", "affine", "blend" (the CLI's `logmap --method`, Python's
/// method=).
const char* to_string(LogMapMethod method);
/// The LogMapMethod named `name` (to_string()'s names): the one parser of the CLI and Python.
/// @throws InvalidInput "'NAME': expected 'blend', 'affine' or 'vector-heat'"
LogMapMethod log_map_method_from(const std::string& name);

/// What one query did. A vertex the result does not define gets a zero vector (transport),
/// NaN + NaN·i (log_map) or NaN (extend_scalar).
struct VectorHeatReport {
  /// Vertices in a connected component without a source, and unreferenced vertices.
  Index unreached_vertices = 0;
  /// Vertices in a component with a source where the heat underflowed (|Y| below 1e-270 of the
  /// component's largest, or below 1e-290): about d > 600·√t from every source. No direction.
  Index unresolved_vertices = 0;
};

/// Stateful Vector Heat Method solver: the constructor flips a copy of the triangulation to
/// intrinsic Delaunay, builds its tangent frames, the connection Laplacian L∇ (n = 1), the cotan
/// Laplacian L and the lumped mass M, and factors M + t·L∇ (complex Hermitian, CHOLMOD) and M + t·L
/// (real) side by side; every query is back-substitutions. log_map() also needs geodesic distances:
/// the first call builds a HeatDistanceSolver on the same triangulation with the same h and t,
/// sharing the solver's M + tL factor (HeatDistanceSolver::heat_factor): one more factorization,
/// L's (two on meshes with boundary: also the zero-Dirichlet heat step); later calls reuse it.
///
/// Method (per query, all heat steps one backward Euler step with the integrated delta as the
/// right-hand side):
///  - transport: Y = (M + tL∇)⁻¹ Y₀ with Y₀ the sources' unit vectors; magnitudes by the scalar
///    heat: u = (M + tL)⁻¹ |Y₀|, φ = (M + tL)⁻¹ 1_sources; X = (u/φ)·Y/|Y|. Y₀ holds unit
///    vectors, not the sources' vectors (the paper's Y₀), so that a long vector does not pull
///    the directions of its neighbours' regions; with one source, or all of one length, u/φ is
///    that length and the scalar solves are skipped.
///  - extend_scalar: u/φ with u = (M + tL)⁻¹ Σ value_s δ_s, φ = (M + tL)⁻¹ Σ δ_s: each vertex
///    gets (a smooth blend near the bisectors of) its nearest source's value.
///  - log_map, LogMapMethod::kAffine (the affine heat method): diffuse the source as an affine
///    point in homogeneous coordinates (z ∈ ℂ, w ∈ ℝ) per vertex, with the affine transport
///    (z, w) ↦ (r z + r e w, w) along each edge (r the connection's rotation, e the edge
///    vector). One backward Euler step from (0, δ_s): w = (M + tL)⁻¹δ_s (scalar heat) and
///    z = (M + tL∇)⁻¹ b with b_i = t·Σ_j w_ij e_{i→j} w_j (w_ij the cotan weights, e_{i→j} the
///    edge vector i → j in i's coordinate: length × the halfedge's direction; on the frame path
///    the edge's length along the chord projected to i's tangent plane). z_x/w_x estimates
///    log_x(s), the source seen from x; on a flat domain with exact boundary angles it is
///    exactly s − x. The result is −(z_x/w_x)·conj(H_x)/|H_x| with H the transported frame (as
///    below). Vertices of a reached component where w or |H| underflow take the kVectorHeat
///    value (its distance has the multi-stage handling of underflow).
///  - log_map, LogMapMethod::kBlend: z_A the kAffine value, z_V the kVectorHeat value (sharing
///    the transported frame H), d = |z_V|, h the mean edge length; disagreement
///    e = max(s / (0.5·h), |z_A − z_V| / (0.05·max(d, h))) with s = max(d − |z_A|, 0) +
///    d·|arg(z_A / z_V)| (the affine radius's shortfall plus the arc between the two directions);
///    β = 1 for e ≤ 1, 0 for e ≥ 2, a smoothstep between; z = β·z_A + (1 − β)·z_V. Where one
///    of the two is undefined, the other.
///  - log_map, LogMapMethod::kVectorHeat: the radius is the heat-method distance d from the source
///    (HeatDistanceSolver: the one `ifem distance` computes, with its multi-stage handling of
///    underflow and the mean of Neumann and Dirichlet heat on boundaries); H = transport of e^{i0}
///    from the source (the parallel frame); the geodesic's direction at each vertex x is ∇d (the
///    gradients of the faces around x, each turned into x's coordinate through its corner and
///    rescaled, averaged with corner-angle weights); the angle is arg(∇d(x) / H(x)), since parallel
///    transport keeps the angle between the geodesic and the transported frame. The paper's radial
///    field (the vector heat of unit outward vectors on the source's one-ring) is not used: an
///    irregular one-ring biases every direction by an angle that does not fall under refinement,
///    where ∇d's error does (docs/decisions.md D-032).
///
/// Conventions: results have one entry per vertex of triangulation() (#V: the input's ids);
/// vectors are in the angular coordinates of frames(), which are those of triangulation() (the
/// flipped copy: when the input is already intrinsic Delaunay, e.g. a PreparedSurface, no flip
/// happens and the coordinates are the input's). Vertices no source reaches, and vertices where
/// the heat underflows, get a zero vector (transport) / NaN (extend_scalar, log_map)
/// (VectorHeatReport counts them). Where geodesics from a source meet (its cut locus: the
/// antipode on a sphere) the diffused vectors cancel and the direction there is arbitrary, as
/// in the paper. On tufted covers and point-cloud
/// triangulations the intrinsic connection is not the surface's (fem/connection.h: vertices
/// have several fans): use the frame path there.
///
/// The frame path (second constructor): the same algorithm on the same scalar operators (L, M,
/// components and the heat distance of the triangulation), with the connection Laplacian of
/// per-vertex 3D frames instead (fem::connection_laplacian_from_frames on L's pattern, frames
/// from frame_basis_3d()): vectors are x + iy for x·e1 + y·e2, and the log map's direction at a
/// vertex is the gradient of the distance by least squares over the vertex's neighbours
/// (through the triangulation's edges; its two-ring where they do not span the tangent plane),
/// projected to its tangent plane: minimize Σ_j |d_j − d_v − g·(x_j − x_v)|² / |x_j − x_v|²
/// over tangent g.
class VectorHeatSolver {
 public:
  /// @throws InvalidInput on bad options or a triangulation without faces
  /// @throws SolverError if a factorization fails
  explicit VectorHeatSolver(const intrinsic::IntrinsicTriangulation& tri,
                            const VectorHeatOptions& options = {});
  /// The frame path. Every vertex of tri must have a position and a frame (no inserted
  /// vertices): positions (#V×3, the length unit of tri's lengths) and basis (#V rows, e.g.
  /// frame_basis_3d() of the input and tri).
  /// @throws InvalidInput as the first constructor, and if positions or basis do not have
  ///         tri.n_vertices() rows
  VectorHeatSolver(const intrinsic::IntrinsicTriangulation& tri, const Positions& positions,
                   const TangentBasis3d& basis, const VectorHeatOptions& options = {});
  /// The intrinsic path, with the 3D tangent bases of its angular coordinates built once here
  /// (tangent_basis_3d(input, triangulation(), frames(), correspondence)) and kept: basis_3d().
  /// input: the surface tri was built from (its vertices are tri's first input.positions.rows());
  /// correspondence: tri's signposts or integer coordinates when tri was refined (optional; with
  /// one the bases are right at input vertices whose neighbours are all inserted vertices,
  /// tangent_basis_3d()).
  /// @throws as the first constructor, and as tangent_basis_3d()
  VectorHeatSolver(const intrinsic::IntrinsicTriangulation& tri, const io::SurfaceInput& input,
                   const VectorHeatOptions& options = {},
                   std::optional<intrinsic::CorrespondenceView> correspondence = {});
  ~VectorHeatSolver();
  VectorHeatSolver(VectorHeatSolver&&) noexcept;
  VectorHeatSolver& operator=(VectorHeatSolver&&) noexcept;

  /// Parallel transport of the sources' vectors to every vertex (vector extension: each vertex
  /// gets its nearest source's vector, transported along the shortest geodesic, with the
  /// magnitudes blended like extend_scalar()), #V complex.
  /// @param sources distinct referenced vertices, each with a finite nonzero vector
  /// @param[out] report optional
  /// @throws InvalidInput on an empty set, a vertex out of range, unreferenced or repeated, a
  ///         zero or non-finite vector (naming sources[k])
  Eigen::VectorXcd transport(const std::vector<VectorSource>& sources,
                             VectorHeatReport* report = nullptr) const;

  /// Closest-point extension of scalar data, #V (NaN where no source reaches).
  /// @throws InvalidInput as transport(), and on a non-finite value
  Eigen::VectorXd extend_scalar(const std::vector<ScalarSource>& sources,
                                VectorHeatReport* report = nullptr) const;

  /// Logarithmic map about a vertex, #V complex: |z| = geodesic distance (absolute, in the
  /// length unit of the triangulation passed in), arg z = the direction at the source in which
  /// the geodesic leaves for that vertex, counter-clockwise from the source's reference halfedge
  /// (triangulation().vertex_halfedge(source)), in the source's angular coordinate. 0 at the
  /// source. A boundary source keeps its true angles (fem/connection.h), so there the angle is
  /// in [0, Θ_v] for the vertices that geodesics inside the surface reach (Θ_v ≤ 2π). On the frame
  /// path the angle is counter-clockwise about the source's normal from its e1.
  /// Vertices in another component than the source's and unreferenced vertices
  /// (report->unreached_vertices; their geodesic distance is ∞) and vertices where neither
  /// method resolves the heat (report->unresolved_vertices) get NaN + NaN·i.
  /// @param method kBlend (the default), kVectorHeat or kAffine (exact on flat regions, far
  ///        smaller errors near the source and in angle, no distance solver; its radius falls
  ///        short far from the source on curved surfaces): docs/decisions.md D-100, D-103
  /// @throws InvalidInput if source is out of range or unreferenced
  Eigen::VectorXcd log_map(Index source, LogMapMethod method,
                           VectorHeatReport* report = nullptr) const;
  /// log_map(source, LogMapMethod::kBlend, report): the default (docs/decisions.md D-103).
  Eigen::VectorXcd log_map(Index source, VectorHeatReport* report = nullptr) const;

  /// The triangulation the solver works on (intrinsic Delaunay unless disabled), its lengths
  /// divided by length_scale() (as HeatDistanceSolver: a power of two near h keeps masses, t
  /// and the factors in range at any input scale). Connectivity, vertex and face ids are the
  /// input's; angles, and so frames(), do not depend on the scale.
  const intrinsic::IntrinsicTriangulation& triangulation() const;
  /// The power of two that triangulation()'s lengths are divided by.
  double length_scale() const;
  /// The tangent frames of triangulation(): the coordinates of sources and results (empty on
  /// the frame path).
  const fem::TangentFrames& frames() const;
  /// True on the frame path: sources and results are in frame_basis().
  bool on_frames() const;
  /// The frame path's 3D frames (empty on the intrinsic path).
  const TangentBasis3d& frame_basis() const;
  /// The 3D tangent bases that place results in space: frame_basis() on the frame path; on the
  /// intrinsic path those built by the constructor with an input, else empty (0 rows).
  const TangentBasis3d& basis_3d() const;
  /// The heat time step t = m·h² (squared length units).
  double time_step() const;

  struct Impl;

 private:
  std::unique_ptr<Impl> impl_;
};

}  // namespace ifem::solvers
