#include "cli/demo_folder.h"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>
#include <system_error>
#include <vector>

#include "common/error.h"
#include "util/atomic_file.h"
#include "util/output_destination.h"

namespace napkin::cli {
namespace {

namespace fs = std::filesystem;

constexpr const char* kStampName = ".napkin-demo";
constexpr const char* kStampHeader =
    "# napkin demo: the files below were written by `napkin demo`, which replaces them on its next run.";
// The SQLite side files of the demo catalogue.
constexpr const char* kDbSideSuffixes[] = {"-wal", "-shm", "-journal"};

// The files a previous demo's stamp lists (empty without a stamp).
std::vector<fs::path> StampedFiles(const fs::path& dir) {
  std::vector<fs::path> files;
  std::ifstream stamp(dir / kStampName);
  for (std::string line; std::getline(stamp, line);)
    if (!line.empty() && line.front() != '#') {
      const fs::path file = fs::path(line).lexically_normal();
      // Only names inside the folder ("../x" or "/x" in a tampered stamp is not the demo's).
      if (file.is_relative() && !file.empty() && *file.begin() != "..") files.push_back(file);
    }
  return files;
}

// Whether `relative` is one of `files`, a SQLite side file of the demo's
// catalogue `catalogue`, or a temporary file napkin's atomic writer left for
// one of them (util/atomic_file.h: ".NAME.tmp-...", left only when killed).
bool IsDemoFile(const fs::path& relative, const std::vector<fs::path>& files, const fs::path& catalogue) {
  for (const fs::path& file : files) {
    if (relative == file) return true;
    if (relative.parent_path() == file.parent_path() &&
        util::IsTemporaryNameOf(relative.filename().string(), file.filename().string()))
      return true;
  }
  for (const char* suffix : kDbSideSuffixes)
    if (relative == fs::path(catalogue.string() + suffix)) return true;
  return false;
}

bool IsFolderOfDemoFiles(const fs::path& relative, const std::vector<fs::path>& files) {
  for (const fs::path& file : files)
    for (fs::path folder = file.parent_path(); !folder.empty(); folder = folder.parent_path())
      if (folder == relative) return true;
  return false;
}

}  // namespace

bool PrepareDemoFolder(const fs::path& dir, const fs::path& catalogue) {
  std::error_code error;
  const fs::file_status status = fs::symlink_status(dir, error);
  if (!fs::exists(status)) {
    fs::create_directories(dir, error);
    if (error)
      throw InputError("cannot create the demo folder '" + dir.string() + "': " + error.message() + ".");
    return false;
  }
  if (!fs::is_directory(fs::status(dir, error)))
    throw InputError("'" + dir.string() + "' is not a folder; name a new folder for the demo.");
  const std::vector<fs::path> stamped = StampedFiles(dir);
  const bool has_stamp = fs::is_regular_file(fs::symlink_status(dir / kStampName, error));
  std::vector<fs::path> files, folders;  // the earlier demo's, all of the folder's entries
  for (auto entry = fs::recursive_directory_iterator(dir, error);
       !error && entry != fs::recursive_directory_iterator(); entry.increment(error)) {
    const fs::path relative = entry->path().lexically_relative(dir);
    const fs::file_status entry_status = entry->symlink_status(error);
    bool ours = false;
    if (fs::is_directory(entry_status)) {
      ours = has_stamp && IsFolderOfDemoFiles(relative, stamped);
      if (ours) folders.push_back(relative);
    } else if (fs::is_regular_file(entry_status)) {
      // The stamp's own temporary file, left by a demo killed while writing
      // it, is napkin's whether or not a stamp is there yet.
      const bool stamp_temporary = util::IsTemporaryNameOf(relative.string(), kStampName);
      ours = stamp_temporary ||
             (has_stamp && (relative == kStampName || IsDemoFile(relative, stamped, catalogue)));
      // The stamp stays until the new one is renamed over it: a demo killed
      // from here on still leaves a stamp listing what it wrote.
      if (ours && relative != kStampName) files.push_back(relative);
    }
    if (!ours)
      throw InputError("the demo folder '" + dir.string() + "' holds '" + entry->path().string() +
                       "', which no earlier demo's stamp (" + kStampName +
                       ") lists; the demo writes only into a new or empty folder or one with nothing but its "
                       "own earlier output (name another --out).");
  }
  if (error) throw InputError("cannot list the demo folder '" + dir.string() + "': " + error.message() + ".");

  const bool had_catalogue = fs::exists(dir / catalogue, error);
  for (const fs::path& file : files) fs::remove(dir / file, error);
  // Deepest first; a folder is removed only when empty.
  std::sort(folders.rbegin(), folders.rend());
  for (const fs::path& folder : folders) fs::remove(dir / folder, error);
  return had_catalogue;
}

void WriteDemoStamp(const fs::path& dir, const std::vector<fs::path>& files) {
  util::WriteFileAtomically(dir / kStampName, [&](util::AtomicFile& file) {
    file.Write(std::string(kStampHeader) + "\n");
    for (const fs::path& path : files) file.Write(path.generic_string() + "\n");
  });
}

}  // namespace napkin::cli
