#include "solvers/linalg/parallel.h"

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <exception>
#include <mutex>
#include <thread>

#include "intrinsic/core/errors.h"
#include "solvers/linalg/cholesky.h"

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

namespace {

// Helper threads kept between run_parallel() calls, waiting for the next batch: a thread start
// costs ~30 µs, and a block of heat sources on a 10k-face mesh runs ~14 parallel steps of
// 0.05–0.8 ms. A helper spins (sched_yield) for the next batch before it sleeps (consecutive
// steps follow each other closely). One batch at a time; a call that finds the pool busy, or runs
// in a child process after fork() (the helpers did not survive it), starts threads of its own.
// Never destroyed (its detached helpers end with the process).
class HelperPool {
 public:
  static HelperPool& instance() {
    static HelperPool* pool = new HelperPool;
    return *pool;
  }

  // Runs work() on `helpers` helper threads and on the calling thread; false if the pool is
  // busy or not this process's.
  bool run(std::size_t helpers, const std::function<void()>& work) {
    if (getpid() != pid_) return false;
    std::unique_lock<std::mutex> batch(batch_mutex_, std::try_to_lock);
    if (!batch.owns_lock()) return false;
    {
      const std::lock_guard<std::mutex> lock(mutex_);
      while (started_ < helpers) {
        // (it starts from the generation before this batch's: the batch is new to it)
        std::thread(&HelperPool::helper, this, generation_.load()).detach();
        ++started_;
      }
      work_ = &work;
      wanted_ = helpers;
      taken_ = 0;
      running_ = helpers;
      generation_.store(generation_.load() + 1, std::memory_order_release);
    }
    wake_.notify_all();
    work();
    std::unique_lock<std::mutex> lock(mutex_);
    finished_.wait(lock, [this] { return running_ == 0; });
    work_ = nullptr;
    return true;
  }

 private:
  HelperPool() : pid_(getpid()) {}

  void helper(std::uint64_t seen) {
    for (;;) {
      for (int spin = 0; spin < kSpins && generation_.load(std::memory_order_acquire) == seen;
           ++spin) {
        std::this_thread::yield();
      }
      std::unique_lock<std::mutex> lock(mutex_);
      wake_.wait(lock, [&] { return generation_.load(std::memory_order_relaxed) != seen; });
      seen = generation_.load(std::memory_order_relaxed);
      if (taken_ == wanted_) continue;  // enough helpers on this batch already
      ++taken_;
      const std::function<void()>* work = work_;
      lock.unlock();
      (*work)();
      lock.lock();
      if (--running_ == 0) finished_.notify_all();
    }
  }

  // sched_yield() calls before sleeping: 0.3–2.4 ms (0.16–1.2 µs each, measured); sleeping at
  // once made a 10k-face block of 32 sources 2.2 -> 2.6 ms
  static constexpr int kSpins = 2000;
  const pid_t pid_;
  std::mutex batch_mutex_;  // one batch at a time
  std::mutex mutex_;
  std::condition_variable wake_, finished_;
  std::atomic<std::uint64_t> generation_{0};
  std::size_t started_ = 0, wanted_ = 0, taken_ = 0, running_ = 0;
  const std::function<void()>* work_ = nullptr;
};

}  // namespace

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
  const std::function<void()> work = [&]() {
    const InsideJob mark;
    for (std::size_t i = next++; i < jobs.size(); i = next++) {
      try {
        jobs[i]();
      } catch (...) {
        errors[i] = std::current_exception();
      }
    }
  };
  if (!HelperPool::instance().run(workers - 1, work)) {
    std::vector<std::thread> threads;
    for (std::size_t w = 1; w < workers; ++w) threads.emplace_back(work);
    work();
    for (auto& t : threads) t.join();
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
