// read_mesh / write_ply: every format ifem reads, PLY with per-vertex properties out.
#include <pybind11/stl.h>

#include <string>
#include <utility>
#include <vector>

#include "arrays.h"
#include "bindings.h"
#include "intrinsic/core/errors.h"
#include "intrinsic/core/geometry.h"
#include "intrinsic/io/mesh_io.h"
#include "solvers/recipes/surface_summary.h"

namespace ifem::python {

namespace {

// (V, F, info): F is 0×3 for a point cloud; info holds what the reader repaired or found.
py::tuple read_mesh(const std::string& path, const py::handle& progress) {
  const ProgressCallback on_progress = progress_callback(progress);
  io::SurfaceInput in;
  {
    const py::gil_scoped_release release;
    in = io::read_surface(path, on_progress);
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

// `ifem info` of a point cloud: what its local triangulations and cover came to.
py::dict cloud_info(const solvers::PreparedSurface& s) {
  const pointcloud::Report& c = s.cloud;
  py::dict d;
  d["points"] = c.points;
  d["k"] = c.k;
  d["local_triangles"] = c.local_triangles;
  d["isolated_points"] = c.isolated_points;
  d["starless_points"] = c.starless_points;
  d["coincident_points"] = c.coincident_points;
  d["normals_from_input"] = c.normals_from_input;
  d["cover_faces"] = s.tri.n_faces();
  d["cover_edges"] = s.tri.n_edges();
  d["area"] = intrinsic::total_area(s.tri);
  d["mollify_delta"] = c.mollify.delta;
  d["flips_to_idt"] = c.flips.flips;
  return d;
}

// `ifem info --json` of a mesh: solvers::summarize_mesh's figures.
py::dict summary_info(const solvers::MeshSummary& m) {
  py::dict d;
  d["vertices"] = m.vertices;
  d["edges"] = m.edges;
  d["faces"] = m.faces;
  d["polygons"] = m.polygons;
  d["unreferenced_vertices"] = m.unreferenced_vertices;
  d["boundary_edges"] = m.boundary_edges;
  d["boundary_loops"] = m.boundary_loops;
  d["components"] = m.components;
  d["euler_characteristic"] = m.euler_characteristic;
  d["genus"] = m.genus ? py::object(py::int_(*m.genus)) : py::object(py::none());
  d["nonmanifold_edges"] = m.nonmanifold_edges;
  d["nonmanifold_vertices"] = m.nonmanifold_vertices;
  d["dropped_degenerate_faces"] = m.dropped_degenerate_faces;
  d["duplicate_faces"] = m.duplicate_faces;
  d["reoriented_faces"] = m.reoriented_faces;
  d["min_angle_deg"] = m.min_angle_deg;
  d["max_angle_deg"] = m.max_angle_deg;
  d["non_delaunay_share"] = m.non_delaunay_share;
  d["flips_to_idt"] = m.flips_to_idt;
  d["mollify_delta"] = m.mollify_delta;
  return d;
}

py::dict mesh_info(const py::handle& V, const py::handle& F, int k, double mollify,
                   const std::string& path, const py::handle& normals) {
  io::SurfaceInput in = surface_input(V, F, normals);
  const std::string p = in.triangles.empty() ? "pointcloud" : path;
  const solvers::PreparedSurface s =
      prepare(std::move(in), prepare_options(mollify, p, true, k), p);
  py::dict d;
  if (s.path == intrinsic::SurfacePath::kPointCloud) {
    d = cloud_info(s);
  } else {
    solvers::MeshSummary m;
    {
      const py::gil_scoped_release release;
      m = solvers::summarize_mesh(s);
    }
    d = summary_info(m);
  }
  d["path"] = intrinsic::to_string(s.path);
  d["path_reason"] = s.reason_detail;
  return d;
}

}  // namespace

void bind_mesh(py::module_& m) {
  m.def("mesh_info", &mesh_info, py::arg("V"), py::arg("F"), py::arg("knn"), py::arg("mollify"),
        py::arg("path"), py::arg("normals") = py::none());
  m.def("read_mesh", &read_mesh, py::arg("path"), py::arg("progress") = py::none());
  m.def("write_ply", &write_ply, py::arg("path"), py::arg("V"), py::arg("F"), py::arg("properties"),
        py::arg("binary"));
}

}  // namespace ifem::python
