// Exact geodesic distance (solvers::exact_distance, intrinsic::exact_distance) for Python:
// ifem.exact_distance in python/ifem/_exact.py wraps it.
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <string>
#include <vector>

#include "arrays.h"
#include "bindings.h"
#include "intrinsic/core/errors.h"
#include "solvers/recipes/exact_distance.h"

namespace ifem::python {
namespace {

// The paths back from `from` as a list of #P×3 arrays (solvers::exact_paths_3d).
py::list paths_in_3d(const solvers::PreparedSurface& s, const intrinsic::ExactDistance& d,
                     const std::vector<Index>& from) {
  py::list out;
  for (const std::vector<Eigen::Vector3d>& line : solvers::exact_paths_3d(s, d, from)) {
    Positions p(static_cast<Eigen::Index>(line.size()), 3);
    for (std::size_t i = 0; i < line.size(); ++i) {
      p.row(static_cast<Eigen::Index>(i)) = line[i].transpose();
    }
    out.append(to_numpy(std::move(p)));
  }
  return out;
}

// (distances, windows, paths or None). refine: None or (min_angle, resolution). paths_from: None
// or vertex ids; with it the surface is not flipped (its faces stay the input's, so the paths'
// points have positions) and refine must be None.
py::tuple exact_distance(const py::handle& V, const py::handle& F, const py::handle& sources,
                         double mollify, const std::string& path, const py::handle& refine,
                         double memory_budget_gb, const py::handle& paths_from) {
  if (!(mollify >= 0.0 && mollify <= 1.0)) {
    throw InvalidInput("mollify must be in [0, 1] (relative to the mean edge length), got " +
                       std::to_string(mollify));
  }
  if (!(memory_budget_gb >= 0.0)) {
    throw InvalidInput("memory_budget must be None or > 0 gigabytes, got " +
                       std::to_string(memory_budget_gb));
  }
  const bool want_paths = !paths_from.is_none();
  if (want_paths && !refine.is_none()) {
    throw InvalidInput("paths_from needs refine=False (paths are given on the input's faces)");
  }
  io::SurfaceInput in = surface_input(V, F);
  if (!in.has_faces()) throw InvalidInput("exact_distance needs faces (F), not a point cloud");
  const Index n = static_cast<Index>(in.positions.rows());
  const std::vector<Index> ids = indices_from(sources, n, "sources");
  const std::vector<Index> from =
      want_paths ? indices_from(paths_from, n, "paths_from") : std::vector<Index>{};
  // the input's own faces: flips keep the distance and cost windows (docs/decisions.md D-321)
  solvers::PrepareOptions o = prepare_options(mollify, path, false, 30);
  if (!refine.is_none()) {
    const py::tuple r = py::reinterpret_borrow<py::tuple>(refine);
    solvers::SurfaceRefineOptions ro;
    ro.min_angle_degrees = r[0].cast<double>();
    ro.resolution = r[1].cast<double>();
    ro.validate();
    o.refine = ro;
  }
  const solvers::PreparedSurface s = prepare(std::move(in), o, path);
  intrinsic::ExactDistanceOptions eo;
  eo.max_memory_bytes = memory_budget_gb * 1e9;
  eo.keep_paths = want_paths;
  intrinsic::ExactDistance full;
  Eigen::VectorXd d;
  {
    const py::gil_scoped_release release;
    d = solvers::exact_distance(s, ids, eo, &full);
  }
  const std::size_t windows = full.windows;
  py::object paths = py::none();
  if (want_paths) paths = paths_in_3d(s, full, from);
  return py::make_tuple(to_numpy(std::move(d)), windows, paths, surface_info(s));
}

}  // namespace

void bind_exact(py::module_& m) {
  m.def("exact_distance", &exact_distance, py::arg("V"), py::arg("F"), py::arg("sources"),
        py::arg("mollify"), py::arg("path"), py::arg("refine"), py::arg("memory_budget_gb"),
        py::arg("paths_from"));
}

}  // namespace ifem::python
