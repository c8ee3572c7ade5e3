#ifndef SOFTBENCH_UTIL_MEMORY_POLICY_H_
#define SOFTBENCH_UTIL_MEMORY_POLICY_H_

namespace softbench {

// Keeps memory the process frees for its own later allocations, instead of
// handing it back to the system and faulting fresh pages in on the next
// image of the same size. glibc's malloc, by default, serves blocks from
// 128 KB up (the size of a 137 x 137 image of doubles) from their own
// mappings and trims the heap's free top past 128 KB, and every new page
// then costs a fault and its zeroing: about 10 us a page on the VM the
// benchmarks run on, where the tag's fit (vision/tag_model.h) spent a
// third of its time in them (docs/benchmarks.md, "The tag fitted whole:
// its cost"). Called once, first thing in main; a no-op where the C
// library is not glibc. Its price is memory on long videos (10 minutes:
// 158 -> 175 MB at 1080p, 328 -> 371 MB at 4K); held only around the fit
// instead, it saved that but made the fit's footage 1.5-3 % slower
// (docs/benchmarks.md, "A 10-minute 4K video: peak memory").
void KeepFreedMemory();

}  // namespace softbench

#endif  // SOFTBENCH_UTIL_MEMORY_POLICY_H_
