// Tangent fields: the smoothest n-direction field, free or aligned (solvers/tangent_fields.h),
// as `ifem field` computes it.
#include <pybind11/stl.h>

#include <string>
#include <utility>

#include "arrays.h"
#include "bindings.h"
#include "intrinsic/core/errors.h"
#include "solvers/tangent_fields.h"

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
    out[k] = {ids[k], d.row(static_cast<Eigen::Index>(k)).transpose()};
  }
  return out;
}

py::tuple direction_field(const py::handle& V, const py::handle& F, int symmetry,
                          bool align_boundary, const py::handle& vertices,
                          const py::handle& directions, double mollify) {
  io::SurfaceInput in = surface_input(V, F);
  if (in.triangles.empty()) throw InvalidInput("F has no faces: direction fields need a mesh");
  solvers::FieldSettings settings;
  settings.symmetry = symmetry;
  settings.align_boundary = align_boundary;
  settings.constraints =
      input_directions(vertices, directions, static_cast<Index>(in.positions.rows()));
  const solvers::PreparedSurface s =
      prepare(std::move(in), prepare_options(mollify, "auto", true, 30), "auto");
  solvers::TangentFieldResult r;
  {
    const py::gil_scoped_release release;
    r = solvers::direction_field_on(s, settings);
  }
  py::dict info = surface_info(s);
  info["singular_faces"] = r.singular_faces;
  info["total_index"] = r.total_index;
  info["constrained"] = r.constrained;
  info["energy"] = r.energy;
  return py::make_tuple(to_numpy(Eigen::MatrixXd(r.vectors)), to_numpy(std::move(r.angle)),
                        to_numpy(std::move(r.singularity)), info);
}

}  // namespace

void bind_fields(py::module_& m) {
  m.def("direction_field", &direction_field, py::arg("V"), py::arg("F"), py::arg("symmetry"),
        py::arg("align_boundary"), py::arg("vertices"), py::arg("directions"), py::arg("mollify"));
}

}  // namespace ifem::python
