#pragma once
// How much memory this process may still take, for refusing work that cannot
// fit before it starts rather than failing with std::bad_alloc (or the
// kernel's OOM killer) minutes into it: the Python module's transform
// (python/) compares engine::ProcessTestBytes with it.
#include <cstdint>
#include <optional>
#include <string>

namespace napkin::util {

struct AvailableMemory {
  std::uint64_t bytes = 0;
  std::string source;  // what limits it, for the sentence: "MemAvailable in /proc/meminfo", ...
};

// The least of the limits that apply: the kernel's estimate of memory
// available without swapping (MemAvailable in /proc/meminfo), the control
// group's memory.max less its memory.current (cgroup v2), and the address
// space limit (RLIMIT_AS, `ulimit -v`) less the address space in use
// (VmSize in /proc/self/status). nullopt where none can be read (not Linux).
std::optional<AvailableMemory> FindAvailableMemory();

// "about 14.2 GB": `bytes` in decimal units with three significant digits.
std::string FormatBytes(std::uint64_t bytes);

// The sentence refusing work that needs about `needed_bytes` ("... needs
// about 31.6 GB of memory, more than the 19.8 GB available (MemAvailable in
// /proc/meminfo)") when it exceeds `available`, else nullopt. `what` starts
// it ("napkin.transform: 100000000 samples of array \"denton-3222\"").
std::optional<std::string> MemoryShortfall(const std::string& what, std::uint64_t needed_bytes,
                                           const std::optional<AvailableMemory>& available);

}  // namespace napkin::util
