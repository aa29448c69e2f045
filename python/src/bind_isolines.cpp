// Isolines of a per-vertex field (solvers/recipes/isolines.h, what `ifem isolines` runs) as flat
// numpy arrays; the Python layer (python/ifem/_isolines.py) wraps them in ifem.Isolines.
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "arrays.h"
#include "bindings.h"
#include "intrinsic/core/errors.h"
#include "solvers/recipes/isolines.h"

namespace ifem::python {

namespace {

using Doubles = py::array_t<double, py::array::c_style | py::array::forcecast>;

// A 1-D real array (non-finite values kept: the recipe decides what they mean).
Eigen::VectorXd reals_from(const py::handle& h, const char* name) {
  if (h.is_none())
    throw InvalidInput(std::string(name) + " must be a 1-D array of numbers, got None");
  const Doubles a = Doubles::ensure(h);
  if (!a) {
    PyErr_Clear();
    throw InvalidInput(std::string(name) + " must be a 1-D array of numbers, got " +
                       py::repr(h).cast<std::string>());
  }
  if (a.ndim() > 1) {
    throw InvalidInput(std::string(name) + " must be 1-D, got " + std::to_string(a.ndim()) +
                       " dimensions");
  }
  Eigen::VectorXd v(a.size());
  for (py::ssize_t i = 0; i < a.size(); ++i) v[i] = a.data()[i];
  return v;
}

py::dict isolines(const py::handle& V, const py::handle& F, const py::handle& f,
                  const py::handle& values, std::optional<Index> count) {
  const Positions x = positions_from(V, "V");
  const std::vector<Triangle> t = triangles_from(F, Index(x.rows()), "F");
  if (t.empty()) throw InvalidInput("F: isolines need a mesh with faces, F has no rows");
  const Eigen::VectorXd field = reals_from(f, "f");
  if (field.size() != x.rows()) {
    throw InvalidInput("f has " + std::to_string(field.size()) + " values, V " +
                       std::to_string(x.rows()) + " rows (one value per vertex)");
  }
  if (values.is_none() == !count.has_value()) {
    throw InvalidInput("give exactly one of values (the levels) and count (evenly spaced levels)");
  }
  std::vector<double> levels;
  if (count) {
    levels = recipes::isoline_levels(field, *count);
  } else {
    const Eigen::VectorXd v = reals_from(values, "values");
    levels.assign(v.data(), v.data() + v.size());
  }
  std::vector<recipes::Isoline> lines;
  {
    const py::gil_scoped_release release;
    lines = recipes::isolines(x, t, field, levels);
  }
  std::size_t n = 0;
  for (const auto& l : lines) n += l.points.size();
  Positions points = Positions::Zero(Eigen::Index(n), 3);
  Eigen::MatrixXd bary = Eigen::MatrixXd::Zero(Eigen::Index(n), 3);
  Eigen::VectorXd param = Eigen::VectorXd::Zero(Eigen::Index(n));
  Eigen::VectorXd line_value = Eigen::VectorXd::Zero(Eigen::Index(lines.size()));
  std::vector<Index> faces, below, above, offsets{0}, level;
  std::vector<bool> closed;
  Eigen::Index r = 0;
  for (const auto& l : lines) {
    for (const auto& p : l.points) {
      points.row(r) = p.position.transpose();
      bary.row(r) = p.bary.transpose();
      param[r++] = p.t;
      faces.push_back(p.face);
      below.push_back(p.below);
      above.push_back(p.above);
    }
    offsets.push_back(Index(r));
    line_value[Eigen::Index(level.size())] = l.value;
    level.push_back(l.level);
    closed.push_back(l.closed);
  }
  py::dict d;
  d["points"] = to_numpy(std::move(points));
  d["faces"] = to_numpy(std::move(faces));
  d["bary"] = to_numpy(std::move(bary));
  d["below"] = to_numpy(std::move(below));
  d["above"] = to_numpy(std::move(above));
  d["t"] = to_numpy(std::move(param));
  d["offsets"] = to_numpy(std::move(offsets));
  d["level"] = to_numpy(std::move(level));
  d["value"] = to_numpy(std::move(line_value));
  d["closed"] = py::array(py::cast(closed)).attr("astype")("bool");
  d["levels"] = py::cast(levels);
  return d;
}

}  // namespace

void bind_isolines(py::module_& m) {
  m.def("isolines", &isolines, py::arg("V"), py::arg("F"), py::arg("f"), py::arg("values"),
        py::arg("count"));
}

}  // namespace ifem::python
