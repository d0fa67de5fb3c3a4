#pragma once
// Shared test helpers: paths and temporary directories.
#include <filesystem>
#include <string>

namespace napkin::test_support {

inline std::filesystem::path SourceDir() { return NAPKIN_SOURCE_DIR; }
inline std::filesystem::path FixturesDir() { return NAPKIN_FIXTURES_DIR; }

// A fresh, empty directory under the system temp dir, removed on destruction.
class TempDir {
 public:
  TempDir();
  ~TempDir();
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  const std::filesystem::path& path() const { return path_; }
  std::filesystem::path operator/(const std::string& name) const { return path_ / name; }

 private:
  std::filesystem::path path_;
};

}  // namespace napkin::test_support
