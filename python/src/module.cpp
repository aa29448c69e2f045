// The extension module ifem._ifem: exception translation and the bindings of each area. The
// Python package (python/ifem/__init__.py) wraps these functions with keyword arguments,
// docstrings and scipy.sparse results.
#include <pybind11/pybind11.h>

#include <exception>
#include <string>

#include "bindings.h"
#include "intrinsic/core/errors.h"

namespace ifem::python {

namespace {

// Raises the Python class `name` of ifem._errors with the C++ message.
void raise(const char* name, const std::exception& e) {
  const py::object cls = py::module_::import("ifem._errors").attr(name);
  PyErr_SetString(cls.ptr(), e.what());
}

void translate(std::exception_ptr p) {
  try {
    if (p) std::rethrow_exception(p);
  } catch (const NonOrientableInput& e) {
    raise("NonOrientableInput", e);
  } catch (const NonManifoldInput& e) {
    raise("NonManifoldInput", e);
  } catch (const InvalidInput& e) {
    raise("InvalidInput", e);
  } catch (const IoError& e) {
    raise("IoError", e);
  } catch (const SolverError& e) {
    raise("SolverError", e);
  } catch (const TraceError& e) {
    raise("TraceError", e);
  } catch (const Error& e) {
    raise("Error", e);
  }
}

}  // namespace

ProgressCallback progress_callback(const py::handle& progress) {
  if (progress.is_none()) return {};
  if (!PyCallable_Check(progress.ptr())) {
    throw InvalidInput("progress must be None or a callable progress(fraction, stage), got " +
                       py::repr(progress).cast<std::string>());
  }
  PyObject* callable = progress.ptr();
  return [callable](double fraction, std::string_view stage) {
    const py::gil_scoped_acquire gil;
    const py::handle fn(callable);
    fn(fraction, py::str(stage.data(), stage.size()));
  };
}

solvers::PrepareOptions prepare_options(double mollify, const std::string& path,
                                        bool intrinsic_delaunay, int k) {
  if (path != "auto" && path != "manifold" && path != "tufted" && path != "pointcloud") {
    throw InvalidInput("path must be 'auto', 'manifold', 'tufted' or 'pointcloud', got '" + path +
                       "'");
  }
  solvers::PrepareOptions o;
  o.mollify_relative_epsilon = mollify;
  o.intrinsic_delaunay = intrinsic_delaunay;
  o.force_tufted = path == "tufted";
  o.force_pointcloud = path == "pointcloud";
  o.knn = k;
  o.validate();
  return o;
}

solvers::PreparedSurface prepare(io::SurfaceInput input, const solvers::PrepareOptions& options,
                                 const std::string& path) {
  solvers::PreparedSurface s;
  {
    const py::gil_scoped_release release;
    s = solvers::prepare_surface(std::move(input), options);
  }
  if (path == "manifold" && s.path != intrinsic::SurfacePath::kManifold) {
    throw NonManifoldInput("path='manifold' was asked for, but the mesh needs the " +
                           std::string(intrinsic::to_string(s.path)) + " path: " + s.reason_detail);
  }
  return s;
}

py::dict surface_info(const solvers::PreparedSurface& s) {
  py::dict d;
  d["path"] = intrinsic::to_string(s.path);
  d["reason"] = s.reason_detail;
  d["flips"] = s.flips.flips;
  d["mollify_delta"] = s.mollify.delta;
  d["dropped_faces"] = s.build.dropped_faces;
  d["reoriented_faces"] = s.build.reoriented_faces;
  d["unreferenced_vertices"] = s.build.unreferenced_vertices;
  d["input_vertices"] = s.n_input_vertices();
  d["vertices"] = s.tri.n_vertices();
  d["faces"] = s.tri.n_faces();
  d["refined"] = s.refined;
  d["inserted_vertices"] = s.tri.n_vertices() - s.n_input_vertices();
  d["signposts"] = s.signposts.has_value();
  // "integer" / "signposts": how inserted vertices keep their places; None without one
  d["correspondence"] = s.signposts ? py::object(py::str("signposts"))
                        : s.integer ? py::object(py::str("integer"))
                                    : py::object(py::none());
  d["mean_edge_length"] = s.input_mean_edge_length;
  d["target_edge_length"] = s.target_edge_length;
  return d;
}

}  // namespace ifem::python

PYBIND11_MODULE(_ifem, m) {
  namespace ip = ifem::python;
  namespace py = pybind11;
  m.doc() = "ifem's compiled core; use the package `ifem`, which wraps it.";
  py::register_exception_translator(ip::translate);
  ip::bind_mesh(m);
  ip::bind_operators(m);
  ip::bind_solvers(m);
  ip::bind_refine(m);
  ip::bind_geodesic(m);
  ip::bind_curves(m);
  ip::bind_fields(m);
  ip::bind_view(m);
  ip::bind_render(m);
  ip::bind_isolines(m);
  ip::bind_signed(m);
  ip::bind_trace(m);
  ip::bind_exact(m);
  ip::bind_simplify(m);
}
