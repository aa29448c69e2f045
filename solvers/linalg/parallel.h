// Independent jobs side by side on OpenMP threads, for the factorizations and the two halves of
// a solve (internal to solvers/). OpenMP is the library's one threading model: the thread count
// is OpenMP's (omp_set_num_threads(), OMP_NUM_THREADS).
#pragma once

#include <functional>
#include <vector>

namespace ifem::solvers {

/// Runs independent jobs on up to min(#jobs, omp_get_max_threads()) OpenMP threads (OpenBLAS at
/// one thread meanwhile), each job on one thread; rethrows the first job's exception (in job
/// order) after all have finished. Called inside an active OpenMP parallel region (e.g. from
/// another run_parallel() job), or in a build without OpenMP, it runs the jobs one after the
/// other on the calling thread: the cores are taken already. Which thread runs a job never
/// changes its result.
void run_parallel(const std::vector<std::function<void()>>& jobs);

/// Runs part(0) and part(1), the two halves of one piece of work: side by side through
/// run_parallel() when `parallel`, else one after the other. The halves are the same either way,
/// so a caller that sums each half on its own and then adds the two gets the same bits.
void run_halves(bool parallel, const std::function<void(int half)>& part);

}  // namespace ifem::solvers
