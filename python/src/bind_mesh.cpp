// read_mesh / write_ply: every format ifem reads, PLY with per-vertex properties out.
#include <pybind11/stl.h>

#include <string>
#include <utility>
#include <vector>

#include "arrays.h"
#include "bindings.h"
#include "intrinsic/core/errors.h"
#include "intrinsic/io/mesh_io.h"

namespace ifem::python {

namespace {

// (V, F, info): F is 0×3 for a point cloud; info holds what the reader repaired or found.
py::tuple read_mesh(const std::string& path) {
  io::SurfaceInput in;
  {
    const py::gil_scoped_release release;
    in = io::read_surface(path);
  }
  py::dict info;
  info["format"] = in.format;
  info["polygons"] = in.n_polygons;
  info["non_triangles"] = in.n_non_triangles;
  info["welded_vertices"] = in.welded_vertices;
  if (in.normals.rows() > 0) info["normals"] = to_numpy(Eigen::MatrixXd(in.normals));
  py::dict properties;
  for (io::VertexProperty& p : in.vertex_properties) {
    properties[py::str(p.name)] = to_numpy(std::move(p.values));
  }
  info["vertex_properties"] = properties;
  return py::make_tuple(to_numpy(std::move(in.positions)), to_numpy(std::move(in.triangles)), info);
}

void write_ply(const std::string& path, const py::handle& V, const py::handle& F,
               const py::dict& properties, bool binary) {
  const Positions positions = positions_from(V, "V");
  const Index n = static_cast<Index>(positions.rows());
  const std::vector<Triangle> faces =
      F.is_none() ? std::vector<Triangle>{} : triangles_from(F, n, "F");
  std::vector<io::VertexProperty> props;
  for (const auto& [key, value] : properties) {
    const std::string name = py::str(key).cast<std::string>();
    const std::string what = "vertex property '" + name + "'";
    py::array a = py::array::ensure(value);
    if (!a || a.ndim() != 1) {
      throw InvalidInput(what + " must be a 1-D array with one value per vertex");
    }
    if (a.size() != n) {
      throw InvalidInput(what + " has " + std::to_string(a.size()) + " values for " +
                         std::to_string(n) + " vertices");
    }
    const char kind = a.dtype().kind();
    if (kind != 'f' && kind != 'i' && kind != 'u' && kind != 'b') {
      throw InvalidInput(what + " must hold numbers, got dtype " +
                         py::str(a.dtype()).cast<std::string>());
    }
    const auto d = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(a);
    props.push_back({name, Eigen::Map<const Eigen::VectorXd>(d.data(), d.size())});
  }
  const py::gil_scoped_release release;
  io::write_ply(path, positions, faces, props, binary);
}

}  // namespace

void bind_mesh(py::module_& m) {
  m.def("read_mesh", &read_mesh, py::arg("path"));
  m.def("write_ply", &write_ply, py::arg("path"), py::arg("V"), py::arg("F"), py::arg("properties"),
        py::arg("binary"));
}

}  // namespace ifem::python
