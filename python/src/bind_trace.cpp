// Straight geodesics (the exponential map): the Python arguments of the trace recipe
// (solvers/recipes/trace_geodesic.h, the one `ifem trace` runs) and its rays as dicts; the
// Python layer (python/ifem/_trace.py) checks the start's shape and makes the result objects.
#include <pybind11/stl.h>

#include <string>
#include <vector>

#include "arrays.h"
#include "bindings.h"
#include "intrinsic/core/errors.h"
#include "solvers/recipes/trace_geodesic.h"

namespace ifem::python {

namespace {

// start: (vertex, face, b0, b1, b2) with vertex ≥ 0 for a vertex start, else the face point.
recipes::GivenPoint start_from(const std::vector<double>& start) {
  recipes::GivenPoint p;
  if (start.at(0) >= 0.0) {
    p.vertex = static_cast<Index>(start[0]);
    p.token = "start = " + std::to_string(p.vertex);
  } else {
    p.face = static_cast<Index>(start.at(1));
    p.bary = {start.at(2), start.at(3), start.at(4)};
    p.token = "start = (face " + std::to_string(p.face) + ")";
  }
  return p;
}

py::dict ray_dict(const recipes::GeodesicRay& r) {
  Positions poly(static_cast<Eigen::Index>(r.polyline.size()), 3);
  for (std::size_t i = 0; i < r.polyline.size(); ++i) {
    poly.row(static_cast<Eigen::Index>(i)) = r.polyline[i].transpose();
  }
  py::dict d;
  d["polyline"] = to_numpy(std::move(poly));
  d["end"] = py::make_tuple(r.end.face, r.end.bary[0], r.end.bary[1], r.end.bary[2]);
  d["end_vertex"] = r.end.vertex == kInvalidIndex ? py::object(py::none()) : py::int_(r.end.vertex);
  d["end_position"] = py::make_tuple(r.end.position[0], r.end.position[1], r.end.position[2]);
  d["end_direction"] = py::make_tuple(r.end_direction[0], r.end_direction[1], r.end_direction[2]);
  d["start_direction"] =
      py::make_tuple(r.start_direction[0], r.start_direction[1], r.start_direction[2]);
  d["length"] = r.length;
  d["hit_boundary"] = r.hit_boundary;
  d["slides"] = r.slides;
  return d;
}

// One ray per direction (`directions`: k×3 values, row after row), all from `start`.
py::list trace_rays(const py::handle& V, const py::handle& F, const std::vector<double>& start,
                    const std::vector<double>& directions, double length, bool slide) {
  const io::SurfaceInput in = surface_input(V, F);
  const recipes::GivenPoint p = start_from(start);
  recipes::TraceGeodesicOptions o;
  o.slide_on_boundary = slide;
  std::vector<recipes::GeodesicRay> rays;
  {
    const py::gil_scoped_release release;
    const recipes::GeodesicTracer tracer(in);
    const std::size_t k = directions.size() / 3;
    for (std::size_t i = 0; i < k; ++i) {
      const Eigen::Vector3d d(directions[3 * i], directions[3 * i + 1], directions[3 * i + 2]);
      try {
        rays.push_back(tracer.trace(p, d, length, o));
      } catch (const InvalidInput& e) {
        if (k == 1) throw;
        throw InvalidInput("direction[" + std::to_string(i) + "]: " + e.what());
      }
    }
  }
  py::list out;
  for (const recipes::GeodesicRay& r : rays) out.append(ray_dict(r));
  return out;
}

}  // namespace

void bind_trace(py::module_& m) {
  m.def("trace_rays", &trace_rays, py::arg("V"), py::arg("F"), py::arg("start"),
        py::arg("directions"), py::arg("length"), py::arg("slide"));
}

}  // namespace ifem::python
