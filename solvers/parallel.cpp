#include "solvers/parallel.h"

#include <algorithm>
#include <atomic>
#include <exception>
#include <thread>

#include "intrinsic/core/errors.h"
#include "solvers/cholesky.h"

namespace ifem::solvers {

namespace {

std::atomic<int> thread_cap{0};
thread_local bool inside_job = false;

// Marks the calling thread as running a job for the scope's lifetime.
class InsideJob {
 public:
  InsideJob() : saved_(inside_job) { inside_job = true; }
  ~InsideJob() { inside_job = saved_; }
  InsideJob(const InsideJob&) = delete;
  InsideJob& operator=(const InsideJob&) = delete;

 private:
  bool saved_;
};

}  // namespace

void set_max_threads(int threads) {
  if (threads < 0) throw InvalidInput("set_max_threads: need threads ≥ 0");
  thread_cap = threads;
}

int max_threads() {
  const int cap = thread_cap;
  return cap > 0 ? cap : int(std::max(1u, std::thread::hardware_concurrency()));
}

void run_parallel(const std::vector<std::function<void()>>& jobs) {
  const std::size_t workers =
      inside_job ? 1 : std::min<std::size_t>(jobs.size(), std::size_t(max_threads()));
  if (workers <= 1) {
    for (const auto& j : jobs) j();
    return;
  }
  const BlasThreadScope one_blas_thread(1);
  std::atomic<std::size_t> next{0};
  std::vector<std::exception_ptr> errors(jobs.size());
  auto work = [&]() {
    const InsideJob mark;
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

void run_halves(bool parallel, const std::function<void(int half)>& part) {
  if (parallel) {
    run_parallel({[&part] { part(0); }, [&part] { part(1); }});
  } else {
    part(0);
    part(1);
  }
}

}  // namespace ifem::solvers
