#include "solvers/linalg/memory.h"

#include <cstdlib>  // defines __GLIBC__ with glibc

#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace ifem {

void retain_freed_memory() {
#if defined(__GLIBC__)
  // mmap only from 32 MB (glibc's largest setting; the fixed value also stops its dynamic
  // threshold), never trim the top, and grow the heap in 64 MB steps (untouched pages cost
  // nothing)
  mallopt(M_MMAP_THRESHOLD, 32 << 20);
  mallopt(M_TRIM_THRESHOLD, 1 << 30);
  mallopt(M_TOP_PAD, 64 << 20);
#endif
}

}  // namespace ifem
