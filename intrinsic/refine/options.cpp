// validate() of the refinement and tracing options (declared in delaunay_refine.h, signpost.h).
#include <cmath>
#include <string>

#include "intrinsic/core/errors.h"
#include "intrinsic/refine/delaunay_refine.h"
#include "intrinsic/refine/signpost.h"

namespace ifem::intrinsic {

namespace {

std::string str(double x) { return std::to_string(x); }

}  // namespace

void RefineOptions::validate() const {
  if (!(min_angle_degrees > 0.0 && min_angle_degrees <= 30.0)) {
    throw InvalidInput(
        "RefineOptions::min_angle_degrees: minimum angle must be in (0, 30] degrees, got " +
        str(min_angle_degrees));
  }
  if (!(max_area >= 0.0) || !std::isfinite(max_area)) {
    throw InvalidInput("RefineOptions::max_area must be finite and ≥ 0 (0: no bound), got " +
                       str(max_area));
  }
  if (max_insertions < -1) {
    throw InvalidInput("RefineOptions::max_insertions must be ≥ −1 (−1: automatic), got " +
                       std::to_string(max_insertions));
  }
  if (!(max_memory_bytes >= 0.0)) {
    throw InvalidInput(
        "RefineOptions::max_memory_bytes must be ≥ 0 (0: automatic, ∞: no budget), got " +
        str(max_memory_bytes));
  }
}

void RelaxOptions::validate() const {
  if (iterations < 0) {
    throw InvalidInput("RelaxOptions::iterations must be ≥ 0, got " + std::to_string(iterations));
  }
  if (!(max_edge_length >= 0.0) || !std::isfinite(max_edge_length)) {
    throw InvalidInput(
        "RelaxOptions::max_edge_length must be finite and ≥ 0 (0: no splitting), got " +
        str(max_edge_length));
  }
  if (max_splits < -1) {
    throw InvalidInput("RelaxOptions::max_splits must be ≥ −1 (−1: automatic), got " +
                       std::to_string(max_splits));
  }
}

void TraceOptions::validate() const {
  if (start_corner < -1 || start_corner > 2) {
    throw InvalidInput("TraceOptions::start_corner must be −1, 0, 1 or 2, got " +
                       std::to_string(start_corner));
  }
  if (max_steps < -1) {
    throw InvalidInput("TraceOptions::max_steps must be ≥ −1 (−1: automatic), got " +
                       std::to_string(max_steps));
  }
}

}  // namespace ifem::intrinsic
