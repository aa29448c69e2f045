// ifem error hierarchy. Library functions throw these on input they cannot use;
// what can be repaired is repaired and counted in a report instead (see README, "Conventions").
#pragma once

#include <stdexcept>
#include <string>

namespace ifem {

/// Base of every exception ifem throws. The message says what and where.
class Error : public std::runtime_error {
 public:
  explicit Error(const std::string& what) : std::runtime_error(what) {}
};

/// Input that cannot be used as given: out-of-range index, NaN coordinate, empty mesh, ...
class InvalidInput : public Error {
 public:
  using Error::Error;
};

/// An edge with 3+ incident faces, or a non-orientable gluing: the manifold path cannot
/// represent it. The tufted cover accepts such inputs.
class NonManifoldInput : public InvalidInput {
 public:
  using InvalidInput::InvalidInput;
};

/// A gluing with no consistent orientation (a Moebius-like loop): the manifold path cannot
/// represent it. The tufted cover accepts such inputs.
class NonOrientableInput : public NonManifoldInput {
 public:
  using NonManifoldInput::NonManifoldInput;
};

/// A file that cannot be read or written: missing, unknown format, malformed, truncated.
class IoError : public Error {
 public:
  using Error::Error;
};

/// A straight-line trace over a surface (signposts: locating an inserted vertex, tracing an
/// intrinsic edge over the input) that could not finish: it crossed more sides than any
/// straight line of that length can (degenerate geometry, rounding loops). Refinement counts
/// these and goes on; everywhere else they propagate.
class TraceError : public Error {
 public:
  using Error::Error;
};

/// A numerical failure: a matrix that is not positive definite, an eigensolver that did
/// not converge.
class SolverError : public Error {
 public:
  using Error::Error;
};

}  // namespace ifem
