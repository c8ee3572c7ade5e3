#include "util/memory_policy.h"

#include <cstdlib>  // defines __GLIBC__ where the C library is glibc

#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace softbench {

void KeepFreedMemory() {
#if defined(__GLIBC__)
  // Blocks up to glibc's largest threshold (32 MB, a 4K frame of 16-bit
  // luma and chroma) from the heap, and a free top of up to 512 MB kept.
  // Either alone is worse than neither: setting one fixes the other at its
  // 128 KB default (measured in docs/benchmarks.md).
  constexpr int kMmapThresholdBytes = 32 << 20;
  constexpr int kTrimThresholdBytes = 512 << 20;
  mallopt(M_MMAP_THRESHOLD, kMmapThresholdBytes);
  mallopt(M_TRIM_THRESHOLD, kTrimThresholdBytes);
#endif
}

}  // namespace softbench
