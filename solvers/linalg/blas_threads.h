// OpenBLAS's thread count for a scope, through its public API only (internal to solvers/ and
// the tools that time it).
#pragma once

namespace ifem::solvers {

/// Sets OpenBLAS's thread count for a scope and restores it afterwards (process-wide: OpenBLAS
/// has a single setting). Nested or concurrent scopes share the first scope's count; the last
/// one to end restores the previous value. Uses only OpenBLAS's public openblas_set_num_threads()
/// and openblas_get_num_threads(), looked up at run time so that the library also links against
/// any other BLAS, where the scope is a no-op (as it is when threads ≤ 0).
class BlasThreadScope {
 public:
  explicit BlasThreadScope(int threads);
  ~BlasThreadScope();
  BlasThreadScope(const BlasThreadScope&) = delete;
  BlasThreadScope& operator=(const BlasThreadScope&) = delete;
  /// The current OpenBLAS thread count, or 0 without OpenBLAS.
  static int current();

 private:
  bool active_ = false;
};

}  // namespace ifem::solvers
