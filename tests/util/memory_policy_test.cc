// The process keeps the memory it frees (util/memory_policy.h).
#include "util/memory_policy.h"

#include <gtest/gtest.h>

#include <cstdlib>  // defines __GLIBC__ where the C library is glibc
#if defined(__GLIBC__)
#include <malloc.h>
#endif

#include <cstring>

// Whether AddressSanitizer's allocator serves malloc: GCC says so with
// __SANITIZE_ADDRESS__, clang (the asan preset's compiler) with
// __has_feature.
#if defined(__SANITIZE_ADDRESS__)
#define SOFTBENCH_TEST_UNDER_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define SOFTBENCH_TEST_UNDER_ASAN 1
#endif
#endif

namespace softbench {
namespace {

#if defined(__GLIBC__) && !defined(SOFTBENCH_TEST_UNDER_ASAN)
// A 24 MB block (about a 4K frame of 16-bit luma and chroma) comes from the
// heap, not a mapping of its own, and its pages stay with the process once
// it is freed. glibc's defaults map it apart and unmap it on free (until a
// freed mapping of that size has raised the threshold), or trim it from the
// heap's top. (Under AddressSanitizer, its own allocator serves every block
// and glibc's settings do not reach it: no test.)
TEST(KeepFreedMemory, ServesLargeBlocksFromTheHeapAndKeepsThem) {
  KeepFreedMemory();
  constexpr size_t kBytes = 24u << 20;
  const struct mallinfo2 before = mallinfo2();
  void* block = std::malloc(kBytes);
  ASSERT_NE(block, nullptr);
  std::memset(block, 1, kBytes);
  const struct mallinfo2 held = mallinfo2();
  EXPECT_EQ(held.hblkhd, before.hblkhd) << "the block was mapped apart";
  std::free(block);
  const struct mallinfo2 after = mallinfo2();
  EXPECT_GE(after.arena, before.arena + kBytes) << "the heap was trimmed";
  EXPECT_GE(after.fordblks, kBytes);
}
#endif

}  // namespace
}  // namespace softbench
