// `ifem view`'s page from arrays (solvers/recipes/view_scene.h): the scene of V, F, named
// per-vertex values, a tangent field's vectors and singularities, polylines and a refined
// triangulation's traced edges, written as one self-contained HTML file.
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <string>
#include <utility>
#include <vector>

#include "arrays.h"
#include "bindings.h"
#include "intrinsic/core/errors.h"
#include "solvers/recipes/view_scene.h"

namespace ifem::python {
namespace {

using Floats = py::array_t<double, py::array::c_style | py::array::forcecast>;

// A 1-D array of #V values (non-finite allowed: drawn grey).
Eigen::VectorXd vertex_values(const py::handle& a, Eigen::Index n, const std::string& name) {
  const Floats x = Floats::ensure(a);
  if (!x || x.ndim() != 1 || x.shape(0) != n) {
    throw InvalidInput("view: " + name + " must be a 1-D array of " + std::to_string(n) +
                       " values (one per vertex)");
  }
  return Eigen::Map<const Eigen::VectorXd>(x.data(), n);
}

// A k×3 array of points (k ≥ 0).
std::vector<Eigen::Vector3d> points(const py::handle& a, const std::string& name) {
  const Floats x = Floats::ensure(a);
  if (!x || x.ndim() != 2 || x.shape(1) != 3) {
    throw InvalidInput("view: " + name + " must be k×3 arrays of points");
  }
  std::vector<Eigen::Vector3d> out;
  for (py::ssize_t i = 0; i < x.shape(0); ++i) out.emplace_back(x.at(i, 0), x.at(i, 1), x.at(i, 2));
  return out;
}

// Writes the page; returns what it holds (counts) for the Python side.
py::dict view(const py::handle& V, const py::handle& F, const std::string& path,
              const std::vector<std::pair<std::string, py::object>>& fields,
              const std::string& units, const py::handle& vectors, int symmetry,
              const py::handle& singularity,
              const std::vector<std::pair<std::string, py::list>>& curves,
              const py::handle& refined, const std::string& title, const std::string& three_dir) {
  const io::SurfaceInput input = surface_input(V, F);
  recipes::Scene scene = recipes::view_scene(input, title);
  const Eigen::Index n = input.positions.rows();
  std::vector<io::VertexProperty> field_props;
  if (!vectors.is_none()) {
    const std::vector<Eigen::Vector3d> v = points(vectors, "vectors");
    if (Eigen::Index(v.size()) != n) throw InvalidInput("view: vectors must be #V×3");
    Eigen::VectorXd fx(n), fy(n), fz(n);
    for (Eigen::Index i = 0; i < n; ++i) fx[i] = v[i].x(), fy[i] = v[i].y(), fz[i] = v[i].z();
    field_props = {{"fx", fx}, {"fy", fy}, {"fz", fz}};
  }
  if (!singularity.is_none()) {
    field_props.push_back({"singularity", vertex_values(singularity, n, "singularity")});
  }
  recipes::add_properties(scene, field_props, "", symmetry);
  for (const auto& [name, values] : fields) {
    recipes::add_field(scene, {name, units, vertex_values(values, n, name)});
  }
  for (recipes::SceneField& f : scene.fields) f.units = units;
  for (const auto& [name, lines] : curves) {
    recipes::Polylines polylines;
    for (const py::handle& line : lines) polylines.push_back(points(line, "curves"));
    recipes::add_polylines(scene, name, polylines);
  }
  const std::string three = recipes::find_three_js(three_dir);
  {
    const py::gil_scoped_release release;
    if (!refined.is_none())
      recipes::add_intrinsic_edges(scene, refined.cast<const Refined&>().st());
    recipes::write_view_page(path, scene, three);
  }
  py::dict info;
  info["fields"] = scene.fields.size();
  info["curves"] = scene.curves.size();
  info["glyphs"] = scene.glyph_segments.rows() / 2;
  info["singularities"] = scene.singularities.size();
  info["intrinsic_edges"] = scene.intrinsic_edges.size();
  return info;
}

py::list to_arrays(const recipes::Polylines& lines) {
  py::list out;
  for (const auto& line : lines) {
    Positions p(Eigen::Index(line.size()), 3);
    for (std::size_t i = 0; i < line.size(); ++i) p.row(Eigen::Index(i)) = line[i];
    out.append(to_numpy(std::move(p)));
  }
  return out;
}

// One polyline per intrinsic edge, traced over the input (k×3 arrays).
py::list traced_edges(const Refined& h) {
  recipes::Polylines lines;
  {
    const py::gil_scoped_release release;
    lines = h.st().traced_edges_3d();
  }
  return to_arrays(lines);
}

}  // namespace

void bind_view(py::module_& m) {
  m.def("view", &view, py::arg("V"), py::arg("F"), py::arg("path"), py::arg("fields"),
        py::arg("units"), py::arg("vectors"), py::arg("symmetry"), py::arg("singularity"),
        py::arg("curves"), py::arg("refined"), py::arg("title"), py::arg("three_dir"));
  m.def("traced_edges", &traced_edges, py::arg("refined"));
}

}  // namespace ifem::python
