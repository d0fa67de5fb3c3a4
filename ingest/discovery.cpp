#include "ingest/discovery.h"

#include <algorithm>
#include <cerrno>
#include <map>
#include <set>
#include <tuple>
#include <utility>

#include "common/error.h"
#include "util/text.h"

namespace napkin::ingest {
namespace fs = std::filesystem;

namespace {

bool IsHidden(const fs::path& path) {
  const std::string name = path.filename().string();
  return !name.empty() && name.front() == '.';
}

// "data/tests/" -> "data/tests" so that filename() names the folder.
fs::path WithoutTrailingSeparator(const fs::path& path) {
  fs::path normal = path.lexically_normal();
  if (normal.has_parent_path() && normal.filename().empty()) normal = normal.parent_path();
  return normal;
}

// Why `path` (a file napkin would read) cannot be a test, or "" when it is a
// regular file: a FIFO named *.csv would block, a link to /dev/zero never end.
std::string NotARegularFile(const fs::path& path) {
  std::error_code error;
  const fs::file_status status = fs::status(path, error);
  // Appended, not `"'" + temporary` (GCC 12's false -Wrestrict, util/text.h InQuotes).
  std::string named = "'";
  named += path.string();
  named += '\'';
  if (error && error.value() == ELOOP)
    return named + " is a loop of symbolic links; point the link at a real file.";
  if (error) return named + " cannot be read (" + error.message() + ").";
  if (!fs::is_regular_file(status))
    return named + " is not a regular file (a FIFO, device or socket); napkin reads only regular files.";
  return "";
}

// The tests of the files found, in the order found: kFileGroup files join
// the group of their folder and stem, whose place is that of its first file.
class FoundTests {
 public:
  explicit FoundTests(Discovery& discovery) : discovery_(discovery) {}

  // A file some format names: its test, or the sentence why it is none.
  void AddFile(const fs::path& file) {
    if (const std::string problem = NotARegularFile(file); !problem.empty()) {
      discovery_.errors.push_back(problem);
      return;
    }
    std::optional<InputFormat> format;
    try {
      format = FormatOfFile(file);
    } catch (const InputError& error) {
      discovery_.errors.push_back(error.what());
      return;
    }
    if (!format) return;
    const InputFormatEntry& entry = FormatEntry(*format);
    switch (entry.span) {
      case TestSpan::kFile:
        discovery_.inputs.push_back({*format, file.stem().string(), file, {}});
        return;
      case TestSpan::kFolder:
        AddFolder(*format, file.has_parent_path() ? file.parent_path() : fs::path("."), file.stem().string());
        return;
      case TestSpan::kFileGroup:
        break;
    }
    const auto key = std::make_tuple(*format, file.parent_path().string(), file.stem().string());
    auto [it, inserted] = groups_.try_emplace(key, discovery_.inputs.size());
    if (inserted)
      discovery_.inputs.push_back(
          {*format, file.stem().string(), file.parent_path() / (file.stem().string() + ".*"), {}});
    discovery_.inputs[it->second].files.push_back(file);
  }

  void AddFolder(InputFormat format, const fs::path& folder, const std::string& name) {
    discovery_.inputs.push_back({format, name, folder, {}});
  }

  // Every test inside `folder` (itself no test), in name order. `visited`
  // holds the canonical folders seen, so a symbolic link back up the tree
  // is not followed forever.
  void AddFolderContents(const fs::path& folder, std::set<fs::path>& visited) {
    std::error_code error;
    const fs::path canonical = fs::canonical(folder, error);
    if (!error && !visited.insert(canonical).second) return;
    std::vector<fs::path> entries;
    for (const auto& entry : fs::directory_iterator(folder, error))
      if (!IsHidden(entry.path())) entries.push_back(entry.path());
    if (error) throw InputError("cannot list folder '" + folder.string() + "': " + error.message() + ".");
    std::sort(entries.begin(), entries.end());
    for (const fs::path& entry : entries) {
      if (fs::is_directory(entry, error)) {
        if (const std::optional<InputFormat> format = FormatOfFolder(entry))
          AddFolder(*format, entry, entry.filename().string());
        else
          AddFolderContents(entry, visited);
      } else if (NamesSomeTest(entry)) {
        AddFile(entry);
      }
    }
  }

  // Sorts each group's files by name (UDS-1992: the report's Table 2-1 order when no map is given).
  void SortGroups() {
    for (const auto& [key, slot] : groups_)
      std::sort(
          discovery_.inputs[slot].files.begin(), discovery_.inputs[slot].files.end(),
          [](const fs::path& a, const fs::path& b) { return a.filename().string() < b.filename().string(); });
  }

 private:
  Discovery& discovery_;
  std::map<std::tuple<InputFormat, std::string, std::string>, std::size_t> groups_;
};

}  // namespace

Discovery DiscoverInputs(const std::vector<std::string>& paths) {
  Discovery discovery;
  FoundTests found(discovery);
  for (const std::string& text : paths) {
    const fs::path path = WithoutTrailingSeparator(text);
    std::error_code error;
    const bool exists = fs::exists(path, error);
    if (error && error.value() == ELOOP) {
      discovery.errors.push_back("'" + text +
                                 "' is a loop of symbolic links; point the link at a real file.");
    } else if (!exists) {
      discovery.errors.push_back("'" + text + "' does not exist.");
    } else if (fs::is_directory(path, error)) {
      if (const std::optional<InputFormat> format = FormatOfFolder(path)) {
        found.AddFolder(*format, path, path.filename().string());
        continue;
      }
      const std::size_t before = discovery.inputs.size();
      const std::size_t errors_before = discovery.errors.size();
      try {
        std::set<fs::path> visited;
        found.AddFolderContents(path, visited);
      } catch (const InputError& list_error) {
        discovery.errors.push_back(list_error.what());
        continue;
      }
      if (discovery.inputs.size() == before && errors_before == discovery.errors.size())
        discovery.errors.push_back("folder '" + text + "' holds no test (" + NoTestOfAnyFormat() + ").");
    } else if (NamesSomeTest(path)) {
      found.AddFile(path);
    } else {
      discovery.errors.push_back("'" + text + "' is not a test: expected " + WhatToGive() +
                                 ", or a folder of tests.");
    }
  }
  found.SortGroups();
  return discovery;
}

}  // namespace napkin::ingest
