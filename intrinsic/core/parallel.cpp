#include "intrinsic/core/parallel.h"

#include <atomic>
#include <chrono>
#include <cstdio>
#include <thread>

namespace ifem {

namespace {

// Tasks running on the machine now (the 4th field of /proc/loadavg, "running/total"), or −1
// when unknown (not Linux).
int running_tasks() {
  std::FILE* f = std::fopen("/proc/loadavg", "r");
  if (!f) return -1;
  double l1 = 0, l5 = 0, l15 = 0;
  int running = -1, total = 0;
  if (std::fscanf(f, "%lf %lf %lf %d/%d", &l1, &l5, &l15, &running, &total) != 5) running = -1;
  std::fclose(f);
  return running;
}

std::int64_t now_ms() {
  return std::chrono::duration_cast<std::chrono::milliseconds>(
             std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

// After a parallel region, this process's OpenMP workers spin for a while (GOMP_SPINCOUNT:
// milliseconds) and count as running: for this long after a region that ran parallel, they are
// not taken for other programs' work.
constexpr std::int64_t kWorkersSpinMs = 50;
std::atomic<std::int64_t> last_parallel_ms{-kWorkersSpinMs};
std::atomic<bool> load_check{true};

}  // namespace

bool parallel_pays(Index n, Index min_n) {
  if (n < min_n) return false;
  static const int cores = static_cast<int>(std::thread::hardware_concurrency());
  if (cores <= 1) return false;
  if (!load_check.load(std::memory_order_relaxed)) return true;
  const int running = running_tasks();
  if (running < 0) return true;
  const std::int64_t now = now_ms();
  int others = running - 1;  // the calling thread is running
  if (now - last_parallel_ms.load(std::memory_order_relaxed) < kWorkersSpinMs) {
    others -= cores - 1;  // perhaps our own spinning workers
  }
  if (others >= cores - 1) return false;  // no idle core
  last_parallel_ms.store(now, std::memory_order_relaxed);
  return true;
}

void set_parallel_load_check(bool enabled) { load_check.store(enabled, std::memory_order_relaxed); }

}  // namespace ifem
