#include "solvers/vector_heat.h"

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <mutex>
#include <optional>
#include <string>
#include <utility>

#include "fem/gradient.h"
#include "fem/operators.h"
#include "intrinsic/core/errors.h"
#include "intrinsic/core/geometry.h"
#include "solvers/cholesky.h"
#include "solvers/components.h"
#include "solvers/heat_distance.h"
#include "solvers/parallel.h"
#include "solvers/poisson.h"

namespace ifem::solvers {

using intrinsic::IntrinsicTriangulation;
using Complex = std::complex<double>;

namespace {

constexpr double kPi = 3.14159265358979323846;
// A vertex's heat (|Y|, φ) is resolved above this fraction of its component's largest value, and
// above an absolute floor that keeps clear of subnormals (as HeatDistanceOptions::resolved_heat).
constexpr double kResolvedRelative = 1e-270;
constexpr double kAbsoluteFloor = 1e-290;
// From this many vertices a query runs its independent solves on two threads (as
// HeatDistanceSolver's two heat solves on meshes with boundary).
constexpr Index kParallelQueryVertices = 20000;
// gradient_directions() rescales a corner's angles only where |angle_scale − 1| exceeds this.
constexpr double kScaleRotation = 1e-3;

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

struct VectorHeatSolver::Impl {
  VectorHeatOptions opt;
  IntrinsicTriangulation tri;  // lengths divided by scale
  fem::TangentFrames frames;
  Eigen::VectorXcd halfedge_unit;  // e^{iθ_h}: the direction of h at its tail, #H
  Components comps;
  Eigen::VectorXd mass;
  double h_mean = 0.0;                               // mean edge length h, in units of scale
  double t = 0.0;                                    // time step, in units of scale²
  double scale = 1.0;                                // a power of two near h
  std::optional<ComplexCholeskySolver> vector_heat;  // M + tL∇
  std::optional<PoissonSolver> scalar_heat;          // M + tL, Neumann
  mutable std::mutex distance_mutex;
  mutable std::unique_ptr<HeatDistanceSolver> distance;  // built by the first log_map()

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
  const HeatDistanceSolver& distance_solver() const;
};

// Two jobs side by side, each assembling its own matrix and factoring it: the complex one (the
// longer: frames, L∇, a complex factorization ≈ 1.6× a real one) and the scalar one.
void VectorHeatSolver::Impl::factor() {
  mass = fem::lumped_mass(tri);
  auto complex_job = [this] {
    const Index nv = tri.n_vertices();
    frames = fem::tangent_frames(tri);
    halfedge_unit.resize(tri.n_halfedges());
    for (Index h = 0; h < tri.n_halfedges(); ++h) {
      halfedge_unit[h] = std::polar(1.0, frames.halfedge_angle[h]);
    }
    // M + tL∇, in place on L∇'s arrays (no second matrix); an unreferenced vertex (zero row,
    // zero mass) gets 1 on the diagonal: its right-hand side is always 0, so it stays 0 and the
    // matrix stays positive definite.
    ComplexSparseMatrix A = fem::connection_laplacian(tri, frames, 1);
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
    vector_heat.emplace(A, CholeskyOptions{});
  };
  auto scalar_job = [this] {
    comps = connected_components(tri);
    PoissonOptions heat_opt;
    heat_opt.screening = 1.0;  // tL + 1·M
    scalar_heat.emplace(t * fem::cotan_laplacian(tri), mass, comps, std::vector<Index>{}, heat_opt);
  };
  run_parallel({complex_job, scalar_job});
}

VectorHeatSolver::VectorHeatSolver(const IntrinsicTriangulation& tri_in,
                                   const VectorHeatOptions& options)
    : impl_(std::make_unique<Impl>()) {
  options.validate();
  if (tri_in.n_faces() == 0) throw InvalidInput("VectorHeatSolver: triangulation has no faces");
  if (static_cast<Index>(options.boundary_vertices.size()) > tri_in.n_vertices()) {
    throw InvalidInput("VectorHeatOptions: boundary_vertices has " +
                       std::to_string(options.boundary_vertices.size()) + " entries for " +
                       str(tri_in.n_vertices()) + " vertices");
  }
  Impl& im = *impl_;
  im.opt = options;
  im.tri = tri_in;
  if (options.intrinsic_delaunay) im.tri.flip_to_delaunay();
  double h = options.mean_edge_length > 0.0 ? options.mean_edge_length : mean_edge_length(tri_in);
  if (!(h > 0.0)) throw InvalidInput("VectorHeatSolver: mean edge length is 0");
  // units of a power of two near h: masses, t and the factors stay in range at any scale
  im.scale = intrinsic::power_of_two_scale(h);
  for (Index e = 0; e < im.tri.n_edges(); ++e) im.tri.set_length(e, im.tri.length(e) / im.scale);
  im.h_mean = h / im.scale;
  im.t = options.time_factor * im.h_mean * im.h_mean;
  im.factor();
}

VectorHeatSolver::~VectorHeatSolver() = default;
VectorHeatSolver::VectorHeatSolver(VectorHeatSolver&&) noexcept = default;
VectorHeatSolver& VectorHeatSolver::operator=(VectorHeatSolver&&) noexcept = default;

const IntrinsicTriangulation& VectorHeatSolver::triangulation() const { return impl_->tri; }
const fem::TangentFrames& VectorHeatSolver::frames() const { return impl_->frames; }
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
  Eigen::MatrixXd b = Eigen::MatrixXd::Zero(nv, 2);  // |vector| and 1 at the sources
  bool one_length = true;
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
    b(v, 0) = len;
    b(v, 1) = 1.0;
    one_length = one_length && len == std::abs(sources[0].vector);
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

const HeatDistanceSolver& VectorHeatSolver::Impl::distance_solver() const {
  std::lock_guard<std::mutex> lock(distance_mutex);
  if (!distance) {
    HeatDistanceOptions o;
    o.time_factor = opt.time_factor;
    o.mean_edge_length = h_mean;  // the same h and t as the vector heat step
    o.intrinsic_delaunay = false;
    o.boundary_vertices = opt.boundary_vertices;
    distance = std::make_unique<HeatDistanceSolver>(tri, o);
  }
  return *distance;
}

Eigen::VectorXcd VectorHeatSolver::log_map(Index source, VectorHeatReport* report) const {
  const Impl& im = *impl_;
  const Index nv = im.tri.n_vertices();
  std::vector<char> seen(nv, 0), source_component(im.comps.count, 0);
  im.check_source(source, "vector heat log_map: source", seen, source_component);
  Eigen::VectorXcd e0 = Eigen::VectorXcd::Zero(nv);
  e0[source] = 1.0;
  Eigen::VectorXcd horizontal;  // e^{i0} transported
  Eigen::VectorXd d;
  const std::vector<std::function<void()>> jobs = {
      [&] { horizontal = im.vector_heat->solve(e0); },
      [&] { d = im.distance_solver().compute_distance({source}) * im.scale; }};
  if (nv >= kParallelQueryVertices) {
    run_parallel(jobs);  // independent solves, memory bound: side by side on large meshes
  } else {
    for (const auto& j : jobs) j();
  }
  const Eigen::VectorXcd radial = im.gradient_directions(d);
  VectorHeatReport rep;
  std::vector<char> ok = im.resolved(horizontal.cwiseAbs(), source_component, rep);
  Eigen::VectorXcd out = Eigen::VectorXcd::Zero(nv);
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
  if (report) *report = rep;
  return out;
}

// --- 3D tangent bases ---------------------------------------------------------------------------

namespace {

// Area-weighted vertex normals of the triangles (unnormalized), or for a point cloud the given
// normals, or the smallest principal axis of the chords to the intrinsic neighbours.
Eigen::MatrixX3d raw_normals(const Positions& p, const std::vector<Triangle>& triangles,
                             const Eigen::MatrixX3d& normals, const IntrinsicTriangulation& tri) {
  const Index n = static_cast<Index>(p.rows());
  Eigen::MatrixX3d out = Eigen::MatrixX3d::Zero(n, 3);
  if (!triangles.empty()) {
    for (const Triangle& f : triangles) {
      const Eigen::Vector3d a = p.row(f[0]), b = p.row(f[1]), c = p.row(f[2]);
      const Eigen::Vector3d nf = (b - a).cross(c - a);  // twice the area times the unit normal
      for (const Index v : f) out.row(v) += nf.transpose();
    }
    return out;
  }
  if (normals.rows() == n) return normals;
  std::vector<Eigen::Matrix3d> cov(static_cast<std::size_t>(n), Eigen::Matrix3d::Zero());
  for (Index h = 0; h < tri.n_halfedges(); ++h) {
    const Index v = tri.tail(h), w = tri.head(h);
    if (v >= n || w >= n || v == w) continue;
    const Eigen::Vector3d d = (p.row(w) - p.row(v)).transpose();
    cov[v] += d * d.transpose();
  }
  for (Index v = 0; v < n; ++v) {
    if (cov[v].isZero()) continue;
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(cov[v]);
    out.row(v) = es.eigenvectors().col(0).transpose();  // eigenvalues ascending
  }
  return out;
}

// A unit vector orthogonal to the unit vector n.
Eigen::Vector3d any_orthogonal(const Eigen::Vector3d& n) {
  const Eigen::Vector3d a =
      std::abs(n.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
  return (a - a.dot(n) * n).normalized();
}

void check_basis_inputs(const Positions& positions, const std::vector<Triangle>& triangles,
                        const Eigen::MatrixX3d& normals, const IntrinsicTriangulation& tri,
                        const fem::TangentFrames& frames) {
  const Index n = static_cast<Index>(positions.rows());
  if (n > tri.n_vertices()) {
    throw InvalidInput("tangent_basis_3d: positions has " + str(n) +
                       " rows for a triangulation of " + str(tri.n_vertices()) + " vertices");
  }
  if (normals.rows() != 0 && normals.rows() != n) {
    throw InvalidInput("tangent_basis_3d: normals has " + str(Index(normals.rows())) +
                       " rows, expected 0 or " + str(n));
  }
  if (frames.halfedge_angle.size() != tri.n_halfedges() ||
      frames.angle_scale.size() != tri.n_vertices()) {
    throw InvalidInput("tangent_basis_3d: frames are not those of the triangulation");
  }
  for (const Triangle& f : triangles) {
    for (const Index v : f) {
      if (v < 0 || v >= n) {
        throw InvalidInput("tangent_basis_3d: triangle index " + str(v) + " out of range [0, " +
                           str(n) + ")");
      }
    }
  }
}

}  // namespace

namespace {

// The chord from tail(h) to head(h) projected to the tail's tangent plane (unit normals).
Eigen::Vector3d projected_chord(const Positions& p, const IntrinsicTriangulation& tri,
                                const Eigen::MatrixX3d& normal, Index h) {
  const Index v = tri.tail(h);
  const Eigen::Vector3d nv = normal.row(v).transpose();
  const Eigen::Vector3d d = (p.row(tri.head(h)) - p.row(v)).transpose();
  return d - d.dot(nv) * nv;
}

// Per positioned vertex, the outgoing halfedge that fixes e1: the reference halfedge when its
// head has a position (and a chord off the normal), else such a halfedge of smallest angle;
// kInvalidIndex when there is none.
std::vector<Index> anchors(const Positions& p, const IntrinsicTriangulation& tri,
                           const fem::TangentFrames& frames, const Eigen::MatrixX3d& normal) {
  const Index n = static_cast<Index>(p.rows());
  auto usable = [&](Index h) {
    const Index w = tri.head(h);
    return w < n && w != tri.tail(h) && projected_chord(p, tri, normal, h).norm() > 0.0;
  };
  std::vector<Index> anchor(static_cast<std::size_t>(n), kInvalidIndex);
  for (Index v = 0; v < n; ++v) {
    const Index h = tri.vertex_halfedge(v);
    if (h != kInvalidIndex && usable(h)) anchor[v] = h;
  }
  for (Index h = 0; h < tri.n_halfedges(); ++h) {
    const Index v = tri.tail(h);
    if (v >= n || !usable(h)) continue;
    const Index a = anchor[v];
    if (a == kInvalidIndex ||
        (a != tri.vertex_halfedge(v) && frames.halfedge_angle[h] < frames.halfedge_angle[a])) {
      anchor[v] = h;
    }
  }
  return anchor;
}

// Per vertex, > 0 when the chords turn counter-clockwise about the normal as the angles grow:
// Σ_h sin(θ_h − θ_anchor) · sin(angle from the anchor's chord to h's, about the normal).
Eigen::VectorXd orientation_votes(const Positions& p, const IntrinsicTriangulation& tri,
                                  const fem::TangentFrames& frames, const Eigen::MatrixX3d& normal,
                                  const std::vector<Index>& anchor) {
  const Index n = static_cast<Index>(p.rows());
  Eigen::VectorXd vote = Eigen::VectorXd::Zero(n);
  for (Index h = 0; h < tri.n_halfedges(); ++h) {
    const Index v = tri.tail(h), w = tri.head(h);
    if (v >= n || w >= n || v == w || anchor[v] == kInvalidIndex) continue;
    const Eigen::Vector3d a = projected_chord(p, tri, normal, anchor[v]);
    const Eigen::Vector3d d = projected_chord(p, tri, normal, h);
    const double norms = a.norm() * d.norm();
    if (!(norms > 0.0)) continue;
    const double s = std::sin(frames.halfedge_angle[h] - frames.halfedge_angle[anchor[v]]);
    vote[v] += s * a.cross(d).dot(normal.row(v).transpose()) / norms;
  }
  return vote;
}

}  // namespace

TangentBasis3d tangent_basis_3d(const Positions& p, const std::vector<Triangle>& triangles,
                                const Eigen::MatrixX3d& normals, const IntrinsicTriangulation& tri,
                                const fem::TangentFrames& frames) {
  check_basis_inputs(p, triangles, normals, tri, frames);
  const Index n = static_cast<Index>(p.rows());
  TangentBasis3d b;
  b.normal = raw_normals(p, triangles, normals, tri);
  std::vector<char> fallback(static_cast<std::size_t>(n), 0);
  for (Index v = 0; v < n; ++v) {
    const double len = b.normal.row(v).norm();
    if (len > 0.0 && std::isfinite(len)) {
      b.normal.row(v) /= len;
    } else {
      b.normal.row(v) = Eigen::RowVector3d::UnitZ();
      fallback[v] = 1;
    }
  }
  const std::vector<Index> anchor = anchors(p, tri, frames, b.normal);
  const Eigen::VectorXd vote = orientation_votes(p, tri, frames, b.normal, anchor);
  b.e1.resize(n, 3);
  b.e2.resize(n, 3);
  for (Index v = 0; v < n; ++v) {
    if (vote[v] < 0.0) b.normal.row(v) *= -1.0;
    const Eigen::Vector3d nv = b.normal.row(v).transpose();
    Eigen::Vector3d e1;
    if (anchor[v] == kInvalidIndex) {
      e1 = any_orthogonal(nv);
      fallback[v] = 1;
    } else {  // the anchor's chord turned back by its angle to angle 0
      const Eigen::Vector3d a = projected_chord(p, tri, b.normal, anchor[v]).normalized();
      const double theta = frames.halfedge_angle[anchor[v]];
      e1 = std::cos(theta) * a - std::sin(theta) * nv.cross(a);
    }
    b.e1.row(v) = e1.transpose();
    b.e2.row(v) = nv.cross(e1).transpose();
  }
  b.fallback_vertices = static_cast<Index>(std::count(fallback.begin(), fallback.end(), 1));
  return b;
}

TangentBasis3d tangent_basis_3d(const io::SurfaceInput& input, const IntrinsicTriangulation& tri,
                                const fem::TangentFrames& frames) {
  return tangent_basis_3d(input.positions, input.triangles, input.normals, tri, frames);
}

Eigen::MatrixX3d to_3d(const Eigen::VectorXcd& z, const TangentBasis3d& basis) {
  const Eigen::Index n = basis.e1.rows();
  if (z.size() < n) {
    throw InvalidInput("to_3d: " + std::to_string(z.size()) + " vectors for a basis of " +
                       std::to_string(n) + " vertices");
  }
  Eigen::MatrixX3d out(n, 3);
  for (Eigen::Index v = 0; v < n; ++v) {
    out.row(v) = z[v].real() * basis.e1.row(v) + z[v].imag() * basis.e2.row(v);
  }
  return out;
}

}  // namespace ifem::solvers
