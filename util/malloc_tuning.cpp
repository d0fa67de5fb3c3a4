#include "util/malloc_tuning.h"

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
