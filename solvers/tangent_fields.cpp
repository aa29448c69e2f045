// Tangent-field recipes on a prepared surface (tangent_fields.h).
#include "solvers/tangent_fields.h"

#include <cmath>
#include <complex>
#include <string>

#include "fem/connection.h"
#include "intrinsic/core/errors.h"
#include "solvers/direction_field.h"
#include "solvers/vector_heat.h"

namespace ifem::solvers {

namespace {

// The constraints in the vertices' angular coordinates (directions projected with the basis).
std::vector<DirectionConstraint> held_directions(const PreparedSurface& s,
                                                 const FieldSettings& settings,
                                                 const TangentBasis3d& basis,
                                                 const fem::TangentFrames& frames) {
  std::vector<DirectionConstraint> held;
  const Index nv = s.n_input_vertices();
  for (std::size_t k = 0; k < settings.constraints.size(); ++k) {
    const InputDirection& c = settings.constraints[k];
    const std::string where =
        "direction " + std::to_string(k) + " (vertex " + std::to_string(c.vertex) + ")";
    if (c.vertex < 0 || c.vertex >= nv) {
      throw InvalidInput(where + ": vertex out of range [0, " + std::to_string(nv) + ")");
    }
    const double x = c.direction.dot(basis.e1.row(c.vertex).transpose());
    const double y = c.direction.dot(basis.e2.row(c.vertex).transpose());
    if (!std::isfinite(x) || !std::isfinite(y) || std::hypot(x, y) <= 1e-9 * c.direction.norm() ||
        c.direction.norm() == 0.0) {
      throw InvalidInput(where + ": the direction is zero, not finite or normal to the surface");
    }
    held.push_back({c.vertex, std::atan2(y, x)});
  }
  if (settings.align_boundary) {
    const std::vector<DirectionConstraint> b = boundary_constraints(s.tri, frames);
    held.insert(held.end(), b.begin(), b.end());
  }
  const std::vector<DirectionConstraint>& given = settings.intrinsic_constraints;
  held.insert(held.end(), given.begin(), given.end());
  return held;
}

// Tangent fields need the surface's own connection: on the tufted cover and point-cloud
// triangulations every vertex has several fans (fem/connection.h), and the directions computed
// there are not the surface's (measured: thousands of spurious singularities on every such
// input of ../shared/data). Refused until frames from the normals exist.
void require_manifold(const PreparedSurface& s, const char* what) {
  if (s.path == intrinsic::SurfacePath::kManifold) return;
  throw InvalidInput(std::string(what) +
                     " needs an edge-manifold, orientable mesh: this input took the " +
                     intrinsic::to_string(s.path) + " path (" + s.reason_detail +
                     "), whose vertices have several fans, so directions there are not the "
                     "surface's");
}

}  // namespace

TangentFieldResult direction_field_on(const PreparedSurface& s, const FieldSettings& settings) {
  DirectionFieldOptions o;
  o.symmetry = settings.symmetry;
  o.validate();
  require_manifold(s, "a direction field");
  const fem::TangentFrames frames = fem::tangent_frames(s.tri);
  const TangentBasis3d basis = tangent_basis_3d(s.input, s.tri, frames);
  const std::vector<DirectionConstraint> held = held_directions(s, settings, basis, frames);
  const DirectionField f =
      held.empty() ? smoothest_field(s.tri, frames, o) : aligned_field(s.tri, frames, held, o);
  const Index nv = s.n_input_vertices();
  const int n = settings.symmetry;
  TangentFieldResult r;
  r.constrained = f.constrained;
  r.energy = f.energy;
  r.iterations = f.iterations;
  r.angle = Eigen::VectorXd::Zero(nv);
  Eigen::VectorXcd direction = Eigen::VectorXcd::Zero(nv);
  for (Index v = 0; v < nv; ++v) {
    if (f.u[v] == std::complex<double>(0.0)) continue;
    r.angle[v] = std::arg(f.u[v]) / n;
    direction[v] = std::polar(1.0, r.angle[v]);
  }
  r.vectors = to_3d(direction, basis);
  const Eigen::VectorXi index = face_indices(s.tri, frames, f.u, n);
  r.face_singularity = input_face_indices(s, frames, f.u, n);
  r.singularity = Eigen::VectorXd::Zero(nv);
  for (Index face = 0; face < s.tri.n_faces(); ++face) {
    if (index[face] == 0) continue;
    ++r.singular_faces;
    r.total_index += index[face];
    Index lowest = s.tri.tail(3 * face);
    for (int k = 1; k < 3; ++k) lowest = std::min(lowest, s.tri.tail(3 * face + k));
    if (lowest < nv) r.singularity[lowest] += index[face];
  }
  return r;
}

VectorHeatSolver vector_heat_solver(const PreparedSurface& s) {
  require_manifold(s, "the vector heat method (transport, log map)");
  VectorHeatOptions o;
  o.intrinsic_delaunay = false;  // s.tri is intrinsic Delaunay: keep its coordinates
  o.mean_edge_length = distance_options(s).mean_edge_length;
  o.boundary_vertices = s.boundary_vertex;
  return VectorHeatSolver(s.tri, o);
}

Eigen::MatrixX3d transport_on(const PreparedSurface& s, const VectorHeatSolver& solver,
                              Index source, const Eigen::Vector3d& vector,
                              VectorHeatReport* report) {
  const Index nv = s.n_input_vertices();
  if (source < 0 || source >= nv) {
    throw InvalidInput("transport: source " + std::to_string(source) + " out of range [0, " +
                       std::to_string(nv) + ")");
  }
  const TangentBasis3d basis = tangent_basis_3d(s.input, solver.triangulation(), solver.frames());
  const std::complex<double> z(vector.dot(basis.e1.row(source).transpose()),
                               vector.dot(basis.e2.row(source).transpose()));
  if (!std::isfinite(std::abs(z)) || std::abs(z) <= 1e-12 * vector.norm() || vector.norm() == 0) {
    throw InvalidInput("transport: the vector at vertex " + std::to_string(source) +
                       " is zero, not finite or normal to the surface");
  }
  const Eigen::VectorXcd x = solver.transport({{source, z}}, report);
  return to_3d(x.head(nv), basis);
}

Eigen::MatrixX2d log_map_on(const PreparedSurface& s, const VectorHeatSolver& solver, Index source,
                            VectorHeatReport* report) {
  const Index nv = s.n_input_vertices();
  if (source < 0 || source >= nv) {
    throw InvalidInput("log map: source " + std::to_string(source) + " out of range [0, " +
                       std::to_string(nv) + ")");
  }
  const Eigen::VectorXcd z = solver.log_map(source, report);
  // the solver's angle 0 is the reference halfedge; the basis' e1 is that halfedge's direction
  Eigen::MatrixX2d uv(nv, 2);
  for (Index v = 0; v < nv; ++v) uv.row(v) << z[v].real(), z[v].imag();
  return uv;
}

}  // namespace ifem::solvers
