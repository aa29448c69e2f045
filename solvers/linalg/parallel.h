// Independent jobs side by side, for the factorizations of the heat solvers (internal to
// solvers/).
#pragma once

#include <functional>
#include <vector>

namespace ifem::solvers {

/// Runs independent jobs on up to min(#jobs, max_threads()) threads (OpenBLAS at one thread each
/// meanwhile); rethrows the first job's exception after all have finished. The threads other
/// than the caller's are helpers kept between calls (a thread start costs ~30 µs; they spin
/// briefly, then sleep); a call that finds them busy with another caller's jobs, or runs in a
/// forked child, starts threads of its own. CHOLMOD's supernodal factorization of a surface
/// Laplacian is mostly small dense blocks where BLAS threads gain little, so two factorizations
/// side by side (BLAS at 1 thread each) finish well before two in a row (docs/DEPENDENCIES.md: ~1.9
/// s vs 2.6–3.0 s at 1M faces). Jobs started from inside another run_parallel() job run one after
/// the other on the calling thread (the cores are taken already).
void run_parallel(const std::vector<std::function<void()>>& jobs);

/// Runs part(0) and part(1), the two halves of one piece of work: side by side through
/// run_parallel() when `parallel`, else one after the other. The halves are the same either way,
/// so a caller that sums each half on its own and then adds the two gets the same bits.
void run_halves(bool parallel, const std::function<void(int half)>& part);

/// Caps the threads run_parallel() uses, process-wide (0: the hardware's core count; ≥ 0).
/// Results never depend on it (tests compare 1 and 2 threads bitwise).
/// @throws InvalidInput if threads < 0
void set_max_threads(int threads);
/// The current cap: set_max_threads()'s value, or the core count.
int max_threads();

}  // namespace ifem::solvers
