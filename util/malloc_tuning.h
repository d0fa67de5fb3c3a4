#pragma once
// How napkin asks glibc's malloc to keep freed memory for reuse: the
// `napkin run` program (jobs/scheduler.cpp, RunOptions::keep_freed_memory)
// and, only when a user calls it, napkin.tune_memory() (python/). The
// transform core itself needs it not (docs/architecture.md "Memory").

namespace napkin::util {

// Every test allocates the same few megabytes of series (signals,
// kinematics, derived channels) and frees them a few milliseconds later.
// glibc's malloc would hand most of that back to the kernel on free (heap
// trimming above M_TRIM_THRESHOLD, and blocks above M_MMAP_THRESHOLD mapped
// and unmapped one by one), so the next test pays a page fault per 4 KiB
// page again: about 10 % of a test's CPU time in the profile. Raising both
// thresholds (64 MiB, 256 MiB) keeps freed memory in the heap for reuse,
// which bounds the process at its largest working set. Process-wide; applied
// once; returns false where it could not be (not glibc, or refused).
bool KeepFreedMemoryForReuse();

}  // namespace napkin::util
