#include "solvers/linalg/blas_threads.h"

#include <dlfcn.h>

#include <mutex>

namespace ifem::solvers {

namespace {

// OpenBLAS's public thread setter and getter (cblas.h), looked up once at run time: null with
// another BLAS, so the library does not depend on OpenBLAS.
struct OpenBlasThreads {
  using Set = void (*)(int);
  using Get = int (*)();
  Set set = nullptr;
  Get get = nullptr;
  OpenBlasThreads() {
    set = reinterpret_cast<Set>(dlsym(RTLD_DEFAULT, "openblas_set_num_threads"));
    get = reinterpret_cast<Get>(dlsym(RTLD_DEFAULT, "openblas_get_num_threads"));
    if (!set || !get) set = nullptr, get = nullptr;
  }
  static const OpenBlasThreads& instance() {
    static const OpenBlasThreads o;
    return o;
  }
};

std::mutex scope_mutex;
int scope_depth = 0;
int scope_saved = 0;

}  // namespace

BlasThreadScope::BlasThreadScope(int threads) {
  const OpenBlasThreads& o = OpenBlasThreads::instance();
  if (threads <= 0 || !o.set) return;
  std::lock_guard<std::mutex> lock(scope_mutex);
  if (scope_depth++ == 0) {
    scope_saved = o.get();
    if (scope_saved != threads) o.set(threads);
  }
  active_ = true;
}

BlasThreadScope::~BlasThreadScope() {
  if (!active_) return;
  const OpenBlasThreads& o = OpenBlasThreads::instance();
  std::lock_guard<std::mutex> lock(scope_mutex);
  if (--scope_depth == 0 && o.get() != scope_saved) o.set(scope_saved);
}

int BlasThreadScope::current() {
  const OpenBlasThreads& o = OpenBlasThreads::instance();
  return o.get ? o.get() : 0;
}

}  // namespace ifem::solvers
