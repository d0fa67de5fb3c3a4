#pragma once
// Writes zip archives for the tests with libzip (never committed binaries):
// the members of an ISO-MME or UDS-1992 test folder, or hand-made members
// with unsafe names.
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

namespace napkin::test_support {

struct ZipEntry {
  std::string name;
  std::string bytes;
};

// Writes `entries` (deflated, or stored when `store`) as the zip archive `path`.
void WriteZip(const std::filesystem::path& path, const std::vector<ZipEntry>& entries, bool store = false);

// Every regular file under `folder`, named relative to `prefix` ("" for the
// folder itself, or e.g. "T1/" to keep a top folder), in name order.
std::vector<ZipEntry> FolderEntries(const std::filesystem::path& folder, const std::string& prefix = "");

}  // namespace napkin::test_support
