// Independent jobs side by side, for the factorizations of the heat solvers (internal to
// solvers/).
#pragma once

#include <functional>
#include <vector>

namespace ifem::solvers {

/// Runs independent jobs on up to min(#jobs, #cores) threads (OpenBLAS at one thread each
/// meanwhile); rethrows the first job's exception after all have finished. CHOLMOD's supernodal
/// factorization of a surface Laplacian is mostly small dense blocks where BLAS threads gain
/// little, so two factorizations side by side (BLAS at 1 thread each) finish well before two in a
/// row (docs/DEPENDENCIES.md: ~1.9 s vs 2.6–3.0 s at 1M faces).
void run_parallel(const std::vector<std::function<void()>>& jobs);

}  // namespace ifem::solvers
