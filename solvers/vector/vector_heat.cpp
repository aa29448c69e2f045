#include "solvers/vector/vector_heat.h"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <mutex>
#include <optional>
#include <string>
#include <utility>

#include "fem/frame_connection.h"
#include "fem/gradient.h"
#include "fem/operators.h"
#include "intrinsic/core/errors.h"
#include "intrinsic/core/geometry.h"
#include "solvers/linalg/cholesky.h"
#include "solvers/linalg/parallel.h"
#include "solvers/scalar/components.h"
#include "solvers/scalar/heat_distance.h"
#include "solvers/scalar/poisson.h"

namespace ifem::solvers {

using intrinsic::IntrinsicTriangulation;
using Complex = std::complex<double>;

namespace {

// A vertex's heat (|Y|, φ) is resolved above this fraction of its component's largest value, and
// above an absolute floor that keeps clear of subnormals (as HeatDistanceOptions::resolved_heat).
constexpr double kResolvedRelative = 1e-270;
constexpr double kAbsoluteFloor = 1e-290;
// From this many vertices a query runs its independent solves on two threads (as
// HeatDistanceSolver's two heat solves on meshes with boundary).
constexpr Index kParallelQueryVertices = 20000;
// gradient_directions() rescales a corner's angles only where |angle_scale − 1| exceeds this.
constexpr double kScaleRotation = 1e-3;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

std::string str(Index v) { return std::to_string(v); }

}  // namespace

void VectorHeatOptions::validate() const {
  if (!(time_factor > 0.0) || !std::isfinite(time_factor)) {
    throw InvalidInput("VectorHeatOptions: time_factor must be > 0 and finite, got " +
                       std::to_string(time_factor));
  }
  if (!(mean_edge_length >= 0.0) || !std::isfinite(mean_edge_length)) {
    throw InvalidInput("VectorHeatOptions: mean_edge_length must be ≥ 0 and finite");
  }
}

// The frame path's data: positions, frames and each vertex's neighbours (for the gradient).
struct FramePath {
  Positions positions;
  TangentBasis3d basis;
  std::vector<std::vector<Index>> neighbours;
};

struct VectorHeatSolver::Impl {
  VectorHeatOptions opt;
  IntrinsicTriangulation tri;  // lengths divided by scale
  fem::TangentFrames frames;   // intrinsic path
  std::optional<FramePath> frame_path;
  TangentBasis3d no_basis;         // what frame_basis() returns on the intrinsic path
  TangentBasis3d basis3d;          // intrinsic path built with an input: its 3D bases
  Eigen::VectorXcd halfedge_unit;  // e^{iθ_h}: the direction of h at its tail, #H
  Components comps;
  Eigen::VectorXd mass;
  double h_mean = 0.0;                               // mean edge length h, in units of scale
  double t = 0.0;                                    // time step, in units of scale²
  double scale = 1.0;                                // a power of two near h
  std::optional<ComplexCholeskySolver> vector_heat;  // M + tL∇
  // M + tL, Neumann: the heat distance's own factor, shared with the log map's distance solver
  std::shared_ptr<const PoissonSolver> scalar_heat;
  mutable std::mutex distance_mutex;
  mutable std::unique_ptr<HeatDistanceSolver> distance;  // built by the first vector-heat log_map()

  void factor();
  // Throws InvalidInput unless v is a referenced vertex not seen before; marks it seen and its
  // component as having a source.
  void check_source(Index v, const std::string& name, std::vector<char>& seen,
                    std::vector<char>& source_component) const;
  // Per vertex: 1 where magnitude is resolved in a component with a source; counts the others.
  std::vector<char> resolved(const Eigen::VectorXd& magnitude,
                             const std::vector<char>& source_component,
                             VectorHeatReport& report) const;
  // Per vertex, the unit direction of ∇φ in the vertex's angular coordinate (0 where it
  // vanishes or φ is not finite around it).
  Eigen::VectorXcd gradient_directions(const Eigen::VectorXd& phi) const;
  // The same on the frame path: least squares over the neighbours, in the vertex's frame.
  Eigen::VectorXcd frame_gradient_directions(const Eigen::VectorXd& phi) const;
  // The connection Laplacian (n = 1) of the path, with frames built on the intrinsic path.
  ComplexSparseMatrix connection(const fem::SparseMatrix& L);
  void construct(const IntrinsicTriangulation& tri_in, const VectorHeatOptions& options);
  const HeatDistanceSolver& distance_solver() const;
  // The affine heat method's right-hand side t·Σ_j w_ij e_{i→j} w_j (#V, in the vertices'
  // coordinates, units of scale) for the scalar heat w.
  Eigen::VectorXcd affine_rhs(const Eigen::VectorXd& w) const;
  // The log maps of the two methods (units of scale), NaN where undefined; rep counts.
  Eigen::VectorXcd affine_log_map(Index source, const std::vector<char>& source_component,
                                  VectorHeatReport& rep) const;
  Eigen::VectorXcd vector_heat_log_map(Index source, const std::vector<char>& source_component,
                                       VectorHeatReport& rep) const;
  // The vector heat log map from the transported frame H and the heat distance d.
  Eigen::VectorXcd vector_heat_log_map_from(Index source, const std::vector<char>& source_component,
                                            const Eigen::VectorXcd& horizontal,
                                            const Eigen::VectorXd& d, VectorHeatReport& rep) const;
  // The affine heat method's solves: w (#V) and zh (#V×2: z, and H the transported frame).
  void affine_solves(Index source, Eigen::VectorXd& w, Eigen::MatrixXcd& zh) const;
  // The affine values -(z/w)·conj(H)/|H|; NaN where w or H underflow or the value is not finite.
  Eigen::VectorXcd affine_values(Index source, const std::vector<char>& source_component,
                                 const Eigen::VectorXd& w, const Eigen::MatrixXcd& zh,
                                 VectorHeatReport& rep) const;
  Eigen::VectorXcd blend_log_map(Index source, const std::vector<char>& source_component,
                                 VectorHeatReport& rep) const;
};

ComplexSparseMatrix VectorHeatSolver::Impl::connection(const fem::SparseMatrix& L) {
  if (frame_path) {
    const TangentBasis3d& b = frame_path->basis;
    return fem::connection_laplacian_from_frames(L, b.normal, b.e1, b.e2, 1);
  }
  frames = fem::tangent_frames(tri);
  halfedge_unit.resize(tri.n_halfedges());
  for (Index h = 0; h < tri.n_halfedges(); ++h) {
    halfedge_unit[h] = std::polar(1.0, frames.halfedge_angle[h]);
  }
  return fem::connection_laplacian(tri, frames, 1);
}

// Two jobs side by side, each assembling its own matrix and factoring it: the complex one (the
// longer: frames, L∇, a complex factorization ≈ 1.6× a real one) and the scalar one.
void VectorHeatSolver::Impl::factor() {
  mass = fem::lumped_mass(tri);
  const fem::SparseMatrix L = fem::cotan_laplacian(tri);
  auto complex_job = [this, &L] {
    const Index nv = tri.n_vertices();
    // M + tL∇, in place on L∇'s arrays (no second matrix); an unreferenced vertex (zero row,
    // zero mass) gets 1 on the diagonal: its right-hand side is always 0, so it stays 0 and the
    // matrix stays positive definite.
    ComplexSparseMatrix A = connection(L);
    A.makeCompressed();
    std::vector<Index> no_diagonal;  // columns without a stored diagonal entry (none in practice)
    for (Index v = 0; v < nv; ++v) {
      const int* rows = A.innerIndexPtr();
      bool found = false;
      for (int k = A.outerIndexPtr()[v]; k < A.outerIndexPtr()[v + 1]; ++k) {
        A.valuePtr()[k] *= t;
        if (rows[k] != v) continue;
        A.valuePtr()[k] += mass[v] > 0.0 ? mass[v] : 1.0;
        found = true;
      }
      if (!found) no_diagonal.push_back(v);
    }
    for (const Index v : no_diagonal) A.coeffRef(v, v) = mass[v] > 0.0 ? mass[v] : 1.0;
    A.makeCompressed();
    // AMD at one BLAS thread (run_parallel's), beside the real factor: the fastest of the
    // measured choices (docs/decisions.md, "Vector heat: complex Cholesky")
    // solves by our kernel on CHOLMOD's factor in place: a transport's point source runs the
    // forward pass on its ancestors only, the backward pass on two threads (docs/decisions.md
    // D-109)
    CholeskyOptions chol;
    chol.solve_kernel = CholeskyOptions::SolveKernel::kSupernodalDouble;
    vector_heat.emplace(A, chol);
  };
  // the heat distance's factor of M + tL (its options and ordering), so that the log map's
  // HeatDistanceSolver shares it instead of factoring the same matrix again (docs/decisions.md
  // D-112)
  auto scalar_job = [this] {
    comps = connected_components(tri);
    scalar_heat = HeatDistanceSolver::heat_factor(tri, t);
  };
  run_parallel({complex_job, scalar_job});
}

void VectorHeatSolver::Impl::construct(const IntrinsicTriangulation& tri_in,
                                       const VectorHeatOptions& options) {
  options.validate();
  if (tri_in.n_faces() == 0) throw InvalidInput("VectorHeatSolver: triangulation has no faces");
  if (static_cast<Index>(options.boundary_vertices.size()) > tri_in.n_vertices()) {
    throw InvalidInput("VectorHeatOptions: boundary_vertices has " +
                       std::to_string(options.boundary_vertices.size()) + " entries for " +
                       str(tri_in.n_vertices()) + " vertices");
  }
  opt = options;
  tri = tri_in;
  if (options.intrinsic_delaunay) tri.flip_to_delaunay();
  double h = options.mean_edge_length > 0.0 ? options.mean_edge_length : mean_edge_length(tri_in);
  if (!(h > 0.0)) throw InvalidInput("VectorHeatSolver: mean edge length is 0");
  // units of a power of two near h: masses, t and the factors stay in range at any scale
  scale = intrinsic::power_of_two_scale(h);
  for (Index e = 0; e < tri.n_edges(); ++e) tri.set_length(e, tri.length(e) / scale);
  h_mean = h / scale;
  t = options.time_factor * h_mean * h_mean;
  if (frame_path) {
    frame_path->neighbours.assign(static_cast<std::size_t>(tri.n_vertices()), {});
    for (Index e = 0; e < tri.n_edges(); ++e) {
      const Index a = tri.tail(tri.edge_halfedge(e)), b = tri.head(tri.edge_halfedge(e));
      if (a == b) continue;
      frame_path->neighbours[a].push_back(b);
      frame_path->neighbours[b].push_back(a);
    }
    for (auto& list : frame_path->neighbours) {
      std::sort(list.begin(), list.end());
      list.erase(std::unique(list.begin(), list.end()), list.end());
    }
  }
  factor();
}

VectorHeatSolver::VectorHeatSolver(const IntrinsicTriangulation& tri_in,
                                   const VectorHeatOptions& options)
    : impl_(std::make_unique<Impl>()) {
  impl_->construct(tri_in, options);
}

VectorHeatSolver::VectorHeatSolver(const IntrinsicTriangulation& tri_in, const Positions& positions,
                                   const TangentBasis3d& basis, const VectorHeatOptions& options)
    : impl_(std::make_unique<Impl>()) {
  const Index nv = tri_in.n_vertices();
  if (positions.rows() != nv || basis.normal.rows() != nv || basis.e1.rows() != nv ||
      basis.e2.rows() != nv) {
    throw InvalidInput(
        "VectorHeatSolver (frame path): positions and frames need one row per "
        "vertex of the triangulation (" +
        str(nv) + "), got " + str(Index(positions.rows())) + " and " +
        str(Index(basis.normal.rows())));
  }
  impl_->frame_path = FramePath{positions, basis, {}};
  impl_->construct(tri_in, options);
}

VectorHeatSolver::VectorHeatSolver(const IntrinsicTriangulation& tri_in,
                                   const io::SurfaceInput& input, const VectorHeatOptions& options,
                                   std::optional<intrinsic::CorrespondenceView> correspondence)
    : impl_(std::make_unique<Impl>()) {
  impl_->construct(tri_in, options);
  impl_->basis3d = tangent_basis_3d(input, impl_->tri, impl_->frames, correspondence);
}

VectorHeatSolver::~VectorHeatSolver() = default;
VectorHeatSolver::VectorHeatSolver(VectorHeatSolver&&) noexcept = default;
VectorHeatSolver& VectorHeatSolver::operator=(VectorHeatSolver&&) noexcept = default;

const IntrinsicTriangulation& VectorHeatSolver::triangulation() const { return impl_->tri; }
const fem::TangentFrames& VectorHeatSolver::frames() const { return impl_->frames; }
bool VectorHeatSolver::on_frames() const { return impl_->frame_path.has_value(); }
const TangentBasis3d& VectorHeatSolver::frame_basis() const {
  return impl_->frame_path ? impl_->frame_path->basis : impl_->no_basis;
}
const TangentBasis3d& VectorHeatSolver::basis_3d() const {
  return impl_->frame_path ? impl_->frame_path->basis : impl_->basis3d;
}
double VectorHeatSolver::length_scale() const { return impl_->scale; }
double VectorHeatSolver::time_step() const { return impl_->t * impl_->scale * impl_->scale; }

void VectorHeatSolver::Impl::check_source(Index v, const std::string& name, std::vector<char>& seen,
                                          std::vector<char>& source_component) const {
  if (v < 0 || v >= tri.n_vertices()) {
    throw InvalidInput(name + " = " + str(v) + " is out of range [0, " + str(tri.n_vertices()) +
                       ")");
  }
  if (comps.label[v] == kInvalidIndex) {
    throw InvalidInput(name + " = " + str(v) + " is not referenced by any face");
  }
  if (seen[v]) throw InvalidInput(name + " = " + str(v) + " repeats an earlier source");
  seen[v] = 1;
  source_component[comps.label[v]] = 1;
}

std::vector<char> VectorHeatSolver::Impl::resolved(const Eigen::VectorXd& magnitude,
                                                   const std::vector<char>& source_component,
                                                   VectorHeatReport& report) const {
  const Index nv = tri.n_vertices();
  std::vector<double> largest(comps.count, 0.0);
  for (Index v = 0; v < nv; ++v) {
    const Index c = comps.label[v];
    if (c != kInvalidIndex && std::isfinite(magnitude[v])) {
      largest[c] = std::max(largest[c], magnitude[v]);
    }
  }
  std::vector<char> ok(nv, 0);
  for (Index v = 0; v < nv; ++v) {
    const Index c = comps.label[v];
    if (c == kInvalidIndex || !source_component[c]) {
      ++report.unreached_vertices;
      continue;
    }
    const double floor = std::max(kResolvedRelative * largest[c], kAbsoluteFloor);
    ok[v] = std::isfinite(magnitude[v]) && magnitude[v] > floor ? 1 : 0;
    if (!ok[v]) ++report.unresolved_vertices;
  }
  return ok;
}

Eigen::VectorXcd VectorHeatSolver::transport(const std::vector<VectorSource>& sources,
                                             VectorHeatReport* report) const {
  const Impl& im = *impl_;
  if (sources.empty()) throw InvalidInput("vector heat transport: the source set is empty");
  const Index nv = im.tri.n_vertices();
  std::vector<char> seen(nv, 0), source_component(im.comps.count, 0);
  Eigen::VectorXcd y0 = Eigen::VectorXcd::Zero(nv);
  bool one_length = true;
  for (const VectorSource& s : sources) {
    one_length = one_length && std::abs(s.vector) == std::abs(sources[0].vector);
  }
  // |vector| and 1 at the sources, for the magnitudes' scalar heat (none for one length)
  Eigen::MatrixXd b = Eigen::MatrixXd::Zero(one_length ? 0 : nv, 2);
  for (std::size_t k = 0; k < sources.size(); ++k) {
    const std::string name = "vector heat transport: sources[" + std::to_string(k) + "]";
    const Index v = sources[k].vertex;
    im.check_source(v, name + ".vertex", seen, source_component);
    const Complex z = sources[k].vector;
    const double len = std::abs(z);
    if (!std::isfinite(z.real()) || !std::isfinite(z.imag()) || !std::isfinite(len)) {
      throw InvalidInput(name + ".vector is not finite");
    }
    if (!(len > 0.0)) throw InvalidInput(name + ".vector is zero (a source needs a direction)");
    y0[v] = z / len;
    if (!one_length) b(v, 0) = len, b(v, 1) = 1.0;
  }
  const Eigen::VectorXcd y = im.vector_heat->solve(y0);
  VectorHeatReport rep;
  const Eigen::VectorXd magnitude = y.cwiseAbs();
  std::vector<char> ok = im.resolved(magnitude, source_component, rep);
  Eigen::VectorXd length = Eigen::VectorXd::Constant(nv, std::abs(sources[0].vector));
  if (!one_length) {
    const Eigen::MatrixXd u = im.scalar_heat->solve_weak_homogeneous(b);
    length = u.col(0).array() / u.col(1).array();
  }
  Eigen::VectorXcd out = Eigen::VectorXcd::Zero(nv);
  for (Index v = 0; v < nv; ++v) {
    if (ok[v] && !std::isfinite(length[v])) {
      ok[v] = 0;
      ++rep.unresolved_vertices;
    }
    if (ok[v]) out[v] = y[v] / magnitude[v] * length[v];
  }
  if (report) *report = rep;
  return out;
}

Eigen::VectorXd VectorHeatSolver::extend_scalar(const std::vector<ScalarSource>& sources,
                                                VectorHeatReport* report) const {
  const Impl& im = *impl_;
  if (sources.empty()) throw InvalidInput("vector heat extend_scalar: the source set is empty");
  const Index nv = im.tri.n_vertices();
  std::vector<char> seen(nv, 0), source_component(im.comps.count, 0);
  Eigen::MatrixXd b = Eigen::MatrixXd::Zero(nv, 2);  // values and 1 at the sources
  for (std::size_t k = 0; k < sources.size(); ++k) {
    const std::string name = "vector heat extend_scalar: sources[" + std::to_string(k) + "]";
    im.check_source(sources[k].vertex, name + ".vertex", seen, source_component);
    if (!std::isfinite(sources[k].value)) throw InvalidInput(name + ".value is not finite");
    b(sources[k].vertex, 0) = sources[k].value;
    b(sources[k].vertex, 1) = 1.0;
  }
  const Eigen::MatrixXd u = im.scalar_heat->solve_weak_homogeneous(b);
  VectorHeatReport rep;
  const std::vector<char> ok = im.resolved(u.col(1), source_component, rep);
  Eigen::VectorXd out = Eigen::VectorXd::Constant(nv, std::numeric_limits<double>::quiet_NaN());
  for (Index v = 0; v < nv; ++v) {
    if (ok[v]) out[v] = u(v, 0) / u(v, 1);
  }
  if (report) *report = rep;
  return out;
}

// Each face's unit gradient (in the face layout of fem::gradient) is placed at each of its
// corners by its angle to the corner's halfedge, rel: at angle θ_h + scale·rel in the vertex's
// coordinate (the angular coordinate stretches each corner uniformly), computed as the rotation
// e^{iθ_h}·e^{i·rel} where |scale − 1| ≤ kScaleRotation (interior vertices of a fine mesh, where
// the difference is below 1e-3·π: no sine or cosine per corner). The corners' unit vectors are
// averaged with their corner angles as weights (area weights were measured worse next to the
// source: 0.24 against 0.075 rad at the reference head on the 16×16 jittered grid).
Eigen::VectorXcd VectorHeatSolver::Impl::gradient_directions(const Eigen::VectorXd& phi) const {
  const Index nf = tri.n_faces();
  Eigen::VectorXd finite = phi;
  for (Index v = 0; v < tri.n_vertices(); ++v) {
    if (!std::isfinite(finite[v])) finite[v] = 0.0;
  }
  const Eigen::MatrixX2d g = fem::gradient(tri, finite);
  Eigen::VectorXcd acc = Eigen::VectorXcd::Zero(tri.n_vertices());
  for (Index f = 0; f < nf; ++f) {
    const Complex gf(g(f, 0), g(f, 1));
    const double gl = std::abs(gf);
    bool use = gl > 0.0 && std::isfinite(gl);
    for (int k = 0; k < 3; ++k) use = use && std::isfinite(phi[tri.tail(3 * f + k)]);
    if (!use) continue;
    const Eigen::Vector2d c2 = fem::face_corner2(tri, f);
    const Complex c[3] = {0.0, tri.halfedge_length(3 * f), Complex(c2.x(), c2.y())};
    for (int k = 0; k < 3; ++k) {
      const Index h = 3 * f + k, v = tri.tail(h);
      const Complex e = c[(k + 1) % 3] - c[k], back = c[(k + 2) % 3] - c[k];
      const Complex rel = gf * std::conj(e) / (gl * std::abs(e));  // e^{i·rel}
      Complex w = halfedge_unit[h] * rel;
      const double stretch = frames.angle_scale[v] - 1.0;
      if (std::abs(stretch) > kScaleRotation) w *= std::polar(1.0, stretch * std::arg(rel));
      acc[v] += std::arg(back * std::conj(e)) * w;  // weight: the corner angle
    }
  }
  for (Index v = 0; v < tri.n_vertices(); ++v) {
    const double l = std::abs(acc[v]);
    acc[v] = l > 0.0 && std::isfinite(l) ? acc[v] / l : Complex(0.0);
  }
  return acc;
}

Eigen::VectorXcd VectorHeatSolver::Impl::frame_gradient_directions(
    const Eigen::VectorXd& phi) const {
  const Index nv = tri.n_vertices();
  const Positions& p = frame_path->positions;
  const TangentBasis3d& b = frame_path->basis;
  Eigen::VectorXcd out = Eigen::VectorXcd::Zero(nv);
  // Least squares over `around`; false when its points do not span the tangent plane.
  auto fit = [&](Index v, const std::vector<Index>& around, Eigen::Vector2d& g) {
    Eigen::Matrix2d A = Eigen::Matrix2d::Zero();
    Eigen::Vector2d rhs = Eigen::Vector2d::Zero();
    for (const Index w : around) {
      if (w == v || !std::isfinite(phi[w])) continue;
      const Eigen::Vector3d d = (p.row(w) - p.row(v)).transpose();
      const Eigen::Vector2d q(d.dot(b.e1.row(v)), d.dot(b.e2.row(v)));
      const double q2 = q.squaredNorm();
      if (!(q2 > 0.0)) continue;
      A += q * q.transpose() / q2;  // weight 1/|q|²: each neighbour's slope counts alike
      rhs += (phi[w] - phi[v]) * q / q2;
    }
    if (!(A.determinant() > 1e-6 * A.trace() * A.trace())) return false;  // collinear or none
    g = A.inverse() * rhs;  // 2×2, well conditioned (checked above)
    return true;
  };
  std::vector<Index> ring2;
  for (Index v = 0; v < nv; ++v) {
    if (!std::isfinite(phi[v])) continue;
    Eigen::Vector2d g;
    bool ok = fit(v, frame_path->neighbours[v], g);
    if (!ok) {
      // A vertex of the flipped tufted cover can keep a single neighbour (the tip of a face
      // alone on the boundary): its two-ring spans the plane.
      ring2.clear();
      for (const Index w : frame_path->neighbours[v]) {
        ring2.push_back(w);
        const auto& n = frame_path->neighbours[w];
        ring2.insert(ring2.end(), n.begin(), n.end());
      }
      std::sort(ring2.begin(), ring2.end());
      ring2.erase(std::unique(ring2.begin(), ring2.end()), ring2.end());
      ok = fit(v, ring2, g);
    }
    const double len = g.norm();
    if (ok && len > 0.0 && std::isfinite(len)) out[v] = Complex(g.x(), g.y()) / len;
  }
  return out;
}

const HeatDistanceSolver& VectorHeatSolver::Impl::distance_solver() const {
  std::lock_guard<std::mutex> lock(distance_mutex);
  if (!distance) {
    HeatDistanceOptions o;
    o.time_factor = opt.time_factor;
    o.mean_edge_length = h_mean;  // the same h and t as the vector heat step
    o.intrinsic_delaunay = false;
    o.boundary_vertices = opt.boundary_vertices;
    distance = std::make_unique<HeatDistanceSolver>(tri, o, scalar_heat);
  }
  return *distance;
}

Eigen::VectorXcd VectorHeatSolver::Impl::vector_heat_log_map(
    Index source, const std::vector<char>& source_component, VectorHeatReport& rep) const {
  const Index nv = tri.n_vertices();
  Eigen::VectorXcd e0 = Eigen::VectorXcd::Zero(nv);
  e0[source] = 1.0;
  Eigen::VectorXcd horizontal;  // e^{i0} transported
  Eigen::VectorXd d;
  const std::vector<std::function<void()>> jobs = {
      [&] { horizontal = vector_heat->solve(e0); },
      [&] { d = distance_solver().compute_distance({source}); }};
  if (nv >= kParallelQueryVertices) {
    run_parallel(jobs);  // independent solves, memory bound: side by side on large meshes
  } else {
    for (const auto& j : jobs) j();
  }
  return vector_heat_log_map_from(source, source_component, horizontal, d, rep);
}

Eigen::VectorXcd VectorHeatSolver::Impl::vector_heat_log_map_from(
    Index source, const std::vector<char>& source_component, const Eigen::VectorXcd& horizontal,
    const Eigen::VectorXd& d, VectorHeatReport& rep) const {
  const Index nv = tri.n_vertices();
  const Eigen::VectorXcd radial =
      frame_path ? frame_gradient_directions(d) : gradient_directions(d);
  std::vector<char> ok = resolved(horizontal.cwiseAbs(), source_component, rep);
  Eigen::VectorXcd out = Eigen::VectorXcd::Constant(nv, Complex(kNaN, kNaN));
  out[source] = 0.0;
  for (Index v = 0; v < nv; ++v) {
    if (v == source || !ok[v]) continue;
    if (!std::isfinite(d[v]) || radial[v] == Complex(0.0)) {
      ++rep.unresolved_vertices;
      continue;
    }
    // the angle between the geodesic and the transported frame is the angle at the source
    const Complex direction = radial[v] / horizontal[v];
    out[v] = d[v] * direction / std::abs(direction);
  }
  return out;
}

// Per halfedge h (i → j) of face f, the weight c = cot(angle opposite h)/2 (divided by the
// multiplicity, as cotan_laplacian()) adds t·c·e_{i→j}·w_j at i and t·c·e_{j→i}·w_i at j, e the
// edge vector in the end's coordinate: ℓ·e^{iθ_h} at i and −r_h·ℓ·e^{iθ_h} at j (the transport
// keeps the edge's direction), or on the frame path ℓ times the unit projection of the chord to
// the end's tangent plane.
Eigen::VectorXcd VectorHeatSolver::Impl::affine_rhs(const Eigen::VectorXd& w) const {
  const Index nv = tri.n_vertices();
  Eigen::VectorXcd b = Eigen::VectorXcd::Zero(nv);
  const double k = t / (2.0 * tri.multiplicity());
  // the chord i → j in i's frame, unit (0 when it is normal to the tangent plane)
  auto chord = [this](Index i, Index j) {
    const Positions& p = frame_path->positions;
    const TangentBasis3d& fb = frame_path->basis;
    const Eigen::Vector3d d = (p.row(j) - p.row(i)).transpose();
    const Complex q(d.dot(fb.e1.row(i)), d.dot(fb.e2.row(i)));
    const double l = std::abs(q);
    return l > 0.0 && std::isfinite(l) ? q / l : Complex(0.0);
  };
  for (Index h = 0; h < tri.n_halfedges(); ++h) {
    const Index i = tri.tail(h), j = tri.head(h);
    if (i == j) continue;  // a self-edge carries no displacement between two vertices
    const double c = k * intrinsic::halfedge_cotan(tri, h) * tri.halfedge_length(h);
    if (!std::isfinite(c) || c == 0.0) continue;
    if (frame_path) {
      b[i] += c * w[j] * chord(i, j);
      b[j] += c * w[i] * chord(j, i);
    } else {
      b[i] += c * w[j] * halfedge_unit[h];
      b[j] -= c * w[i] * frames.transport[h] * halfedge_unit[h];
    }
  }
  return b;
}

// The affine heat method: w = (M + tL)⁻¹δ_s, z = (M + tL∇)⁻¹ affine_rhs(w), H = (M + tL∇)⁻¹
// e^{i0}δ_s (one two-column solve with z).
void VectorHeatSolver::Impl::affine_solves(Index source, Eigen::VectorXd& w,
                                           Eigen::MatrixXcd& zh) const {
  const Index nv = tri.n_vertices();
  Eigen::MatrixXd delta = Eigen::MatrixXd::Zero(nv, 1);
  delta(source, 0) = 1.0;
  w = scalar_heat->solve_weak_homogeneous(delta).col(0);
  Eigen::MatrixXcd rhs(nv, 2);
  rhs.col(0) = affine_rhs(w);
  rhs.col(1).setZero();
  rhs(source, 1) = 1.0;
  zh = vector_heat->solve(rhs);
}

// z/w is the source's position in x's tangent plane (log_x(s)), read at the source through the
// transported frame H.
Eigen::VectorXcd VectorHeatSolver::Impl::affine_values(Index source,
                                                       const std::vector<char>& source_component,
                                                       const Eigen::VectorXd& w,
                                                       const Eigen::MatrixXcd& zh,
                                                       VectorHeatReport& rep) const {
  const Index nv = tri.n_vertices();
  VectorHeatReport wrep, hrep;
  const std::vector<char> ok_w = resolved(w, source_component, wrep);
  const std::vector<char> ok_h = resolved(zh.col(1).cwiseAbs(), source_component, hrep);
  rep.unreached_vertices = wrep.unreached_vertices;
  Eigen::VectorXcd out = Eigen::VectorXcd::Constant(nv, Complex(kNaN, kNaN));
  out[source] = 0.0;
  for (Index v = 0; v < nv; ++v) {
    if (v == source || !ok_w[v] || !ok_h[v]) continue;
    const Complex z = zh(v, 0), h = zh(v, 1);
    const Complex value = -(z / w[v]) * std::conj(h) / std::abs(h);
    if (std::isfinite(value.real()) && std::isfinite(value.imag())) out[v] = value;
  }
  return out;
}

// Vertices of a reached component where w or H underflow get the vector heat method's value
// (its heat distance has the multi-stage handling).
Eigen::VectorXcd VectorHeatSolver::Impl::affine_log_map(Index source,
                                                        const std::vector<char>& source_component,
                                                        VectorHeatReport& rep) const {
  const Index nv = tri.n_vertices();
  Eigen::VectorXd w;
  Eigen::MatrixXcd zh;
  affine_solves(source, w, zh);
  Eigen::VectorXcd out = affine_values(source, source_component, w, zh, rep);
  std::vector<Index> fallback;
  for (Index v = 0; v < nv; ++v) {
    const Index c = comps.label[v];
    if (v == source || c == kInvalidIndex || !source_component[c]) continue;
    if (!std::isfinite(out[v].real())) fallback.push_back(v);
  }
  if (!fallback.empty()) {
    VectorHeatReport frep;
    const Eigen::VectorXcd vh = vector_heat_log_map_from(
        source, source_component, zh.col(1), distance_solver().compute_distance({source}), frep);
    for (const Index v : fallback) {
      out[v] = vh[v];
      if (!std::isfinite(vh[v].real())) ++rep.unresolved_vertices;
    }
  }
  return out;
}

// Both methods from one transported frame H (the affine solve's second column) and one heat
// distance d; per vertex the affine value z_A where it agrees with the vector heat value z_V,
// z_V where it does not, a smooth step between. Disagreement, in units of the blend's scales:
// e = max(s / (kBlendEdges·h), |z_A − z_V| / (kBlendRelative·max(d, h))), with s the affine
// map's radial shortfall max(d − |z_A|, 0) plus the arc d·|arg(z_A/z_V)| between the two
// directions (the affine map's failure mode far from the source on curved surfaces: its radius
// falls short). β = 1 for e ≤ 1, 0 for e ≥ 2, smoothstep between; z = β z_A + (1 − β) z_V.
Eigen::VectorXcd VectorHeatSolver::Impl::blend_log_map(Index source,
                                                       const std::vector<char>& source_component,
                                                       VectorHeatReport& rep) const {
  constexpr double kBlendEdges = 0.5;      // the shortfall allowed, in mean edge lengths
  constexpr double kBlendRelative = 0.05;  // the disagreement allowed, relative to d
  const Index nv = tri.n_vertices();
  Eigen::VectorXd w, d;
  Eigen::MatrixXcd zh;
  const std::vector<std::function<void()>> jobs = {
      [&] { affine_solves(source, w, zh); },
      [&] { d = distance_solver().compute_distance({source}); }};
  if (nv >= kParallelQueryVertices) {
    run_parallel(jobs);
  } else {
    for (const auto& j : jobs) j();
  }
  VectorHeatReport arep;
  const Eigen::VectorXcd za = affine_values(source, source_component, w, zh, arep);
  Eigen::VectorXcd out = vector_heat_log_map_from(source, source_component, zh.col(1), d, rep);
  for (Index v = 0; v < nv; ++v) {
    const Complex a = za[v], b = out[v];
    if (v == source || !std::isfinite(a.real())) continue;
    if (!std::isfinite(b.real())) {  // the vector heat value unresolved (counted): the affine one
      out[v] = a;
      --rep.unresolved_vertices;
      continue;
    }
    const double dv = std::abs(b);
    const double arc = dv * std::abs(std::arg(a / b));
    const double shortfall = std::max(dv - std::abs(a), 0.0) + arc;
    const double e = std::max(shortfall / (kBlendEdges * h_mean),
                              std::abs(a - b) / (kBlendRelative * std::max(dv, h_mean)));
    const double x = std::clamp(2.0 - e, 0.0, 1.0);
    const double beta = x * x * (3.0 - 2.0 * x);
    out[v] = beta * a + (1.0 - beta) * b;
  }
  return out;
}

Eigen::VectorXcd VectorHeatSolver::log_map(Index source, VectorHeatReport* report) const {
  return log_map(source, LogMapMethod::kBlend, report);
}

Eigen::VectorXcd VectorHeatSolver::log_map(Index source, LogMapMethod method,
                                           VectorHeatReport* report) const {
  const Impl& im = *impl_;
  std::vector<char> seen(im.tri.n_vertices(), 0), source_component(im.comps.count, 0);
  im.check_source(source, "vector heat log_map: source", seen, source_component);
  VectorHeatReport rep;
  Eigen::VectorXcd out;
  switch (method) {
    case LogMapMethod::kAffine:
      out = im.affine_log_map(source, source_component, rep);
      break;
    case LogMapMethod::kBlend:
      out = im.blend_log_map(source, source_component, rep);
      break;
    default:
      out = im.vector_heat_log_map(source, source_component, rep);
      break;
  }
  out *= im.scale;
  if (report) *report = rep;
  return out;
}

const char* to_string(LogMapMethod method) {
  switch (method) {
    case LogMapMethod::kVectorHeat:
      return "vector-heat";
    case LogMapMethod::kAffine:
      return "affine";
    case LogMapMethod::kBlend:
      return "blend";
  }
  return "?";
}

LogMapMethod log_map_method_from(const std::string& name) {
  for (const LogMapMethod m :
       {LogMapMethod::kBlend, LogMapMethod::kAffine, LogMapMethod::kVectorHeat}) {
    if (name == to_string(m)) return m;
  }
  throw InvalidInput("'" + name + "': expected 'blend', 'affine' or 'vector-heat'");
}

}  // namespace ifem::solvers
