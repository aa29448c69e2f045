#include "solvers/linalg/parallel.h"

#include <algorithm>
#include <exception>

#ifdef _OPENMP
#include <omp.h>
#endif

#include "solvers/linalg/blas_threads.h"

namespace ifem::solvers {

void run_parallel(const std::vector<std::function<void()>>& jobs) {
  const int n = int(jobs.size());
#ifdef _OPENMP
  const int threads = omp_in_parallel() ? 1 : std::min(n, omp_get_max_threads());
#else
  const int threads = 1;
#endif
  if (threads <= 1) {
    for (const auto& j : jobs) j();
    return;
  }
  // OpenBLAS's own threads would compete with these for the same cores
  const BlasThreadScope one_blas_thread(1);
  std::vector<std::exception_ptr> errors(jobs.size());
  // an exception must not leave an OpenMP region: each job's is kept and rethrown after it
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads)
  for (int i = 0; i < n; ++i) {
    try {
      jobs[std::size_t(i)]();
    } catch (...) {
      errors[std::size_t(i)] = std::current_exception();
    }
  }
  for (const auto& e : errors) {
    if (e) std::rethrow_exception(e);
  }
}

void run_halves(bool parallel, const std::function<void(int half)>& part) {
  if (parallel) {
    run_parallel({[&part] { part(0); }, [&part] { part(1); }});
  } else {
    part(0);
    part(1);
  }
}

}  // namespace ifem::solvers
