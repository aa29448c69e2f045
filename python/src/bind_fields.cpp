// Tangent fields: the smoothest n-direction field, free or aligned
// (solvers/recipes/tangent_fields.h), as `ifem field` computes it.
#include <pybind11/stl.h>

#include <memory>
#include <string>
#include <utility>

#include "arrays.h"
#include "bindings.h"
#include "intrinsic/core/errors.h"
#include "solvers/recipes/curve_fields.h"
#include "solvers/recipes/tangent_fields.h"

namespace ifem::python {

namespace {

// (vertex ids, #K×3 directions) as constraints on input vertices.
std::vector<solvers::InputDirection> input_directions(const py::handle& vertices,
                                                      const py::handle& directions, Index n) {
  if (vertices.is_none() && directions.is_none()) return {};
  if (vertices.is_none() || directions.is_none()) {
    throw InvalidInput("constraints need both vertices and directions (or neither)");
  }
  const std::vector<Index> ids = indices_from(vertices, n, "constraint_vertices", true);
  const Positions d = ids.empty() ? Positions(0, 3) : positions_from(directions, "directions");
  if (static_cast<std::size_t>(d.rows()) != ids.size()) {
    throw InvalidInput("directions must have one row per constraint vertex (" +
                       std::to_string(ids.size()) + "), got " + std::to_string(d.rows()));
  }
  std::vector<solvers::InputDirection> out(ids.size());
  for (std::size_t k = 0; k < ids.size(); ++k) {
    out[k] = {ids[k], d.row(static_cast<Eigen::Index>(k)).transpose(),
              "constraint_vertices[" + std::to_string(k) + "]"};
  }
  return out;
}

// The surface arguments every field function shares: mollify, path, knn, point normals.
struct FieldArgs {
  double mollify = 1e-5;
  std::string path = "auto";
  int knn = 30;
  Index max_iterations = -1;    ///< with curves: FlipOut's cap (−1: the library's default)
  bool accept_partial = false;  ///< with curves: accept curves left at that cap
};

solvers::PreparedSurface prepared(io::SurfaceInput in, const FieldArgs& a) {
  return prepare(std::move(in), prepare_options(a.mollify, a.path, true, a.knn), a.path);
}

// The field on the input with the curves inserted and held (solvers/recipes/curve_fields.h): curves
// need the manifold path (signposts), so path must be 'auto' or 'manifold'.
solvers::TangentFieldResult field_along_curves(io::SurfaceInput in, const py::list& curves,
                                               const solvers::FieldOptions& settings,
                                               const FieldArgs& a, py::dict& info) {
  if (a.path != "auto" && a.path != "manifold") {
    throw InvalidInput(
        "curves need the manifold path (signposts on an edge-manifold, orientable "
        "mesh), not path='" +
        a.path + "'");
  }
  const solvers::CurveSurface s = prepare_with_curves(std::move(in), curves, py::none(), a.mollify,
                                                      false, a.max_iterations, a.accept_partial);
  solvers::TangentFieldResult r;
  {
    const py::gil_scoped_release release;
    r = solvers::curve_direction_field(s, settings);
  }
  info = surface_info(s.surface);
  info["curves"] = curve_surface_info(s);
  return r;
}

// curves: None, or a list of curve specs (ifem.Curve's tuples).
py::tuple direction_field(const py::handle& V, const py::handle& F, int symmetry,
                          bool align_boundary, const py::handle& vertices,
                          const py::handle& directions, const py::handle& normals,
                          const FieldArgs& a, const py::handle& curves) {
  solvers::FieldOptions settings;
  settings.symmetry = symmetry;
  settings.align_boundary = align_boundary;
  io::SurfaceInput in = surface_input(V, F, normals);
  settings.constraints =
      input_directions(vertices, directions, static_cast<Index>(in.positions.rows()));
  py::dict info;
  solvers::TangentFieldResult r;
  if (!curves.is_none()) {
    r = field_along_curves(std::move(in), curves.cast<py::list>(), settings, a, info);
  } else {
    const solvers::PreparedSurface s = prepared(std::move(in), a);
    {
      const py::gil_scoped_release release;
      r = solvers::direction_field_on(s, settings);
    }
    info = surface_info(s);
  }
  info["singular_faces"] = r.singular_faces;
  std::vector<Index> face_index(r.face_singularity.data(),
                                r.face_singularity.data() + r.face_singularity.size());
  info["face_singularity"] = to_numpy(std::move(face_index));
  info["total_index"] = r.total_index;
  info["constrained"] = r.constrained;
  info["energy"] = r.energy;
  info["orientation_conflicts"] = r.orientation_conflicts;
  info["components"] = r.components;
  info["free_components"] = r.free_components;
  info["empty_components"] = r.empty_components;
  info["flat_components"] = r.flat_components;
  info["skipped_constraints"] = r.skipped_constraints;
  return py::make_tuple(to_numpy(Eigen::MatrixXd(r.vectors)), to_numpy(std::move(r.angle)),
                        to_numpy(std::move(r.singularity)), info);
}

// A prepared surface and its vector heat solver (factored once; queries reuse it).
class VectorHeat {
 public:
  VectorHeat(const py::handle& V, const py::handle& F, const py::handle& normals,
             const FieldArgs& a)
      : s_(prepared(surface_input(V, F, normals), a)), solver_(build(s_)) {}

  py::array transport(const py::handle& source, const py::handle& vector) const {
    const Index v = single_vertex(source);
    const Positions x = positions_from(vector, "vector");
    if (x.rows() != 1) throw InvalidInput("vector must be one 3D vector");
    Eigen::MatrixX3d out;
    {
      const py::gil_scoped_release release;
      out = solvers::transport_on(s_, solver_, v, x.row(0).transpose());
    }
    return to_numpy(Eigen::MatrixXd(out));
  }

  // (uv #V×2, distance #V, {"unreached": n, "unresolved": n}); method "blend", "affine" or
  // "vector-heat"
  py::tuple log_map(const py::handle& source, const std::string& method) const {
    const Index v = single_vertex(source);
    solvers::LogMapMethod m;
    try {
      m = solvers::log_map_method_from(method);
    } catch (const InvalidInput& e) {
      throw InvalidInput(std::string("method = ") + e.what());
    }
    solvers::LogMapResult r;
    {
      const py::gil_scoped_release release;
      r = solvers::log_map_on(s_, solver_, v, m);
    }
    py::dict counts;
    counts["unreached"] = r.report.unreached_vertices;
    counts["unresolved"] = r.report.unresolved_vertices;
    return py::make_tuple(to_numpy(Eigen::MatrixXd(r.uv)), to_numpy(std::move(r.distance)), counts);
  }

  py::dict info() const { return surface_info(s_); }

 private:
  static solvers::VectorHeatSolver build(const solvers::PreparedSurface& s) {
    const py::gil_scoped_release release;
    return solvers::vector_heat_solver(s);
  }
  Index single_vertex(const py::handle& source) const {
    const std::vector<Index> ids = indices_from(source, s_.n_input_vertices(), "source");
    if (ids.size() != 1) throw InvalidInput("source must be one vertex id");
    return ids[0];
  }

  solvers::PreparedSurface s_;
  solvers::VectorHeatSolver solver_;
};

}  // namespace

void bind_fields(py::module_& m) {
  py::class_<VectorHeat>(m, "VectorHeat")
      .def(py::init([](const py::handle& V, const py::handle& F, const py::handle& normals,
                       double mollify, const std::string& path, int knn) {
             return std::make_unique<VectorHeat>(V, F, normals, FieldArgs{mollify, path, knn});
           }),
           py::arg("V"), py::arg("F"), py::arg("normals"), py::arg("mollify"), py::arg("path"),
           py::arg("knn"))
      .def("transport", &VectorHeat::transport, py::arg("source"), py::arg("vector"))
      .def("log_map", &VectorHeat::log_map, py::arg("source"), py::arg("method"))
      .def("info", &VectorHeat::info);
  m.def(
      "direction_field",
      [](const py::handle& V, const py::handle& F, int symmetry, bool align_boundary,
         const py::handle& vertices, const py::handle& directions, const py::handle& normals,
         double mollify, const std::string& path, int knn, const py::handle& curves,
         Index max_iterations, bool accept_partial) {
        return direction_field(V, F, symmetry, align_boundary, vertices, directions, normals,
                               FieldArgs{mollify, path, knn, max_iterations, accept_partial},
                               curves);
      },
      py::arg("V"), py::arg("F"), py::arg("symmetry"), py::arg("align_boundary"),
      py::arg("vertices"), py::arg("directions"), py::arg("normals"), py::arg("mollify"),
      py::arg("path"), py::arg("knn"), py::arg("curves"), py::arg("max_iterations") = -1,
      py::arg("accept_partial") = false);
}

}  // namespace ifem::python
