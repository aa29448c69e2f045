// Checked conversions between numpy arrays and ifem's types (arrays.h).
#include "arrays.h"

#include <cmath>
#include <memory>
#include <utility>

#include "intrinsic/core/errors.h"

namespace ifem::python {

namespace {

std::string shape_of(const py::array& a) {
  std::string s = "(";
  for (py::ssize_t d = 0; d < a.ndim(); ++d) {
    s += (d ? ", " : "") + std::to_string(a.shape(d));
  }
  return s + (a.ndim() == 1 ? ",)" : ")");
}

std::string dtype_of(const py::array& a) { return py::str(a.dtype()).cast<std::string>(); }

// Any array-like (lists included) as an ndarray, without converting its dtype.
py::array as_array(const py::handle& obj, const char* name) {
  if (obj.is_none()) throw InvalidInput(std::string(name) + " is None");
  try {
    return py::array::ensure(obj);
  } catch (const py::error_already_set&) {
  }
  throw InvalidInput(std::string(name) + " is not an array (got " +
                     py::str(py::type::of(obj)).cast<std::string>() + ")");
}

bool is_integer(const py::array& a) {
  const char k = a.dtype().kind();
  return k == 'i' || k == 'u';
}

bool is_real(const py::array& a) { return a.dtype().kind() == 'f' || is_integer(a); }

void require_n_by_3(const py::array& a, const char* name, const char* what) {
  if (a.ndim() != 2 || a.shape(1) != 3) {
    throw InvalidInput(std::string(name) + " must be an n×3 array of " + what + ", got shape " +
                       shape_of(a));
  }
}

// Integer entries as int64, C order (a copy only when the dtype or order differ).
py::array_t<std::int64_t, py::array::c_style | py::array::forcecast> as_int64(const py::array& a,
                                                                              const char* name) {
  if (!is_integer(a)) {
    throw InvalidInput(std::string(name) + " must hold integers, got dtype " + dtype_of(a));
  }
  return py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>::ensure(a);
}

// n rows of three ids from a C-order buffer, each checked against [0, n_vertices).
template <typename Id>
std::vector<Triangle> checked_triangles(const Id* x, std::size_t n, Index n_vertices,
                                        const char* name) {
  (void)checked_index(n, name);
  std::vector<Triangle> t(n);
  bool bad = false;
  for (std::size_t f = 0; f < n; ++f) {
    for (std::size_t k = 0; k < 3; ++k) {
      const Id v = x[3 * f + k];
      bad |= v < 0 || v >= static_cast<Id>(n_vertices);
      t[f][k] = static_cast<Index>(v);
    }
  }
  if (!bad) return t;
  for (std::size_t i = 0; i < 3 * n; ++i) {
    if (x[i] >= 0 && x[i] < static_cast<Id>(n_vertices)) continue;
    throw InvalidInput(std::string(name) + " row " + std::to_string(i / 3) + " has vertex id " +
                       std::to_string(x[i]) + ", out of range [0, " + std::to_string(n_vertices) +
                       ")");
  }
  return t;
}

template <typename Owned>
py::capsule owner(Owned* p) {
  return py::capsule(p, [](void* q) { delete static_cast<Owned*>(q); });
}

}  // namespace

Positions positions_from(const py::handle& array, const char* name) {
  const py::array a = as_array(array, name);
  require_n_by_3(a, name, "positions");
  if (!is_real(a)) {
    throw InvalidInput(std::string(name) + " must hold real numbers, got dtype " + dtype_of(a));
  }
  if (a.shape(0) == 0) throw InvalidInput(std::string(name) + " is empty (0 rows)");
  const auto d = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(a);
  const Index n = checked_index(static_cast<std::size_t>(d.shape(0)), name);
  Positions p(n, 3);
  std::copy(d.data(), d.data() + 3 * static_cast<std::size_t>(n), p.data());
  const bool finite = p.allFinite();
  for (Index i = 0; !finite && i < n; ++i) {  // the search only runs when one is bad
    if (!p.row(i).allFinite()) {
      throw InvalidInput(std::string(name) + " row " + std::to_string(i) + " is not finite (" +
                         std::to_string(p(i, 0)) + ", " + std::to_string(p(i, 1)) + ", " +
                         std::to_string(p(i, 2)) + ")");
    }
  }
  return p;
}

std::vector<Triangle> triangles_from(const py::handle& array, Index n_vertices, const char* name) {
  const py::array a = as_array(array, name);
  if (a.ndim() == 2 && a.shape(0) == 0) return {};
  require_n_by_3(a, name, "vertex ids");
  if (!is_integer(a)) {
    throw InvalidInput(std::string(name) + " must hold integers, got dtype " + dtype_of(a));
  }
  // ids that fit in 32 bits are read as int32 (numpy's and ifem's usual type: no conversion),
  // wider ones as int64; either way every id is range-checked.
  const py::ssize_t size = a.dtype().itemsize();
  if (size < 4 || (a.dtype().kind() == 'i' && size == 4)) {
    const auto ids =
        py::array_t<std::int32_t, py::array::c_style | py::array::forcecast>::ensure(a);
    return checked_triangles(ids.data(), static_cast<std::size_t>(ids.shape(0)), n_vertices, name);
  }
  const auto ids = as_int64(a, name);
  return checked_triangles(ids.data(), static_cast<std::size_t>(ids.shape(0)), n_vertices, name);
}

std::vector<Index> indices_from(const py::handle& array, Index n, const char* name,
                                bool allow_empty) {
  const py::array a = as_array(array, name);
  if (a.ndim() > 1) {
    throw InvalidInput(std::string(name) + " must be a 1-D list of vertex ids, got shape " +
                       shape_of(a));
  }
  if (a.size() == 0) {
    if (allow_empty) return {};
    throw InvalidInput(std::string(name) + " is empty");
  }
  const auto ids = as_int64(a, name);
  std::vector<Index> out(static_cast<std::size_t>(ids.size()));
  for (std::size_t i = 0; i < out.size(); ++i) {
    const std::int64_t v = ids.data()[i];
    if (v < 0 || v >= n) {
      throw InvalidInput(std::string(name) + "[" + std::to_string(i) + "] = " + std::to_string(v) +
                         " is out of range [0, " + std::to_string(n) + ")");
    }
    out[i] = static_cast<Index>(v);
  }
  return out;
}

Eigen::VectorXd values_from(const py::handle& array, Eigen::Index size, const char* name) {
  const py::array a = as_array(array, name);
  if (a.ndim() > 1 || !is_real(a)) {
    throw InvalidInput(std::string(name) + " must be a 1-D array of real numbers, got shape " +
                       shape_of(a) + " and dtype " + dtype_of(a));
  }
  if (size >= 0 && a.size() != size) {
    throw InvalidInput(std::string(name) + " must have " + std::to_string(size) + " values, got " +
                       std::to_string(a.size()));
  }
  const auto d = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(a);
  Eigen::VectorXd v = Eigen::Map<const Eigen::VectorXd>(d.data(), d.size());
  for (Eigen::Index i = 0; i < v.size(); ++i) {
    if (!std::isfinite(v[i])) {
      throw InvalidInput(std::string(name) + "[" + std::to_string(i) + "] is not finite (" +
                         std::to_string(v[i]) + ")");
    }
  }
  return v;
}

io::SurfaceInput surface_input(const py::handle& V, const py::handle& F,
                               const py::handle& normals) {
  io::SurfaceInput in;
  in.positions = positions_from(V, "V");
  const Index n = static_cast<Index>(in.positions.rows());
  if (!F.is_none()) in.triangles = triangles_from(F, n, "F");
  in.n_polygons = static_cast<Index>(in.triangles.size());
  in.triangle_polygon.resize(in.triangles.size());
  for (std::size_t t = 0; t < in.triangles.size(); ++t) in.triangle_polygon[t] = Index(t);
  if (!normals.is_none()) {
    const py::array a = as_array(normals, "normals");
    require_n_by_3(a, "normals", "normal vectors");
    if (a.shape(0) != n) {
      throw InvalidInput("normals must have one row per point (" + std::to_string(n) + "), got " +
                         std::to_string(a.shape(0)));
    }
    const auto d = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(a);
    in.normals.resize(n, 3);
    for (Index i = 0; i < n; ++i) {
      for (int k = 0; k < 3; ++k) in.normals(i, k) = d.data()[3 * i + k];
    }
  }
  in.format = "arrays";
  return in;
}

py::array to_numpy(Eigen::VectorXd&& v) {
  auto* p = new Eigen::VectorXd(std::move(v));
  return py::array_t<double>({p->size()}, {sizeof(double)}, p->data(), owner(p));
}

py::array to_numpy(Eigen::MatrixXd&& m) {
  auto* p = new Eigen::MatrixXd(std::move(m));
  const auto r = static_cast<py::ssize_t>(p->rows()), c = static_cast<py::ssize_t>(p->cols());
  return py::array_t<double>({r, c}, {py::ssize_t(sizeof(double)), py::ssize_t(sizeof(double)) * r},
                             p->data(), owner(p));
}

py::array to_numpy(Positions&& m) {
  auto* p = new Positions(std::move(m));
  const auto r = static_cast<py::ssize_t>(p->rows());
  return py::array_t<double>({r, py::ssize_t(3)},
                             {py::ssize_t(3 * sizeof(double)), py::ssize_t(sizeof(double))},
                             p->data(), owner(p));
}

py::array to_numpy(std::vector<Index>&& v) {
  auto* p = new std::vector<Index>(std::move(v));
  return py::array_t<Index>({static_cast<py::ssize_t>(p->size())}, {sizeof(Index)}, p->data(),
                            owner(p));
}

py::array to_numpy(std::vector<Triangle>&& t) {
  auto* p = new std::vector<Triangle>(std::move(t));
  static_assert(sizeof(Triangle) == 3 * sizeof(Index), "Triangle must be three packed ids");
  return py::array_t<Index>({static_cast<py::ssize_t>(p->size()), py::ssize_t(3)},
                            {py::ssize_t(sizeof(Triangle)), py::ssize_t(sizeof(Index))},
                            reinterpret_cast<Index*>(p->data()), owner(p));
}

py::tuple to_csc_parts(Eigen::SparseMatrix<double, Eigen::ColMajor, int>&& A) {
  using Sparse = Eigen::SparseMatrix<double, Eigen::ColMajor, int>;
  A.makeCompressed();
  auto* p = new Sparse();
  p->swap(A);  // Eigen 3.4's SparseMatrix has no move constructor: std::move would copy
  const py::capsule keep = owner(p);
  const auto nnz = static_cast<py::ssize_t>(p->nonZeros());
  const auto cols = static_cast<py::ssize_t>(p->cols());
  py::array data = py::array_t<double>({nnz}, {sizeof(double)}, p->valuePtr(), keep);
  py::array indices = py::array_t<int>({nnz}, {sizeof(int)}, p->innerIndexPtr(), keep);
  py::array indptr = py::array_t<int>({cols + 1}, {sizeof(int)}, p->outerIndexPtr(), keep);
  return py::make_tuple(data, indices, indptr, py::make_tuple(p->rows(), p->cols()));
}

}  // namespace ifem::python
