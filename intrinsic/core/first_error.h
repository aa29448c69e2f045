// Carrying an exception out of an OpenMP loop (exceptions may not leave one): the loop records
// the first Error, the code after the loop rethrows it, keeping whether it was a TraceError.
#pragma once

#include <string>

#include "intrinsic/core/errors.h"

namespace ifem {

/// The first Error recorded (thread-safe), rethrown after the parallel loop by rethrow_if_any().
class FirstError {
 public:
  /// Records `e` thrown at `where` (e.g. "edge 12") unless an earlier one is recorded.
  void record(const Error& e, const std::string& where) {
    const bool trace = dynamic_cast<const TraceError*>(&e) != nullptr;
#pragma omp critical(ifem_first_error)
    if (message_.empty()) {
      message_ = where + ": " + e.what();
      trace_ = trace;
    }
  }
  /// Throws the recorded failure as "<context>: <where>: <what>" (a TraceError if it was one,
  /// else an Error); does nothing when none was recorded.
  void rethrow_if_any(const std::string& context) const {
    if (message_.empty()) return;
    if (trace_) throw TraceError(context + ": " + message_);
    throw Error(context + ": " + message_);
  }

 private:
  std::string message_;
  bool trace_ = false;
};

}  // namespace ifem
