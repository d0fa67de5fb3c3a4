#include "formats/file_hash.h"

#include <algorithm>
#include <system_error>
#include <vector>

#include "common/error.h"
#include "formats/json_file.h"
#include "util/sha256.h"

namespace napkin::formats {

namespace {

void HashFileInto(const std::filesystem::path& path, util::Sha256& hash) {
  // Only regular files of at most the data ceiling (a FIFO or /dev/zero
  // behind a link would block or never end).
  ReadFileInChunks(path, kMaxDataFileBytes, [&](std::string_view chunk) { hash.Update(chunk); });
}

}  // namespace

std::string HashPath(const std::filesystem::path& path) {
  util::Sha256 hash;
  std::error_code error;
  if (std::filesystem::is_directory(path, error)) {
    std::vector<std::filesystem::path> files;
    for (const auto& entry : std::filesystem::recursive_directory_iterator(path, error))
      if (entry.is_regular_file()) files.push_back(entry.path());
    if (error) throw InputError("cannot list folder '" + path.string() + "'.");
    std::sort(files.begin(), files.end());
    for (const auto& file : files) {
      const std::string relative = std::filesystem::relative(file, path).generic_string();
      hash.Update(relative);
      hash.Update(std::string_view("\0", 1));
      HashFileInto(file, hash);
    }
  } else {
    HashFileInto(path, hash);
  }
  return hash.HexDigest();
}

}  // namespace napkin::formats
