// Tangent-field recipes on a prepared surface (tangent_fields.h).
#include "solvers/recipes/tangent_fields.h"

#include <algorithm>
#include <cmath>
#include <complex>
#include <string>

#include "fem/connection.h"
#include "fem/frame_connection.h"
#include "fem/operators.h"
#include "intrinsic/core/errors.h"
#include "solvers/scalar/components.h"
#include "solvers/vector/direction_field.h"
#include "solvers/vector/vector_heat.h"

namespace ifem::solvers {

namespace {

// The constraints in the vertices' angular coordinates (directions projected with the basis).
std::vector<DirectionConstraint> held_directions(const PreparedSurface& s,
                                                 const FieldOptions& settings,
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
    const std::vector<DirectionConstraint> b =
        boundary_constraints(s.tri, frames, settings.symmetry);
    held.insert(held.end(), b.begin(), b.end());
  }
  const std::vector<DirectionConstraint>& given = settings.intrinsic_constraints;
  held.insert(held.end(), given.begin(), given.end());
  return held;
}

// The tufted cover and point-cloud triangulations have several fans per vertex
// (fem/connection.h), so their intrinsic angles are not the surface's directions: there the
// fields run on frames from the input's normals (fem/frame_connection.h), which need a position
// for every vertex of the triangulation.
bool on_frame_path(const PreparedSurface& s, const char* what) {
  if (s.path == intrinsic::SurfacePath::kManifold) return false;
  if (s.tri.n_vertices() != s.n_input_vertices()) {
    throw InvalidInput(std::string(what) + " on the " + intrinsic::to_string(s.path) +
                       " path uses frames from the input's positions, so every vertex must be "
                       "an input vertex: do not refine (" +
                       std::to_string(s.tri.n_vertices() - s.n_input_vertices()) +
                       " inserted vertices)");
  }
  return true;
}

// The signposts of a refined surface, for the 3D bases of input vertices whose neighbours are
// all inserted vertices (tangent_basis_3d); none otherwise.
const intrinsic::SignpostTriangulation* signposts_of(const PreparedSurface& s) {
  return s.signposts ? &*s.signposts : nullptr;
}

// The field's singular faces added to their lowest corner (input vertices only).
void add_singularities(const std::vector<Triangle>& faces, const Eigen::VectorXi& index, Index nv,
                       TangentFieldResult& r) {
  r.singularity = Eigen::VectorXd::Zero(nv);
  for (std::size_t face = 0; face < faces.size(); ++face) {
    const int k = index[static_cast<Index>(face)];
    if (k == 0) continue;
    ++r.singular_faces;
    r.total_index += k;
    const Index lowest = *std::min_element(faces[face].begin(), faces[face].end());
    if (lowest < nv) r.singularity[lowest] += k;
  }
}

// The faces of the intrinsic triangulation as vertex triples (for add_singularities()).
std::vector<Triangle> triangulation_faces(const intrinsic::IntrinsicTriangulation& tri) {
  std::vector<Triangle> faces(static_cast<std::size_t>(tri.n_faces()));
  for (Index f = 0; f < tri.n_faces(); ++f) {
    faces[f] = {tri.tail(3 * f), tri.tail(3 * f + 1), tri.tail(3 * f + 2)};
  }
  return faces;
}

// The result's vectors and angles from the power representation u in the given basis.
TangentFieldResult field_result(const DirectionField& f, const TangentBasis3d& basis, Index nv,
                                int n) {
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
  return r;
}

// direction_field_on() on the frame path.
TangentFieldResult frame_field(const PreparedSurface& s, const FieldOptions& settings,
                               const DirectionFieldOptions& o) {
  if (settings.align_boundary) {
    throw InvalidInput(std::string("align_boundary needs the manifold path: this input took the ") +
                       intrinsic::to_string(s.path) + " path (" + s.reason_detail + ")");
  }
  if (!settings.intrinsic_constraints.empty()) {
    throw InvalidInput(std::string("intrinsic constraints (curves) need the manifold path: this "
                                   "input took the ") +
                       intrinsic::to_string(s.path) + " path (" + s.reason_detail + ")");
  }
  const TangentBasis3d basis = frame_basis_3d(s.input, s.tri);
  const fem::ComplexSparseMatrix L = fem::connection_laplacian_from_frames(
      fem::cotan_laplacian(s.tri), basis.normal, basis.e1, basis.e2, settings.symmetry);
  const Eigen::VectorXd mass = fem::lumped_mass(s.tri);
  const Components comps = connected_components(s.tri);
  const std::vector<DirectionConstraint> held =
      held_directions(s, settings, basis, fem::TangentFrames{});
  const DirectionField f =
      held.empty() ? smoothest_field(L, mass, comps, o) : aligned_field(L, mass, comps, held, o);
  TangentFieldResult r = field_result(f, basis, s.n_input_vertices(), settings.symmetry);
  const Eigen::VectorXi index =
      frame_face_indices(s.input.positions, s.input.triangles, basis, f.u, settings.symmetry);
  add_singularities(s.input.triangles, index, s.n_input_vertices(), r);
  r.face_singularity = index;  // already on the input's triangles
  r.orientation_conflicts = basis.orientation_conflicts;
  return r;
}

}  // namespace

void FieldOptions::validate() const {
  if (symmetry < 1) {
    throw InvalidInput("FieldOptions: symmetry must be ≥ 1, got " + std::to_string(symmetry));
  }
  for (std::size_t k = 0; k < intrinsic_constraints.size(); ++k) {
    const DirectionConstraint& c = intrinsic_constraints[k];
    if (c.vertex < 0 || !std::isfinite(c.angle)) {
      throw InvalidInput("FieldOptions: intrinsic_constraints[" + std::to_string(k) +
                         "] needs a vertex ≥ 0 and a finite angle");
    }
  }
}

TangentFieldResult direction_field_on(const PreparedSurface& s, const FieldOptions& settings) {
  settings.validate();
  DirectionFieldOptions o;
  o.symmetry = settings.symmetry;
  o.validate();
  if (on_frame_path(s, "a direction field")) return frame_field(s, settings, o);
  const fem::TangentFrames frames = fem::tangent_frames(s.tri);
  const TangentBasis3d basis = tangent_basis_3d(s.input, s.tri, frames, signposts_of(s));
  const std::vector<DirectionConstraint> held = held_directions(s, settings, basis, frames);
  const DirectionField f =
      held.empty() ? smoothest_field(s.tri, frames, o) : aligned_field(s.tri, frames, held, o);
  const Index nv = s.n_input_vertices();
  TangentFieldResult r = field_result(f, basis, nv, settings.symmetry);
  add_singularities(triangulation_faces(s.tri), face_indices(s.tri, frames, f.u, settings.symmetry),
                    nv, r);
  r.face_singularity = input_face_indices(s, frames, f.u, settings.symmetry);
  return r;
}

VectorHeatSolver vector_heat_solver(const PreparedSurface& s) {
  VectorHeatOptions o;
  o.intrinsic_delaunay = false;  // s.tri is intrinsic Delaunay: keep its coordinates
  o.mean_edge_length = distance_options(s).mean_edge_length;
  o.boundary_vertices = s.boundary_vertex;
  if (on_frame_path(s, "the vector heat method (transport, log map)")) {
    return VectorHeatSolver(s.tri, s.input.positions, frame_basis_3d(s.input, s.tri), o);
  }
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
  const TangentBasis3d basis =
      solver.on_frames()
          ? solver.frame_basis()
          : tangent_basis_3d(s.input, solver.triangulation(), solver.frames(), signposts_of(s));
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
