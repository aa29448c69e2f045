// laplacian / point_cloud_laplacian: L and M on the input's vertices, from the intrinsic
// triangulation of whichever path the input takes.
#include <pybind11/stl.h>

#include <memory>
#include <string>
#include <utility>

#include "arrays.h"
#include "bindings.h"
#include "fem/operators.h"
#include "intrinsic/core/errors.h"
#include "intrinsic/core/timer.h"

namespace ifem::python {

namespace {

// (L parts, M diagonal, info) of an input prepared on a path. info["seconds"] is the library's
// own time: preparing, assembling, and freeing the surface again, as a C++ caller would; the
// rest of the Python call (checking and converting arrays, wrapping results) is the binding's
// overhead (BENCHMARKS.md, "Python package").
py::tuple prepare_and_assemble(io::SurfaceInput in, const solvers::PrepareOptions& o,
                               const std::string& path) {
  const Stopwatch watch;
  fem::SparseMatrix L;
  Eigen::VectorXd m;
  auto s = std::make_unique<solvers::PreparedSurface>(prepare(std::move(in), o, path));
  const py::dict info = surface_info(*s);
  {
    const py::gil_scoped_release release;
    fem::cotan_laplacian(s->tri).swap(L);  // Eigen 3.4's SparseMatrix has no move assignment
    m = fem::lumped_mass(s->tri);
    s.reset();  // freeing the surface is part of the library's time
  }
  info["seconds"] = watch.seconds();
  return py::make_tuple(to_csc_parts(std::move(L)), to_numpy(std::move(m)), info);
}

py::tuple laplacian(const py::handle& V, const py::handle& F, double mollify,
                    const std::string& path, bool intrinsic_delaunay) {
  const Stopwatch watch;
  io::SurfaceInput in = surface_input(V, F);
  const double seconds_convert = watch.seconds();
  if (in.triangles.empty()) {
    throw InvalidInput("F has no faces: for a point cloud use point_cloud_laplacian(P, k)");
  }
  if (path == "pointcloud") {
    throw InvalidInput("path='pointcloud': use point_cloud_laplacian(P, k) for point clouds");
  }
  const solvers::PrepareOptions o = prepare_options(mollify, path, intrinsic_delaunay, 30);
  py::tuple out = prepare_and_assemble(std::move(in), o, path);
  out[2]["seconds_convert"] = seconds_convert;
  return out;
}

py::tuple point_cloud_laplacian(const py::handle& P, int k, const py::handle& normals,
                                double mollify) {
  io::SurfaceInput in = surface_input(P, py::none(), normals);
  if (k < 2 || k >= in.positions.rows()) {
    throw InvalidInput("k must be in [2, number of points) = [2, " +
                       std::to_string(in.positions.rows()) + "), got " + std::to_string(k));
  }
  const solvers::PrepareOptions o = prepare_options(mollify, "pointcloud", true, k);
  return prepare_and_assemble(std::move(in), o, "pointcloud");
}

}  // namespace

void bind_operators(py::module_& m) {
  m.def("laplacian", &laplacian, py::arg("V"), py::arg("F"), py::arg("mollify"), py::arg("path"),
        py::arg("intrinsic_delaunay"));
  m.def("point_cloud_laplacian", &point_cloud_laplacian, py::arg("P"), py::arg("k"),
        py::arg("normals"), py::arg("mollify"));
}

}  // namespace ifem::python
