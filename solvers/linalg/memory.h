// The process's memory policy for short runs (the CLI, the benchmarks that time what it does).
#pragma once

namespace ifem {

/// Makes the C library keep the memory the program frees for its next allocations instead of
/// handing it back to the kernel (glibc malloc: no trimming of the heap's top, blocks below
/// 32 MB from the heap rather than from mmap). Why: a page's first touch is a fault plus its
/// zeroing, ~1–2 µs on a virtual machine, and a heat precompute frees and allocates again most
/// of its memory (a permuted copy of each matrix, the analysis's block, AMD's workspace): the
/// rocketship precompute went from 0.049 to 0.042 s (docs/decisions.md, "Small meshes: freed
/// memory kept"). The price: the resident size no longer shrinks after a peak, which a process
/// that ends after one job does not mind; a long-lived host (a notebook, a server) chooses for
/// itself whether to call it. Process-wide; call it first thing in main(). A no-op without
/// glibc.
void retain_freed_memory();

}  // namespace ifem
