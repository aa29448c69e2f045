// Carrying an exception out of an OpenMP region (exceptions may not leave one: std::terminate):
// the region records the first exception of any type, the code after it rethrows that very
// exception, so the caller sees its type (InvalidInput, TraceError, SolverError,
// std::bad_alloc, ...) as if the loop had been sequential.
#pragma once

#include <atomic>
#include <exception>
#include <stdexcept>
#include <string>

#include "intrinsic/core/errors.h"

namespace ifem {

/// The first exception recorded (thread-safe), rethrown after the parallel region by
/// rethrow_if_any(). Usage, in every OpenMP region whose body can throw:
///
///     FirstError failure;
///     #pragma omp parallel for
///     for (...) {
///       if (failure.failed()) continue;  // optional: stop early
///       try { ... } catch (...) { failure.record_current("edge " + std::to_string(e)); }
///     }
///     failure.rethrow_if_any("context");
class FirstError {
 public:
  /// Records the exception being handled (call inside a catch block), thrown at `where`
  /// (e.g. "edge 12"), unless an earlier one is recorded.
  void record_current(const std::string& where) noexcept {
    std::exception_ptr e = std::current_exception();
#pragma omp critical(ifem_first_error)
    if (!error_) {
      error_ = e;
      try {
        where_ = where;
      } catch (...) {  // no memory left for the note: the exception itself still counts
      }
      failed_.store(true, std::memory_order_relaxed);
    }
  }
  /// Same as record_current() (kept for callers that catch an Error by name): records the
  /// exception being handled, which must be `e`.
  void record(const Error& e, const std::string& where) noexcept {
    (void)e;
    record_current(where);
  }
  /// Whether an exception was recorded (a hint to skip the remaining work).
  bool failed() const noexcept { return failed_.load(std::memory_order_relaxed); }
  /// Rethrows the recorded exception. An ifem Error is rethrown as the same type with the
  /// message "<context>: <where>: <what>" (InvalidInput, TraceError, SolverError, ...); any
  /// other exception (std::bad_alloc, ...) is rethrown as it was. Does nothing when none was
  /// recorded.
  void rethrow_if_any(const std::string& context) const {
    if (!error_) return;
    const std::string prefix = context + ": " + (where_.empty() ? "" : where_ + ": ");
    try {
      std::rethrow_exception(error_);
    } catch (const NonOrientableInput& e) {
      throw NonOrientableInput(prefix + e.what());
    } catch (const NonManifoldInput& e) {
      throw NonManifoldInput(prefix + e.what());
    } catch (const InvalidInput& e) {
      throw InvalidInput(prefix + e.what());
    } catch (const IoError& e) {
      throw IoError(prefix + e.what());
    } catch (const TraceError& e) {
      throw TraceError(prefix + e.what());
    } catch (const SolverError& e) {
      throw SolverError(prefix + e.what());
    } catch (const Error& e) {
      throw Error(prefix + e.what());
    }
    // other types (std::bad_alloc, std::length_error, ...) propagate from rethrow_exception
  }

 private:
  std::exception_ptr error_;
  std::string where_;
  std::atomic<bool> failed_{false};
};

}  // namespace ifem
