#include "solvers/parallel.h"

#include <algorithm>
#include <atomic>
#include <exception>
#include <thread>

#include "solvers/cholesky.h"

namespace ifem::solvers {

void run_parallel(const std::vector<std::function<void()>>& jobs) {
  const unsigned cores = std::max(1u, std::thread::hardware_concurrency());
  const std::size_t workers = std::min<std::size_t>(jobs.size(), cores);
  if (workers <= 1) {
    for (const auto& j : jobs) j();
    return;
  }
  const BlasThreadScope one_blas_thread(1);
  std::atomic<std::size_t> next{0};
  std::vector<std::exception_ptr> errors(jobs.size());
  auto work = [&]() {
    for (std::size_t i = next++; i < jobs.size(); i = next++) {
      try {
        jobs[i]();
      } catch (...) {
        errors[i] = std::current_exception();
      }
    }
  };
  std::vector<std::thread> threads;
  for (std::size_t w = 1; w < workers; ++w) threads.emplace_back(work);
  work();
  for (auto& t : threads) t.join();
  for (const auto& e : errors) {
    if (e) std::rethrow_exception(e);
  }
}

}  // namespace ifem::solvers
