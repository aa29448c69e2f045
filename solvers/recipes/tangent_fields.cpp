// Tangent-field recipes on a prepared surface (tangent_fields.h).
#include "solvers/recipes/tangent_fields.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <complex>
#include <limits>
#include <map>
#include <string>
#include <utility>

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
// Directions at vertices of flat components (comps.label kInvalidIndex) are skipped, counted in
// *skipped: they have no tangent plane.
std::vector<DirectionConstraint> held_directions(const PreparedSurface& s,
                                                 const FieldOptions& settings,
                                                 const TangentBasis3d& basis,
                                                 const fem::TangentFrames& frames,
                                                 const Components& comps, Index* skipped) {
  std::vector<DirectionConstraint> held;
  const Index nv = s.n_input_vertices();
  *skipped = 0;
  auto name = [&](std::size_t k) {
    const InputDirection& c = settings.constraints[k];
    return (c.origin.empty() ? "direction " + std::to_string(k) : c.origin) + " (vertex " +
           std::to_string(c.vertex) + ")";
  };
  std::vector<std::size_t> first(nv, settings.constraints.size());  // per vertex: its first
  for (std::size_t k = 0; k < settings.constraints.size(); ++k) {
    const InputDirection& c = settings.constraints[k];
    const std::string where = name(k);
    if (c.vertex < 0 || c.vertex >= nv) {
      throw InvalidInput(where + ": vertex out of range [0, " + std::to_string(nv) + ")");
    }
    std::size_t& seen = first[c.vertex];
    if (seen < k) {  // a second direction at one vertex: the same one (any length) or refused
      const Eigen::Vector3d a = settings.constraints[seen].direction.normalized();
      if ((a - c.direction.normalized()).norm() > 1e-12) {
        throw InvalidInput(where + ": a second, different direction at the vertex of " +
                           name(seen) + "; one direction per vertex");
      }
    }
    seen = std::min(seen, k);
    if (comps.label[c.vertex] == kInvalidIndex) {
      ++*skipped;
      continue;
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

// The components of s.tri that can carry a field: a component whose input faces (the
// triangulation's own for a point cloud) span no area in space (every face of zero area,
// collinear or coincident corners, up to 1e-10 of its longest edge squared) has no tangent plane,
// so its vertices are labelled kInvalidIndex (count kept: direction_field.h counts them empty).
// *flat: how many.
Components field_components(const PreparedSurface& s, const std::vector<Triangle>& tri_faces,
                            Index* flat) {
  Components comps = connected_components(s.tri);
  const std::vector<Triangle>& faces = s.input.triangles.empty() ? tri_faces : s.input.triangles;
  const Index nv = s.n_input_vertices();
  std::vector<double> area(comps.count, 0.0), longest(comps.count, 0.0);
  for (const Triangle& f : faces) {
    if (f[0] >= nv || f[1] >= nv || f[2] >= nv || comps.label[f[0]] == kInvalidIndex) continue;
    const Index c = comps.label[f[0]];
    const Eigen::Vector3d a = s.input.positions.row(f[0]), b = s.input.positions.row(f[1]),
                          d = s.input.positions.row(f[2]);
    area[c] += 0.5 * (b - a).cross(d - a).norm();
    longest[c] = std::max({longest[c], (b - a).norm(), (d - a).norm(), (d - b).norm()});
  }
  std::vector<char> is_flat(comps.count, 0);
  *flat = 0;
  for (Index c = 0; c < comps.count; ++c) {
    is_flat[c] = !(area[c] > 1e-10 * longest[c] * longest[c]);
    *flat += is_flat[c];
  }
  for (Index& c : comps.label) {
    if (c != kInvalidIndex && is_flat[c]) c = kInvalidIndex;
  }
  return comps;
}

// The result's vectors and angles from the power representation u in the given basis.
TangentFieldResult field_result(const DirectionField& f, const TangentBasis3d& basis, Index nv,
                                int n) {
  TangentFieldResult r;
  r.constrained = f.constrained;
  r.energy = f.energy;
  r.iterations = f.iterations;
  r.free_components = f.free_components;
  r.empty_components = f.empty_components;
  r.angle = Eigen::VectorXd::Zero(nv);
  Eigen::VectorXcd direction = Eigen::VectorXcd::Zero(nv);
  for (Index v = 0; v < nv; ++v) {
    if (f.u[v] == std::complex<double>(0.0)) continue;
    r.angle[v] = std::arg(f.u[v]) / n;
    direction[v] = std::polar(1.0, r.angle[v]);
  }
  r.vectors = to_3d(direction, basis);
  for (Index v = 0; v < nv; ++v) {
    if (direction[v] == std::complex<double>(0.0)) r.vectors.row(v).setZero();  // no direction
  }
  return r;
}

// The frame path's boundary directions, as boundary_constraints() on the manifold path: along
// every edge of the input's faces that only one face has (the input's boundary; the tufted cover
// has none), at its first vertex as the face runs (the edge leaving it; a vertex where several
// leave takes the mean of their n-th powers). Skipped at vertices of flat components and where
// the edge is normal to the frame.
std::vector<DirectionConstraint> frame_boundary_directions(const PreparedSurface& s,
                                                           const TangentBasis3d& basis,
                                                           const Components& comps) {
  if (s.input.triangles.empty()) {
    throw InvalidInput("align_boundary needs a mesh's faces: a point cloud has no boundary");
  }
  std::map<std::pair<Index, Index>, int> uses;
  auto key = [](Index a, Index b) { return std::make_pair(std::min(a, b), std::max(a, b)); };
  for (const Triangle& f : s.input.triangles) {
    for (int k = 0; k < 3; ++k) ++uses[key(f[k], f[(k + 1) % 3])];
  }
  std::vector<DirectionConstraint> out;
  for (const Triangle& f : s.input.triangles) {
    for (int k = 0; k < 3; ++k) {
      const Index a = f[k], b = f[(k + 1) % 3];
      if (a == b || uses[key(a, b)] != 1) continue;
      if (comps.label[a] == kInvalidIndex) continue;
      const Eigen::Vector3d d = (s.input.positions.row(b) - s.input.positions.row(a)).transpose();
      const double x = d.dot(basis.e1.row(a).transpose()), y = d.dot(basis.e2.row(a).transpose());
      if (std::isfinite(x) && std::isfinite(y) && std::hypot(x, y) > 1e-9 * d.norm()) {
        out.push_back({a, std::atan2(y, x)});
      }
    }
  }
  return out;
}

// direction_field_on() on the frame path.
TangentFieldResult frame_field(const PreparedSurface& s, const FieldOptions& settings,
                               const DirectionFieldOptions& o) {
  if (!settings.intrinsic_constraints.empty()) {
    throw InvalidInput(std::string("intrinsic constraints (curves) need the manifold path: this "
                                   "input took the ") +
                       intrinsic::to_string(s.path) + " path (" + s.reason_detail + ")");
  }
  const TangentBasis3d basis = frame_basis_3d(s.input, s.tri);
  const fem::ComplexSparseMatrix L = fem::connection_laplacian_from_frames(
      fem::cotan_laplacian(s.tri), basis.normal, basis.e1, basis.e2, settings.symmetry);
  const Eigen::VectorXd mass = fem::lumped_mass(s.tri);
  Index flat = 0, skipped = 0;
  const Components comps = field_components(s, triangulation_faces(s.tri), &flat);
  FieldOptions given = settings;
  given.align_boundary = false;  // held_directions() knows the manifold path's boundary only
  std::vector<DirectionConstraint> held =
      held_directions(s, given, basis, fem::TangentFrames{}, comps, &skipped);
  if (settings.align_boundary) {
    const std::vector<DirectionConstraint> b = frame_boundary_directions(s, basis, comps);
    held.insert(held.end(), b.begin(), b.end());
  }
  const DirectionField f =
      held.empty() ? smoothest_field(L, mass, comps, o) : aligned_field(L, mass, comps, held, o);
  TangentFieldResult r = field_result(f, basis, s.n_input_vertices(), settings.symmetry);
  r.components = comps.count;
  r.flat_components = flat;
  r.skipped_constraints = skipped;
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
  const TangentBasis3d basis = tangent_basis_3d(s.input, s.tri, frames, s.correspondence());
  const std::vector<Triangle> faces = triangulation_faces(s.tri);
  Index flat = 0, skipped = 0;
  const Components comps = field_components(s, faces, &flat);
  const std::vector<DirectionConstraint> held =
      held_directions(s, settings, basis, frames, comps, &skipped);
  const fem::ComplexSparseMatrix L = fem::connection_laplacian(s.tri, frames, settings.symmetry);
  const Eigen::VectorXd mass = fem::lumped_mass(s.tri);
  const DirectionField f =
      held.empty() ? smoothest_field(L, mass, comps, o) : aligned_field(L, mass, comps, held, o);
  const Index nv = s.n_input_vertices();
  TangentFieldResult r = field_result(f, basis, nv, settings.symmetry);
  r.components = comps.count;
  r.flat_components = flat;
  r.skipped_constraints = skipped;
  add_singularities(faces, face_indices(s.tri, frames, f.u, settings.symmetry), nv, r);
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
  return VectorHeatSolver(s.tri, s.input, o, s.correspondence());  // keeps the 3D bases
}

Eigen::MatrixX3d transport_on(const PreparedSurface& s, const VectorHeatSolver& solver,
                              Index source, const Eigen::Vector3d& vector,
                              VectorHeatReport* report) {
  const Index nv = s.n_input_vertices();
  if (source < 0 || source >= nv) {
    throw InvalidInput("transport: source " + std::to_string(source) + " out of range [0, " +
                       std::to_string(nv) + ")");
  }
  // the solver's own bases (vector_heat_solver(s) builds them once); rebuilt for a solver made
  // without the input
  TangentBasis3d rebuilt;
  const bool kept = solver.basis_3d().e1.rows() == nv;
  if (!kept)
    rebuilt =
        tangent_basis_3d(s.input, solver.triangulation(), solver.frames(), s.correspondence());
  const TangentBasis3d& basis = kept ? solver.basis_3d() : rebuilt;
  const std::complex<double> z(vector.dot(basis.e1.row(source).transpose()),
                               vector.dot(basis.e2.row(source).transpose()));
  if (!std::isfinite(std::abs(z)) || std::abs(z) <= 1e-12 * vector.norm() || vector.norm() == 0) {
    throw InvalidInput("transport: the vector at vertex " + std::to_string(source) +
                       " is zero, not finite or normal to the surface");
  }
  const Eigen::VectorXcd x = solver.transport({{source, z}}, report);
  Eigen::MatrixX3d out = to_3d(x.head(nv), basis);
  for (Index v = 0; v < nv; ++v) {  // the solver's "none" is 0: NaN here, as distance's inf
    if (x[v] == std::complex<double>(0.0)) out.row(v).setConstant(std::nan(""));
  }
  return out;
}

LogMapResult log_map_on(const PreparedSurface& s, const VectorHeatSolver& solver, Index source,
                        LogMapMethod method) {
  const Index nv = s.n_input_vertices();
  if (source < 0 || source >= nv) {
    throw InvalidInput("log map: source " + std::to_string(source) + " out of range [0, " +
                       std::to_string(nv) + ")");
  }
  LogMapResult r;
  const Eigen::VectorXcd z = solver.log_map(source, method, &r.report);
  // the solver's angle 0 is the reference halfedge; the basis' e1 is that halfedge's direction
  r.uv.resize(nv, 2);
  for (Index v = 0; v < nv; ++v) r.uv.row(v) << z[v].real(), z[v].imag();
  const Components comps = connected_components(solver.triangulation());
  const Index c0 = comps.label[source];
  r.distance.resize(nv);
  for (Index v = 0; v < nv; ++v) {
    const bool reached = comps.label[v] != kInvalidIndex && comps.label[v] == c0;
    r.distance[v] = reached ? std::abs(z[v]) : std::numeric_limits<double>::infinity();
  }
  return r;
}

Eigen::MatrixX2d log_map_on(const PreparedSurface& s, const VectorHeatSolver& solver, Index source,
                            VectorHeatReport* report) {
  LogMapResult r = log_map_on(s, solver, source, LogMapMethod::kBlend);
  if (report) *report = r.report;
  return std::move(r.uv);
}

}  // namespace ifem::solvers
