// Arrays between numpy and ifem: checked conversion of V / F / index lists / value vectors into
// the library's types (clear exceptions, never a crash), and results handed to numpy without a
// copy (the Eigen object moves into a capsule that the numpy array keeps alive).
//
// Every check throws ifem::InvalidInput (Python: ifem.InvalidInput, a ValueError) naming the
// argument, what was expected and what came: shape, dtype kind, the first non-finite row, the
// first index out of range.
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <string>
#include <vector>

#include "intrinsic/core/types.h"
#include "intrinsic/io/mesh_io.h"

namespace ifem::python {

namespace py = pybind11;

/// #V×3 positions from any real or integer array (float32, Fortran order and other strides are
/// converted). @throws InvalidInput on another shape or dtype, no rows, or a non-finite entry
Positions positions_from(const py::handle& array, const char* name);

/// #F×3 triangles from an integer array (any integer dtype and order), each id in
/// [0, n_vertices). @throws InvalidInput on a non-integer dtype, another shape, or an id out of
/// range (naming the row)
std::vector<Triangle> triangles_from(const py::handle& array, Index n_vertices, const char* name);

/// A 1-D list of vertex ids (or a Python int), each in [0, n). Empty allowed when allow_empty.
/// @throws InvalidInput on a non-integer dtype, more than one dimension or an id out of range
std::vector<Index> indices_from(const py::handle& array, Index n, const char* name,
                                bool allow_empty = false);

/// A 1-D float vector of exactly `size` finite values (size < 0: any length).
/// @throws InvalidInput on another length, dtype or a non-finite value
Eigen::VectorXd values_from(const py::handle& array, Eigen::Index size, const char* name);

/// An input from arrays: V (#V×3) and F (#F×3, may be None or empty for a point cloud) and
/// optional per-vertex normals (#V×3; rows that are zero or not finite mean "none").
io::SurfaceInput surface_input(const py::handle& V, const py::handle& F,
                               const py::handle& normals = py::none());

/// A numpy view of a vector / matrix that takes ownership of it (no copy).
py::array to_numpy(Eigen::VectorXd&& v);
py::array to_numpy(Eigen::MatrixXd&& m);
py::array to_numpy(Positions&& p);
py::array to_numpy(std::vector<Index>&& v);
py::array to_numpy(std::vector<Triangle>&& t);

/// A compressed-column sparse matrix as the tuple (data, indices, indptr, (rows, cols)) that
/// scipy.sparse.csc_matrix takes; the three arrays share the matrix's own buffers (no copy).
py::tuple to_csc_parts(Eigen::SparseMatrix<double, Eigen::ColMajor, int>&& A);

}  // namespace ifem::python
