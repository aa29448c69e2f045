// simplify: intrinsic simplification (intrinsic/simplify/simplify.h) of an input on whichever
// path it takes, with the prolongation P and, on request, the tangent-vector one
// (fem/prolongation.h).
#include <algorithm>
#include <complex>
#include <memory>
#include <string>
#include <utility>

#include "arrays.h"
#include "bindings.h"
#include "fem/prolongation.h"
#include "intrinsic/core/errors.h"
#include "intrinsic/simplify/simplify.h"

namespace ifem::python {

namespace {

// Complex CSC parts (data complex128, indices, indptr, shape), copied.
py::tuple complex_csc_parts(fem::ComplexSparseMatrix& A) {
  A.makeCompressed();
  const auto nnz = static_cast<py::ssize_t>(A.nonZeros());
  py::array_t<std::complex<double>> data(nnz);
  py::array_t<int> indices(nnz), indptr(A.cols() + 1);
  std::copy(A.valuePtr(), A.valuePtr() + nnz, data.mutable_data());
  std::copy(A.innerIndexPtr(), A.innerIndexPtr() + nnz, indices.mutable_data());
  std::copy(A.outerIndexPtr(), A.outerIndexPtr() + A.cols() + 1, indptr.mutable_data());
  return py::make_tuple(data, indices, indptr, py::make_tuple(A.rows(), A.cols()));
}

// (coarse faces #Fc×3, kept input ids #Vc, P parts, side lengths #Fc×3, info, tangent P parts
// or None)
py::tuple simplify(const py::handle& V, const py::handle& F, Index vertices, double ratio,
                   double mollify, const std::string& path, const py::handle& progress,
                   bool tangent) {
  io::SurfaceInput in = surface_input(V, F);
  solvers::PrepareOptions po = prepare_options(mollify, path, true, 30);
  po.self_edges = false;  // a point cloud's cover without self-edges (D-345), as `ifem simplify`
  auto s = std::make_unique<solvers::PreparedSurface>(prepare(std::move(in), po, path));
  py::dict info = surface_info(*s);
  intrinsic::SimplifyOptions o;
  o.target_vertices = vertices;
  o.ratio = ratio;
  o.on_progress = progress_callback(progress);
  intrinsic::Simplification r;
  fem::SparseMatrix P;
  fem::ComplexSparseMatrix Pt;
  std::vector<Triangle> faces;
  Eigen::MatrixXd lengths;
  {
    const py::gil_scoped_release release;
    r = intrinsic::simplify(s->tri, o);
    fem::prolongation(r).swap(P);
    if (tangent) Pt = fem::tangent_prolongation(s->tri, r);
    const auto& c = r.coarse;
    faces.resize(c.n_faces());
    lengths.resize(c.n_faces(), 3);
    for (Index f = 0; f < c.n_faces(); ++f) {
      faces[f] = {c.tail(3 * f), c.tail(3 * f + 1), c.tail(3 * f + 2)};
      for (int k = 0; k < 3; ++k) lengths(f, k) = c.halfedge_length(3 * f + k);
    }
  }
  const auto& rep = r.report;
  info["vertices_before"] = rep.vertices_before;
  info["vertices_after"] = rep.vertices_after;
  info["removals"] = rep.removals;
  info["boundary_removals"] = rep.boundary_removals;
  info["flattened"] = rep.flattened;
  info["pillows"] = rep.pillows;
  info["simplify_flips"] = rep.flips;
  info["stuck"] = rep.stuck;
  info["area_change_before_rescale"] = rep.area_change_before_rescale;
  info["multiplicity"] = r.coarse.multiplicity();
  py::object tangent_parts = py::none();
  if (tangent) tangent_parts = complex_csc_parts(Pt);
  return py::make_tuple(to_numpy(std::move(faces)), to_numpy(std::move(r.coarse_to_fine)),
                        to_csc_parts(std::move(P)), to_numpy(std::move(lengths)), info,
                        tangent_parts);
}

}  // namespace

void bind_simplify(py::module_& m) {
  m.def("simplify", &simplify, py::arg("V"), py::arg("F"), py::arg("vertices"), py::arg("ratio"),
        py::arg("mollify"), py::arg("path"), py::arg("progress"), py::arg("tangent"));
}

}  // namespace ifem::python
