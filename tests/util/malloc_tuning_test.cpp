// util/malloc_tuning.h: once asked, glibc's malloc serves a block of tens of
// megabytes from the heap and keeps it there when freed, so the next test
// reuses those pages instead of faulting them in again.
#include "util/malloc_tuning.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <cstring>

#if defined(__GLIBC__)
#include <malloc.h>
#endif

#if defined(__SANITIZE_ADDRESS__)
#define NAPKIN_TEST_UNDER_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define NAPKIN_TEST_UNDER_ASAN 1
#endif
#endif

namespace napkin::util {
namespace {

TEST(MallocTuningTest, FreedBlocksStayInTheHeapForReuse) {
#if !defined(__GLIBC__)
  GTEST_SKIP() << "not glibc: napkin leaves the C library's malloc as it is";
#elif defined(NAPKIN_TEST_UNDER_ASAN)
  GTEST_SKIP() << "AddressSanitizer replaces glibc's malloc (its mallopt does nothing): "
                  "checked in builds without sanitizers";
#else
  ASSERT_TRUE(KeepFreedMemoryForReuse());
  EXPECT_TRUE(KeepFreedMemoryForReuse());  // applied once, still reported as applied

  // 48 MiB: above glibc's default mmap threshold (128 KiB, at most 32 MiB
  // once it adapts), below napkin's 64 MiB and the 256 MiB trim threshold.
  constexpr std::size_t kBlockBytes = std::size_t{48} << 20;
  const struct mallinfo2 before = mallinfo2();
  char* block = static_cast<char*>(std::malloc(kBlockBytes));
  ASSERT_NE(block, nullptr);
  std::memset(block, 1, kBlockBytes);
  asm volatile("" : : "r"(block) : "memory");  // the block is used: keep the malloc
  const struct mallinfo2 allocated = mallinfo2();
  std::free(block);
  const struct mallinfo2 freed = mallinfo2();

  EXPECT_EQ(allocated.hblkhd, before.hblkhd) << "the block was mapped on its own, not taken from the heap";
  EXPECT_GE(allocated.arena, before.arena + kBlockBytes);
  EXPECT_EQ(freed.arena, allocated.arena) << "the heap was trimmed: the freed block went back to the kernel";
  EXPECT_GE(freed.fordblks, kBlockBytes);  // and is free for the next allocation
#endif
}

}  // namespace
}  // namespace napkin::util
