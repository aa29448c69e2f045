// Signed distance to curves or oriented points (solvers/recipes/signed_distance.h), as
// `ifem distance --signed` computes it.
#include <pybind11/stl.h>

#include <string>
#include <utility>

#include "arrays.h"
#include "bindings.h"
#include "intrinsic/core/errors.h"
#include "solvers/recipes/signed_distance.h"

namespace ifem::python {

namespace {

// (point ids, #K×3 normals) as oriented points on input vertices.
std::vector<solvers::InputDirection> oriented_points(const py::handle& ids_in,
                                                     const py::handle& normals_in, Index n) {
  const std::vector<Index> ids = indices_from(ids_in, n, "points");
  const Positions d = positions_from(normals_in, "point_normals");
  if (static_cast<std::size_t>(d.rows()) != ids.size()) {
    throw InvalidInput("point_normals must have one row per point (" + std::to_string(ids.size()) +
                       "), got " + std::to_string(d.rows()));
  }
  std::vector<solvers::InputDirection> out(ids.size());
  for (std::size_t k = 0; k < ids.size(); ++k) {
    out[k] = {ids[k], d.row(static_cast<Eigen::Index>(k)).transpose(),
              "points[" + std::to_string(k) + "]"};
  }
  return out;
}

// (d, info): curves (a list of specs) or points with point_normals, exactly one of them.
py::tuple signed_distance(const py::handle& V, const py::handle& F, const py::handle& normals,
                          const py::handle& curves, const py::handle& points,
                          const py::handle& point_normals, const py::handle& refine,
                          double time_factor, const std::string& level_set, double mollify,
                          const std::string& path, int knn, Index max_iterations,
                          bool accept_partial) {
  solvers::SignedDistanceOptions o;
  o.time_factor = time_factor;
  o.level_set = solvers::signed_level_set_from(level_set);
  o.validate();
  if (curves.is_none() == points.is_none()) {
    throw InvalidInput("signed_distance needs curves or points (with point_normals), one of them");
  }
  solvers::SignedDistanceReport rep;
  Eigen::VectorXd d;
  py::dict info;
  if (!curves.is_none()) {
    if (path != "auto" && path != "manifold") {
      throw InvalidInput(
          "curves need the manifold path (an edge-manifold, orientable mesh), not "
          "path='" +
          path + "'");
    }
    const solvers::CurveSurface s =
        prepare_with_curves(surface_input(V, F, normals), curves.cast<py::list>(), refine, mollify,
                            false, max_iterations, accept_partial);
    {
      const py::gil_scoped_release release;
      d = solvers::signed_distance(s, o, &rep);
    }
    info = surface_info(s.surface);
    info["curves"] = curve_surface_info(s);
  } else {
    if (!refine.is_none()) throw InvalidInput("refine cannot be used with points");
    if (point_normals.is_none()) throw InvalidInput("points need point_normals (#K×3)");
    io::SurfaceInput in = surface_input(V, F, normals);
    const std::vector<solvers::InputDirection> pts =
        oriented_points(points, point_normals, static_cast<Index>(in.positions.rows()));
    const solvers::PreparedSurface s =
        prepare(std::move(in), prepare_options(mollify, path, true, knn), path);
    {
      const py::gil_scoped_release release;
      d = solvers::signed_distance(s, pts, o, &rep);
    }
    info = surface_info(s);
  }
  info["time_step"] = rep.time_step;
  info["unreached_vertices"] = rep.unreached_vertices;
  info["unresolved_vertices"] = rep.unresolved_vertices;
  return py::make_tuple(to_numpy(std::move(d)), info);
}

}  // namespace

void bind_signed(py::module_& m) {
  m.def("signed_distance", &signed_distance, py::arg("V"), py::arg("F"), py::arg("normals"),
        py::arg("curves"), py::arg("points"), py::arg("point_normals"), py::arg("refine"),
        py::arg("time_factor"), py::arg("level_set"), py::arg("mollify"), py::arg("path"),
        py::arg("k"), py::arg("max_iterations"), py::arg("accept_partial"));
}

}  // namespace ifem::python
