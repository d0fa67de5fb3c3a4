// Every file of the project that a source file's comments or includes cite exists (issue 43
// point 9: serve/api.h sent the reader to an http_service header in serve/, never there).
#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <set>
#include <string>
#include <vector>

#include "tests/support/run_command.h"
#include "tests/support/test_support.h"

namespace napkin::test_support {
namespace {

namespace fs = std::filesystem;

// The paths under the project's folders that `text` names, e.g. "serve/http_server.h",
// "docs/serve.md": a folder name and '/' after a character that cannot be in a path, then path
// characters ending in one of the extensions the project's files have.
std::vector<std::string> CitedPaths(const std::string& text) {
  static const std::vector<std::string> kFolders = {
      "app",    "bench",   "cli",     "common", "config", "db",    "deploy",
      "docs",   "engine",  "formats", "fuzz",   "ingest", "jobs",  "packaging",
      "python", "records", "schema",  "serve",  "synth",  "tests", "util"};
  static const std::vector<std::string> kExtensions = {".h", ".cpp", ".md", ".sql", ".json", ".sh", ".py"};
  const auto path_char = [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '.' || c == '/' || c == '-';
  };
  std::vector<std::string> paths;
  for (const std::string& folder : kFolders) {
    const std::string start = folder + "/";
    for (std::size_t at = text.find(start); at != std::string::npos; at = text.find(start, at + 1)) {
      if (at > 0 && (path_char(text[at - 1]) || text[at - 1] == '<')) continue;  // inside a path, <sys/...>
      std::size_t end = at + start.size();
      while (end < text.size() && path_char(text[end])) ++end;
      std::string path = text.substr(at, end - at);
      while (!path.empty() && (path.back() == '.' || path.back() == '/' || path.back() == '-'))
        path.pop_back();
      for (const std::string& extension : kExtensions)
        if (path.ends_with(extension)) {
          paths.push_back(path);
          break;
        }
    }
  }
  return paths;
}

// A placeholder in capitals stands for any file ("config/limits/NAME.json").
bool IsPlaceholder(const std::string& path) {
  const std::string name = fs::path(path).stem().string();
  return !name.empty() && std::all_of(name.begin(), name.end(), [](char c) {
    return std::isupper(static_cast<unsigned char>(c)) || std::isdigit(static_cast<unsigned char>(c)) ||
           c == '_';
  });
}

TEST(CitedFiles, EveryProjectFileASourceCitesExists) {
  const fs::path root = SourceDir();
  std::set<std::string> missing;
  std::size_t sources = 0, citations = 0;
  for (const fs::path folder : {"app", "cli", "common", "db", "engine", "formats", "fuzz", "ingest", "jobs",
                                "python", "records", "serve", "synth", "tests", "util"}) {
    for (const fs::directory_entry& entry : fs::recursive_directory_iterator(root / folder)) {
      const std::string extension = entry.path().extension().string();
      if (!entry.is_regular_file() || (extension != ".h" && extension != ".cpp")) continue;
      ++sources;
      for (const std::string& path : CitedPaths(ReadText(entry.path()))) {
        if (IsPlaceholder(path)) continue;
        ++citations;
        if (!fs::exists(root / path))
          missing.insert(fs::relative(entry.path(), root).string() + " cites " + path);
      }
    }
  }
  EXPECT_GT(sources, 100u);
  EXPECT_GT(citations, 1000u);
  EXPECT_EQ(missing, std::set<std::string>{});
}

}  // namespace
}  // namespace napkin::test_support
