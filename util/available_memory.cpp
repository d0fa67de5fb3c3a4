#include "util/available_memory.h"

#include <sys/resource.h>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string_view>

namespace napkin::util {
namespace {

// The value of `key` ("MemAvailable:") in a /proc file of "Key: value kB"
// lines, in bytes.
std::optional<std::uint64_t> ProcKibibytes(const char* path, std::string_view key) {
  std::ifstream file(path);
  std::string line;
  while (std::getline(file, line)) {
    if (line.compare(0, key.size(), key) != 0) continue;
    std::istringstream value(line.substr(key.size()));
    std::uint64_t kib = 0;
    if (value >> kib) return kib * 1024;
    return std::nullopt;
  }
  return std::nullopt;
}

// A cgroup v2 interface file holding one number ("max" is no limit).
std::optional<std::uint64_t> CgroupNumber(const std::string& path) {
  std::ifstream file(path);
  std::uint64_t value = 0;
  if (file >> value) return value;
  return std::nullopt;
}

// This process's cgroup v2 folder ("0::/user.slice/..." in /proc/self/cgroup).
std::optional<std::string> CgroupFolder() {
  std::ifstream file("/proc/self/cgroup");
  std::string line;
  while (std::getline(file, line))
    if (line.rfind("0::", 0) == 0) return "/sys/fs/cgroup" + line.substr(3);
  return std::nullopt;
}

void KeepLeast(std::optional<AvailableMemory>& least, std::uint64_t bytes, std::string source) {
  if (!least || bytes < least->bytes) least = AvailableMemory{bytes, std::move(source)};
}

}  // namespace

std::optional<AvailableMemory> FindAvailableMemory() {
  std::optional<AvailableMemory> least;
  if (const auto bytes = ProcKibibytes("/proc/meminfo", "MemAvailable:"))
    KeepLeast(least, *bytes, "MemAvailable in /proc/meminfo");
  if (const auto folder = CgroupFolder()) {
    const auto limit = CgroupNumber(*folder + "/memory.max");
    const auto used = CgroupNumber(*folder + "/memory.current");
    if (limit && used)
      KeepLeast(least, *limit > *used ? *limit - *used : 0,
                "the control group's memory.max less memory.current");
  }
  rlimit address_space{};
  if (getrlimit(RLIMIT_AS, &address_space) == 0 && address_space.rlim_cur != RLIM_INFINITY) {
    const std::uint64_t used = ProcKibibytes("/proc/self/status", "VmSize:").value_or(0);
    const std::uint64_t limit = address_space.rlim_cur;
    KeepLeast(least, limit > used ? limit - used : 0,
              "the address-space limit RLIMIT_AS (ulimit -v) less VmSize");
  }
  return least;
}

std::string FormatBytes(std::uint64_t bytes) {
  static constexpr const char* kUnits[] = {"bytes", "kB", "MB", "GB", "TB", "PB", "EB"};
  auto value = static_cast<double>(bytes);
  std::size_t unit = 0;
  while (value >= 999.5 && unit + 1 < std::size(kUnits)) {
    value /= 1000.0;
    ++unit;
  }
  char text[32];
  if (unit == 0)
    std::snprintf(text, sizeof text, "%llu bytes", static_cast<unsigned long long>(bytes));
  else
    std::snprintf(text, sizeof text, "%.*f %s",
                  value < 9.995   ? 2
                  : value < 99.95 ? 1
                                  : 0,
                  value, kUnits[unit]);
  return text;
}

std::optional<std::string> MemoryShortfall(const std::string& what, std::uint64_t needed_bytes,
                                           const std::optional<AvailableMemory>& available) {
  if (!available || needed_bytes <= available->bytes) return std::nullopt;
  return what + " needs about " + FormatBytes(needed_bytes) + " of memory, more than the " +
         FormatBytes(available->bytes) + " available (" + available->source + ").";
}

}  // namespace napkin::util
