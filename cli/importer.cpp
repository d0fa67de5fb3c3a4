#include "cli/importer.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <utility>

#include "engine/error.h"
#include "formats/array_json.h"
#include "formats/channel_map.h"
#include "formats/content_hash.h"
#include "formats/csv.h"
#include "formats/isomme.h"
#include "formats/text.h"
#include "formats/uds1992.h"

namespace napkin::cli {
namespace fs = std::filesystem;

namespace {

bool IsHidden(const fs::path& path) {
  const std::string name = path.filename().string();
  return !name.empty() && name.front() == '.';
}

bool HasExtension(const fs::path& path, std::string_view extension) {
  return formats::EqualsIgnoreCase(path.extension().string(), extension);
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

ImportInput CsvInput(const fs::path& file) {
  ImportInput input;
  input.format = InputFormat::kCsv;
  input.name = file.stem().string();
  input.source = file;
  return input;
}

ImportInput IsoMmeInput(const fs::path& folder, const std::string& name) {
  ImportInput input;
  input.format = InputFormat::kIsoMme;
  input.name = name;
  input.source = folder;
  return input;
}

// Every test inside `folder` (not itself an ISO-MME test), in name order.
// `visited` holds the canonical folders seen, so a symbolic link back up the
// tree is not followed forever.
void DiscoverFolder(const fs::path& folder, std::vector<ImportInput>& found, std::set<fs::path>& visited) {
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
        DiscoverFolder(entry, found, visited);
      }
    } else if (HasExtension(entry, ".csv")) {
      found.push_back(CsvInput(entry));
    } else if (IsUdsFile(entry)) {
      uds.Add(entry, found);
    }
  }
}

// Error messages name the input: formats' messages usually do already.
std::string NamingSource(const std::string& message, const ImportInput& input) {
  if (message.find(input.source.string()) != std::string::npos) return message;
  for (const fs::path& file : input.files)
    if (message.find(file.string()) != std::string::npos) return message;
  return input.source.string() + ": " + message;
}

Eigen::Vector3d Triple(const std::vector<double>& values, const char* what) {
  if (values.empty()) return Eigen::Vector3d::Zero();
  if (values.size() != 3) throw InputError(std::string(what) + " needs three comma-separated numbers.");
  for (const double value : values)
    if (!std::isfinite(value)) throw InputError(std::string(what) + " needs finite numbers.");
  return {values[0], values[1], values[2]};
}

// What ImportTests resolves once for all inputs.
struct PreparedImport {
  engine::ArrayGeometry array;
  db::ArrayRecord array_record;
  std::optional<formats::ChannelMap> channel_map;  // given with --channel-map
  formats::ChannelMap default_map;                 // for ISO-MME without --channel-map
  engine::InitialState initial;
};

struct ReadTest {
  engine::TestSignals signals;
  std::vector<std::string> warnings;
  std::string channel_map;  // name of the map used, "" for CSV and Table 2-1 order
};

ReadTest ReadInput(const ImportInput& input, const PreparedImport& prepared, const std::string& test_id) {
  ReadTest read;
  switch (input.format) {
    case InputFormat::kCsv: {
      formats::CsvSignals csv = formats::ReadSignalsCsv(input.source, &prepared.array);
      read.signals = std::move(csv.signals);
      read.warnings = std::move(csv.warnings);
      break;
    }
    case InputFormat::kIsoMme: {
      const formats::ChannelMap& map = prepared.channel_map ? *prepared.channel_map : prepared.default_map;
      read.signals = formats::ReadIsoMmeSignals(input.source, prepared.array, map);
      read.channel_map = map.name;
      break;
    }
    case InputFormat::kUds1992: {
      const formats::ChannelMap* map = prepared.channel_map ? &*prepared.channel_map : nullptr;
      read.signals = formats::ReadUdsTest(input.files, prepared.array, map, test_id);
      if (map != nullptr) read.channel_map = map->name;
      break;
    }
  }
  return read;
}

ImportResult ImportOne(db::Catalogue& catalogue, const ImportInput& input, const PreparedImport& prepared,
                       const ImportOptions& options) {
  ImportResult result;
  result.test_id = options.test_id.value_or(input.name);
  const std::string& test_id = result.test_id;
  try {
    const std::string content_hash = ContentHash(input);
    if (catalogue.ExistsTestByHash(content_hash)) {
      result.outcome = ImportOutcome::kSkipped;
      result.message = test_id + ": already imported (same content), skipped.";
      return result;
    }
    if (const std::optional<db::TestId> existing = catalogue.FindTestByExternalId(test_id)) {
      const db::TestRecord record = catalogue.ReadTest(*existing);
      throw InputError("test '" + test_id + "' from '" + input.source.string() +
                       "' differs from the catalogue's test of that id (imported from '" +
                       record.source_path + "'); import it with another --test-id.");
    }

    // Read and check everything before writing anything.
    ReadTest read = ReadInput(input, prepared, test_id);
    std::vector<std::string> units;
    for (const std::string& slot : read.signals.slots) {
      const std::optional<std::size_t> sensor = prepared.array.FindSlot(slot);
      if (!sensor)
        throw InputError("channel '" + slot + "' is not a slot of array '" + prepared.array.name + "'.");
      units.push_back(prepared.array.sensors[*sensor].unit);
    }
    nlohmann::json metadata = nlohmann::json::object();
    metadata["format"] = InputFormatName(input.format);
    if (!read.channel_map.empty()) metadata["channel_map"] = read.channel_map;
    if (input.format == InputFormat::kUds1992) {
      nlohmann::json files = nlohmann::json::array();
      for (const fs::path& file : input.files) files.push_back(file.filename().string());
      metadata["files"] = std::move(files);
    }

    db::TestRecord record;
    record.external_id = test_id;
    record.series = options.series;
    record.variant = options.variant;
    record.metadata_json = metadata.dump();
    record.initial_state = prepared.initial;
    std::error_code error;
    const fs::path absolute = fs::absolute(input.source, error);
    record.source_path = (error ? input.source : absolute).lexically_normal().string();
    record.content_hash = content_hash;

    // The test is stored whole or not at all.
    db::Transaction transaction = catalogue.BeginTransaction();
    record.array_id = catalogue.WriteArray(prepared.array_record);
    const db::TestId test = catalogue.WriteTest(record);
    catalogue.WriteRawChannels(test, read.signals, units);
    transaction.Commit();

    result.outcome = ImportOutcome::kImported;
    result.message = test_id + ": imported from " + record.source_path + ".";
    for (std::string& warning : read.warnings) result.warnings.push_back(NamingSource(warning, input));
  } catch (const InputError& error) {
    result.outcome = ImportOutcome::kFailed;
    result.message = NamingSource(error.what(), input);
  }
  return result;
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
  }
  return "?";
}

Discovery DiscoverInputs(const std::vector<std::string>& paths) {
  Discovery discovery;
  UdsGroups uds;  // UDS-1992 files given one by one
  for (const std::string& text : paths) {
    const fs::path path = WithoutTrailingSeparator(text);
    std::error_code error;
    if (!fs::exists(path, error)) {
      discovery.errors.push_back("'" + text + "' does not exist.");
    } else if (fs::is_directory(path, error)) {
      if (HoldsMmeFile(path)) {
        discovery.inputs.push_back(IsoMmeInput(path, path.filename().string()));
        continue;
      }
      const std::size_t before = discovery.inputs.size();
      try {
        std::set<fs::path> visited;
        DiscoverFolder(path, discovery.inputs, visited);
      } catch (const InputError& list_error) {
        discovery.errors.push_back(list_error.what());
        continue;
      }
      if (discovery.inputs.size() == before)
        discovery.errors.push_back("folder '" + text +
                                   "' holds no test (no CSV file, ISO-MME test folder or UDS-1992 file).");
    } else if (HasExtension(path, ".csv")) {
      discovery.inputs.push_back(CsvInput(path));
    } else if (HasExtension(path, ".mme")) {
      discovery.inputs.push_back(
          IsoMmeInput(path.has_parent_path() ? path.parent_path() : fs::path("."), path.stem().string()));
    } else if (IsUdsFile(path)) {
      uds.Add(path, discovery.inputs);
    } else {
      discovery.errors.push_back(
          "'" + text +
          "' is not a test: expected a CSV file (.csv), an ISO-MME test folder or .mme "
          "file, a UDS-1992 channel file (.001 ...) or a folder of tests.");
    }
  }
  UdsGroups::SortMembers(discovery.inputs);
  return discovery;
}

std::string ContentHash(const ImportInput& input) {
  if (input.format != InputFormat::kUds1992) return formats::HashPath(input.source);
  formats::Sha256 hash;
  hash.Update("uds-1992 group\n");
  for (const fs::path& file : input.files) hash.Update(formats::HashPath(file) + "\n");
  return hash.HexDigest();
}

std::string ImportReport::SummaryLine() const {
  auto tests = [](std::int64_t n) { return std::to_string(n) + (n == 1 ? " test" : " tests"); };
  std::string line =
      "imported " + tests(imported) + ", skipped " + std::to_string(skipped) + " already present";
  if (failed > 0) line += ", " + std::to_string(failed) + " failed";
  return line + ".";
}

ImportReport ImportTests(db::Catalogue& catalogue, const std::vector<std::string>& paths,
                         const ImportOptions& options, const ImportProgress& progress) {
  PreparedImport prepared;
  prepared.array = formats::LoadArray(options.array);
  prepared.array_record = MakeArrayRecord(prepared.array);
  if (!options.channel_map.empty()) prepared.channel_map = formats::LoadChannelMap(options.channel_map);
  prepared.default_map = formats::LoadChannelMap("default");
  prepared.initial.orientation_rad = Triple(options.orientation_rad, "--orientation");
  prepared.initial.velocity_fixed_mps = Triple(options.initial_velocity_mps, "--initial-velocity");
  if (options.test_id && options.test_id->empty()) throw ImportUsageError("--test-id must not be empty.");

  const Discovery discovery = DiscoverInputs(paths);
  if (options.test_id && discovery.inputs.size() + discovery.errors.size() > 1)
    throw ImportUsageError("--test-id names one test, but the paths hold " +
                           std::to_string(discovery.inputs.size() + discovery.errors.size()) + " inputs.");

  ImportReport report;
  const std::size_t total = discovery.errors.size() + discovery.inputs.size();
  std::size_t done = 0;
  for (const std::string& error : discovery.errors) {
    ImportResult result;
    result.message = error;
    ++report.failed;
    report.results.push_back(std::move(result));
    if (progress) progress(++done, total, report.results.back());
  }
  for (const ImportInput& input : discovery.inputs) {
    ImportResult result = ImportOne(catalogue, input, prepared, options);
    switch (result.outcome) {
      case ImportOutcome::kImported:
        ++report.imported;
        break;
      case ImportOutcome::kSkipped:
        ++report.skipped;
        break;
      case ImportOutcome::kFailed:
        ++report.failed;
        break;
    }
    report.results.push_back(std::move(result));
    if (progress) progress(++done, total, report.results.back());
  }
  return report;
}

}  // namespace napkin::cli
