// When a loop runs on OpenMP threads: large enough, and with a core free to take the work.
#pragma once

#include "intrinsic/core/types.h"

namespace ifem {

/// Whether an OpenMP loop over n elements should run on several threads (the `if` clause of its
/// `#pragma omp parallel`): n ≥ min_n, and another core is idle right now — fewer tasks are
/// running on the machine (Linux's instantaneous count in /proc/loadavg, this thread included)
/// than it has cores: on a busy machine a team's barrier waits for a thread that first has to be
/// scheduled (docs/decisions.md D-043). Results never depend on the answer (loops write
/// disjoint outputs or reduce integers). Costs one read of /proc/loadavg when n ≥ min_n.
bool parallel_pays(Index n, Index min_n = kParallelMin);

/// Turns the idle-core check of parallel_pays() off (false: every loop of ≥ min_n elements
/// uses the OpenMP team, e.g. for tests of thread-count independence) or back on (the default).
void set_parallel_load_check(bool enabled);

}  // namespace ifem
