#include "ingest/discovery.h"

#include <algorithm>
#include <cerrno>
#include <map>
#include <set>
#include <utility>

#include "common/error.h"
#include "formats/uds1992.h"
#include "util/text.h"

namespace napkin::ingest {
namespace fs = std::filesystem;

namespace {

bool IsHidden(const fs::path& path) {
  const std::string name = path.filename().string();
  return !name.empty() && name.front() == '.';
}

bool HasExtension(const fs::path& path, std::string_view extension) {
  return util::EqualsIgnoreCase(path.extension().string(), extension);
}

// UDS-1992 channel files are numbered: v0001.001 ... v0001.009.
bool IsUdsFile(const fs::path& path) {
  const std::string extension = path.extension().string();
  return extension.size() == 4 &&
         std::all_of(extension.begin() + 1, extension.end(), [](char c) { return c >= '0' && c <= '9'; });
}

bool HoldsMmeFile(const fs::path& folder) {
  std::error_code error;
  for (const auto& entry : fs::directory_iterator(folder, error))
    if (entry.is_regular_file(error) && HasExtension(entry.path(), ".mme")) return true;
  return false;
}

// "data/tests/" -> "data/tests" so that filename() names the folder.
fs::path WithoutTrailingSeparator(const fs::path& path) {
  fs::path normal = path.lexically_normal();
  if (normal.has_parent_path() && normal.filename().empty()) normal = normal.parent_path();
  return normal;
}

// UDS-1992 files collected from the paths, grouped by folder and stem when
// discovery ends; `slot` is the index in `inputs` reserved for the group.
class UdsGroups {
 public:
  void Add(const fs::path& file, std::vector<ImportInput>& inputs) {
    const auto key = std::make_pair(file.parent_path().string(), file.stem().string());
    auto [it, inserted] = slots_.try_emplace(key, inputs.size());
    if (inserted) {
      ImportInput input;
      input.format = InputFormat::kUds1992;
      input.name = file.stem().string();
      input.source = file.parent_path() / (file.stem().string() + ".*");
      inputs.push_back(std::move(input));
    }
    inputs[it->second].files.push_back(file);
  }

  // Sorts each group's files by name (the report's Table 2-1 order when no map is given).
  static void SortMembers(std::vector<ImportInput>& inputs) {
    for (ImportInput& input : inputs)
      if (input.format == InputFormat::kUds1992)
        for (auto& [stem, files] : formats::GroupUdsFilesByStem(input.files)) input.files = std::move(files);
  }

 private:
  std::map<std::pair<std::string, std::string>, std::size_t> slots_;
};

// A CSV file or a zip archive: one input, named after the file.
ImportInput FileInput(InputFormat format, const fs::path& file) {
  return {format, file.stem().string(), file, {}};
}

ImportInput IsoMmeInput(const fs::path& folder, const std::string& name) {
  return {InputFormat::kIsoMme, name, folder, {}};
}

// Why `path` (a file napkin would read) cannot be a test, or "" when it is a
// regular file: a FIFO named *.csv would block, a link to /dev/zero never end.
std::string NotARegularFile(const fs::path& path) {
  std::error_code error;
  const fs::file_status status = fs::status(path, error);
  if (error && error.value() == ELOOP)
    return "'" + path.string() + "' is a loop of symbolic links; point the link at a real file.";
  if (error) return "'" + path.string() + "' cannot be read (" + error.message() + ").";
  if (!fs::is_regular_file(status))
    return "'" + path.string() + "' is not a regular file (a FIFO, device or socket); napkin reads only " +
           "regular files.";
  return "";
}

// Every test inside `folder` (not itself an ISO-MME test), in name order.
// `visited` holds the canonical folders seen, so a symbolic link back up the
// tree is not followed forever. Entries that look like tests but are not
// regular files (or are broken or looping links) are reported in `errors`.
void DiscoverFolder(const fs::path& folder, std::vector<ImportInput>& found, std::set<fs::path>& visited,
                    std::vector<std::string>& errors) {
  std::error_code error;
  const fs::path canonical = fs::canonical(folder, error);
  if (!error && !visited.insert(canonical).second) return;
  std::vector<fs::path> entries;
  for (const auto& entry : fs::directory_iterator(folder, error))
    if (!IsHidden(entry.path())) entries.push_back(entry.path());
  if (error) throw InputError("cannot list folder '" + folder.string() + "': " + error.message() + ".");
  std::sort(entries.begin(), entries.end());
  UdsGroups uds;
  for (const fs::path& entry : entries) {
    if (fs::is_directory(entry, error)) {
      if (HoldsMmeFile(entry)) {
        found.push_back(IsoMmeInput(entry, entry.filename().string()));
      } else {
        DiscoverFolder(entry, found, visited, errors);
      }
    } else if (HasExtension(entry, ".csv") || IsUdsFile(entry) || HasExtension(entry, ".zip")) {
      if (const std::string problem = NotARegularFile(entry); !problem.empty()) {
        errors.push_back(problem);
      } else if (HasExtension(entry, ".csv")) {
        found.push_back(FileInput(InputFormat::kCsv, entry));
      } else if (HasExtension(entry, ".zip")) {
        found.push_back(FileInput(InputFormat::kZipArchive, entry));
      } else {
        uds.Add(entry, found);
      }
    }
  }
}

}  // namespace

const char* InputFormatName(InputFormat format) {
  switch (format) {
    case InputFormat::kCsv:
      return "csv";
    case InputFormat::kIsoMme:
      return "iso-mme";
    case InputFormat::kUds1992:
      return "uds-1992";
    case InputFormat::kZipArchive:
      return "zip";
  }
  return "?";
}

Discovery DiscoverInputs(const std::vector<std::string>& paths) {
  Discovery discovery;
  UdsGroups uds;  // UDS-1992 files given one by one
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
      if (HoldsMmeFile(path)) {
        discovery.inputs.push_back(IsoMmeInput(path, path.filename().string()));
        continue;
      }
      const std::size_t before = discovery.inputs.size();
      const std::size_t errors_before = discovery.errors.size();
      try {
        std::set<fs::path> visited;
        DiscoverFolder(path, discovery.inputs, visited, discovery.errors);
      } catch (const InputError& list_error) {
        discovery.errors.push_back(list_error.what());
        continue;
      }
      if (discovery.inputs.size() == before && errors_before == discovery.errors.size())
        discovery.errors.push_back(
            "folder '" + text +
            "' holds no test (no CSV file, ISO-MME test folder, UDS-1992 file or zip archive).");
    } else if (const std::string problem = NotARegularFile(path);
               !problem.empty() &&
               (HasExtension(path, ".csv") || IsUdsFile(path) || HasExtension(path, ".zip"))) {
      discovery.errors.push_back(problem);
    } else if (HasExtension(path, ".csv")) {
      discovery.inputs.push_back(FileInput(InputFormat::kCsv, path));
    } else if (HasExtension(path, ".mme")) {
      discovery.inputs.push_back(
          IsoMmeInput(path.has_parent_path() ? path.parent_path() : fs::path("."), path.stem().string()));
    } else if (IsUdsFile(path)) {
      uds.Add(path, discovery.inputs);
    } else if (HasExtension(path, ".zip")) {
      discovery.inputs.push_back(FileInput(InputFormat::kZipArchive, path));
    } else {
      discovery.errors.push_back(
          "'" + text +
          "' is not a test: expected a CSV file (.csv), an ISO-MME test folder or .mme "
          "file, a UDS-1992 channel file (.001 ...), a zip archive of one test (.zip) or a folder of tests.");
    }
  }
  UdsGroups::SortMembers(discovery.inputs);
  return discovery;
}

}  // namespace napkin::ingest
