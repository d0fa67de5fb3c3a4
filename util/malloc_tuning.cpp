#include "util/malloc_tuning.h"

// <cstdlib> first: __GLIBC__ is defined by the C library's own headers, so
// testing it before any is included would always take the #else branch.
#include <cstdlib>

#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace napkin::util {

bool KeepFreedMemoryForReuse() {
#if defined(__GLIBC__)
  static const bool kKept = [] {
    constexpr int kMmapThresholdBytes = 64 << 20;
    constexpr int kTrimThresholdBytes = 256 << 20;
    return mallopt(M_MMAP_THRESHOLD, kMmapThresholdBytes) == 1 &&
           mallopt(M_TRIM_THRESHOLD, kTrimThresholdBytes) == 1;
  }();
  return kKept;
#else
  return false;
#endif
}

}  // namespace napkin::util
