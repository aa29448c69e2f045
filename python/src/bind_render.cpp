// render: a headless picture of a mesh, a per-vertex field and curves (solvers/recipes/render.h)
// as an H×W×3 uint8 array, written as PNG when a path is given.
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <string>
#include <utility>
#include <vector>

#include "arrays.h"
#include "bindings.h"
#include "intrinsic/core/errors.h"
#include "solvers/recipes/recipes.h"
#include "solvers/recipes/view_scene.h"

namespace ifem::python {

namespace {

/// A #V field that may hold non-finite values (drawn grey), unlike values_from().
Eigen::VectorXd field_from(const py::handle& field, Eigen::Index n) {
  const auto a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(field);
  if (!a || a.ndim() != 1 || a.size() != n) {
    throw InvalidInput("field must be a 1-D array of " + std::to_string(n) +
                       " numbers (one per vertex)");
  }
  return Eigen::Map<const Eigen::VectorXd>(a.data(), a.size());
}

std::vector<std::vector<Eigen::Vector3d>> curves_from(const py::handle& curves) {
  std::vector<std::vector<Eigen::Vector3d>> out;
  if (curves.is_none()) return out;
  for (const py::handle& c : curves) {
    const Positions p = positions_from(c, "curves[i]");
    std::vector<Eigen::Vector3d> line(p.rows());
    for (Eigen::Index i = 0; i < p.rows(); ++i) line[i] = p.row(i).transpose();
    out.push_back(std::move(line));
  }
  return out;
}

// (image H×W×3 uint8, lo, hi): lo / hi the colour range used (NaN without a field)
py::tuple render(const py::handle& V, const py::handle& F, const py::handle& field,
                 const py::handle& curves, std::pair<int, int> size, double azimuth,
                 double elevation, const std::string& colormap, std::pair<double, double> range,
                 int isolines, bool wireframe, int supersample, double fill, double curve_width,
                 bool legend, const py::handle& refined, const std::string& output) {
  solvers::RenderScene scene;
  scene.positions = positions_from(V, "V");
  const Index n = static_cast<Index>(scene.positions.rows());
  if (!F.is_none()) scene.triangles = triangles_from(F, n, "F");
  if (!field.is_none()) scene.field = field_from(field, n);
  scene.curves = curves_from(curves);
  solvers::RenderOptions o;
  std::tie(o.width, o.height) = size;
  o.azimuth_deg = azimuth;
  o.elevation_deg = elevation;
  o.colormap = solvers::colormap_from_name(colormap);
  std::tie(o.range_lo, o.range_hi) = range;
  o.isolines = isolines;
  o.wireframe = wireframe;
  o.supersample = supersample;
  o.fill = fill;
  o.curve_width = curve_width;
  o.legend = legend;
  solvers::Rendering r;
  {
    const py::gil_scoped_release release;
    if (!refined.is_none()) {
      // traced as `ifem view` traces them (checks that the triangulation is of this mesh)
      recipes::Scene traced;
      traced.positions = scene.positions;
      traced.faces = scene.triangles;
      recipes::add_intrinsic_edges(traced, refined.cast<const Refined&>().st());
      scene.intrinsic_edges = std::move(traced.intrinsic_edges);
    }
    r = recipes::render(scene, o);
    if (!output.empty()) solvers::write_png(output, r.image);
  }
  py::array_t<std::uint8_t> image({r.image.height, r.image.width, 3});
  std::copy(r.image.rgb.begin(), r.image.rgb.end(), image.mutable_data());
  return py::make_tuple(image, r.range_lo, r.range_hi);
}

}  // namespace

void bind_render(py::module_& m) {
  m.def("render", &render, py::arg("V"), py::arg("F"), py::arg("field"), py::arg("curves"),
        py::arg("size"), py::arg("azimuth"), py::arg("elevation"), py::arg("colormap"),
        py::arg("range"), py::arg("isolines"), py::arg("wireframe"), py::arg("supersample"),
        py::arg("fill"), py::arg("curve_width"), py::arg("legend"), py::arg("refined"),
        py::arg("output"));
  m.def(
      "named_view",
      [](const std::string& name) {
        const auto v = solvers::named_view(name);
        return std::make_pair(v[0], v[1]);
      },
      py::arg("name"));
  m.def(
      "read_polylines",
      [](const std::string& path) {
        std::vector<std::vector<Eigen::Vector3d>> lines;
        {
          const py::gil_scoped_release release;
          lines = solvers::read_polylines(path);
        }
        py::list out;
        for (const auto& line : lines) {
          Positions p(static_cast<Eigen::Index>(line.size()), 3);
          for (std::size_t i = 0; i < line.size(); ++i) p.row(i) = line[i].transpose();
          out.append(to_numpy(std::move(p)));
        }
        return out;
      },
      py::arg("path"));
}

}  // namespace ifem::python
