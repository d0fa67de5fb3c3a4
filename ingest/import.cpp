#include "ingest/import.h"

#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <utility>

#include "common/error.h"
#include "engine/rotation.h"
#include "formats/array_json.h"
#include "formats/channel_map.h"
#include "formats/csv.h"
#include "ingest/content_hash.h"
#include "ingest/dummy_heads.h"
#include "ingest/store.h"
#include "ingest/zip_input.h"
#include "records/array_record.h"
#include "util/sha256.h"
#include "util/text.h"
#include "util/utf8.h"

namespace napkin::ingest {
namespace fs = std::filesystem;

namespace {

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
  // --array; without it each input's channel codes define its array (ingest/array_from_codes.h).
  std::optional<engine::ArrayGeometry> array;
  std::optional<db::ArrayRow> array_record;
  std::optional<formats::ChannelMap> channel_map;  // given with --channel-map
  formats::ChannelMap default_map;                 // for inputs of channels without --channel-map
  formats::CsvColumnMap csv_columns;               // the map's "column" entries, then --column
  engine::InitialState initial;
  bool velocity_given = false;  // --initial-velocity
};

// The test-level information as metadata (docs/formats.md "Test information"): empty fields left out.
nlohmann::json TestInfoJson(const formats::TestInfo& info, const std::string& position) {
  nlohmann::json json = nlohmann::json::object();
  for (const auto& [key, value] :
       {std::pair<const char*, const std::string*>{"test_number", &info.test_number},
        {"title", &info.title},
        {"vehicle", &info.vehicle},
        {"dummy", &info.dummy},
        {"position", &position},
        {"date", &info.date},
        {"laboratory", &info.laboratory}})
    if (!value->empty()) json[key] = *value;
  // The sensors feeding the slots (DTS SLICEWare: serial, hardware anti-aliasing filter in Hz).
  if (!info.sensors.empty()) {
    nlohmann::json sensors = nlohmann::json::array();
    for (const formats::SensorInfo& sensor : info.sensors) {
      nlohmann::json entry = {{"slot", sensor.slot}};
      if (!sensor.code.empty()) entry["code"] = sensor.code;
      if (!sensor.serial.empty()) entry["serial"] = sensor.serial;
      if (!sensor.hardware_filter.empty()) {
        const std::optional<double> hz = util::ParseDouble(sensor.hardware_filter);
        if (hz && std::isfinite(*hz))
          entry["hardware_filter_hz"] = *hz;
        else
          entry["hardware_filter"] = sensor.hardware_filter;
      }
      sensors.push_back(std::move(entry));
    }
    json["sensors"] = std::move(sensors);
  }
  return json;
}

// Names of an unknown encoding are refused, never guessed (docs/formats.md
// "Text encoding"): the path stored as the test's source and, for UDS-1992,
// the file names stored in its metadata must be UTF-8.
void CheckPathsAreUtf8(const ImportInput& input) {
  std::error_code error;
  const fs::path absolute = fs::absolute(input.source, error);
  std::vector<fs::path> paths = {error ? input.source : absolute};
  paths.insert(paths.end(), input.files.begin(), input.files.end());
  for (const fs::path& path : paths)
    if (!util::IsValidUtf8(path.string()))
      throw InputError("'" + util::Abbreviated(path.string(), util::kQuotedInputLongChars) +
                       "': the path is not valid UTF-8 (the bytes that are not are shown as \\xHH), and "
                       "napkin stores names in UTF-8 only; rename it, e.g. with `convmv -f latin1 -t utf8 "
                       "--notest`, and import it again.");
}

ImportResult Failed(const std::string& test_id, std::string message) {
  ImportResult result;
  result.outcome = ImportOutcome::kFailed;
  result.test_id = test_id;
  result.message = std::move(message);
  return result;
}

// Stores one dummy head of `input`, read for array `array` (its record `array_record`); the
// input's content hash was not found.
ImportResult StoreHead(db::Catalogue& catalogue, const ImportInput& input, const PreparedImport& prepared,
                       const ImportOptions& options, const InputHeads& read, const db::ArrayRow& array_record,
                       HeadSignals& head, const std::string& test_id, const std::string& content_hash) {
  ImportResult result;
  result.test_id = test_id;
  auto skipped = [&] {
    result.outcome = ImportOutcome::kSkipped;
    result.message = test_id + ": already imported (same content), skipped.";
    return result;
  };
  if (catalogue.ExistsTestByHash(content_hash)) return skipped();
  std::error_code error;
  const fs::path absolute = fs::absolute(input.source, error);
  const std::string source_path = (error ? input.source : absolute).lexically_normal().string();
  std::optional<db::TestId> replacing;
  if (const std::optional<db::TestId> existing = catalogue.FindTestByExternalId(test_id)) {
    const db::TestRow record = catalogue.ReadTest(*existing);
    // Another import of the same input (a concurrent process) stored it
    // between the two look-ups: present, not failed.
    if (record.content_hash == content_hash) return skipped();
    if (!options.supersede_changed_source || record.source_path != source_path)
      throw InputError("test '" + test_id + "' from '" + input.source.string() +
                       "' differs from the catalogue's test of that id (imported from '" +
                       record.source_path + "'); import it with another --test-id.");
    replacing = existing;
  }
  nlohmann::json metadata = nlohmann::json::object();
  metadata["format"] = InputFormatName(head.archived_format.value_or(input.format));
  if (head.archived_format) metadata["archive"] = InputFormatName(input.format);
  if (!head.channel_map.empty()) metadata["channel_map"] = head.channel_map;
  if (read.array_from_codes) metadata["array_from_codes"] = true;
  if (FormatEntry(input.format).span == TestSpan::kFileGroup) {
    nlohmann::json files = nlohmann::json::array();
    for (const fs::path& file : input.files) files.push_back(file.filename().string());
    metadata["files"] = std::move(files);
  }
  if (nlohmann::json info = TestInfoJson(head.info, head.position); !info.empty())
    metadata["test"] = std::move(info);
  if (!head.notes.empty()) metadata["notes"] = head.notes;

  db::TestRow record;
  record.external_id = test_id;
  record.series = options.series;
  record.variant = options.variant;
  record.initial_state = prepared.initial;
  if (!prepared.velocity_given && head.initial_velocity_body_mps) {
    // INIVEL is along the CG channels' own axes: rotated into the fixed frame by R0.
    record.initial_state.velocity_fixed_mps =
        engine::InitialFixedFromBody(prepared.initial.orientation_rad) * *head.initial_velocity_body_mps;
    metadata["initial_velocity"] = "inivel";
  }
  if (prepared.velocity_given && head.initial_velocity_body_mps)
    result.warnings.push_back(test_id +
                              ": the INIVEL its files record is not used, as --initial-velocity "
                              "gives the initial velocity.");
  record.metadata_json = metadata.dump();
  record.source_path = source_path;
  record.content_hash = content_hash;

  // The store skips content another process stored meanwhile.
  if (!StoreTest(catalogue, read.array, array_record, record, head.signals, replacing)) return skipped();
  result.outcome = ImportOutcome::kImported;
  result.superseded = replacing.has_value();
  result.message = replacing ? test_id + ": imported again from " + record.source_path +
                                   ", whose content changed; the new content replaces the old."
                             : test_id + ": imported from " + record.source_path + ".";
  for (std::string& note : head.notes) result.warnings.push_back(NamingSource(note, input));
  return result;
}

// The results of one input: one per dummy head imported, or one failure.
std::vector<ImportResult> ImportOne(db::Catalogue& catalogue, const ImportInput& input,
                                    const PreparedImport& prepared, const ImportOptions& options) {
  std::string test_id = options.test_id.value_or(input.name);
  try {
    CheckPathsAreUtf8(input);
    // Ids are UTF-8, printable and of sane length: they reach terminals,
    // tables, JSON and export file names (docs/formats.md "Names, limits and
    // escaping").
    util::CheckName("test id", test_id);
    const std::string input_hash = InputContentHash(input);
    // An input of one dummy keeps its content hash; nothing more to read when it is stored (unless
    // the files name the test: its id is read from them, for the sentence).
    const bool id_from_files = !options.test_id && FormatEntry(input.format).names_its_test;
    if (!options.position && !id_from_files && catalogue.ExistsTestByHash(input_hash)) {
      ImportResult result;
      result.outcome = ImportOutcome::kSkipped;
      result.test_id = test_id;
      result.message = test_id + ": already imported (same content), skipped.";
      return {result};
    }

    // Read and check everything before writing anything.
    HeadReadOptions read_options;
    read_options.array = prepared.array ? &*prepared.array : nullptr;
    read_options.array_option = options.array_option;
    read_options.channel_map = prepared.channel_map ? &*prepared.channel_map : nullptr;
    read_options.default_map = &prepared.default_map;
    read_options.csv_columns = prepared.csv_columns;
    read_options.position = options.position;
    if (options.test_id) read_options.one_test_expected = "--test-id names one test";
    read_options.initial_omega_body_radps = prepared.initial.omega_body_radps;
    InputHeads read = ReadInputHeads(input, read_options, test_id);
    // The id the files give the test (DTS SLICEWare's Test ID), unless --test-id gives one.
    if (!options.test_id && read.test_id) {
      test_id = *read.test_id;
      util::CheckName("test id", test_id);
    }
    const db::ArrayRow array_record =
        prepared.array_record ? *prepared.array_record : records::MakeImportedArrayRecord(read.array);

    std::vector<ImportResult> results;
    for (HeadSignals& head : read.heads) {
      // Several dummies: TEST/<position>, and the position in the content hash
      // (docs/formats.md "Several dummies in one test").
      const std::string head_id = read.several && !options.test_id ? test_id + "/" + head.position : test_id;
      const std::string content_hash =
          read.several ? util::Sha256Hex(input_hash + "\nposition " + head.position) : input_hash;
      try {
        results.push_back(
            StoreHead(catalogue, input, prepared, options, read, array_record, head, head_id, content_hash));
      } catch (const InputError& error) {
        results.push_back(Failed(head_id, NamingSource(error.what(), input)));
      }
    }
    if (!results.empty())
      for (std::string& warning : read.warnings)
        results.front().warnings.insert(results.front().warnings.begin(), NamingSource(warning, input));
    return results;
  } catch (const InputError& error) {
    return {Failed(test_id, NamingSource(error.what(), input))};
  } catch (const std::filesystem::filesystem_error& error) {
    // The input's files could not be read (removed, unreadable meanwhile): the test's failure.
    return {Failed(test_id, "test '" + test_id + "' from " + input.source.string() + " could not be read (" +
                                error.code().message() + "); it was not imported.")};
  }
  // Only input errors are a test's failure (README "import"). A database
  // failure concerns every test, and anything else (std::logic_error, ...: a
  // bug in napkin; std::bad_alloc) is no property of the test: it stops the
  // import, keeping the tests stored so far, and the CLI reports it as an
  // internal error, as `run` does (jobs/README.md "Errors").
}

}  // namespace

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
  if (!options.array.empty()) {
    prepared.array = formats::LoadArray(options.array);
    prepared.array_record = records::MakeImportedArrayRecord(*prepared.array);
  }
  if (!options.channel_map.empty()) prepared.channel_map = formats::LoadChannelMap(options.channel_map);
  prepared.default_map = formats::LoadChannelMap("default");
  prepared.csv_columns =
      CsvColumnsOf(prepared.channel_map ? &*prepared.channel_map : nullptr, options.csv_columns);
  for (const auto& [slot, column] : prepared.csv_columns)
    if (prepared.array && slot != "time_s" && !prepared.array->FindSlot(slot))
      throw UsageError("--column names slot '" + slot + "', which array '" + prepared.array->name +
                       "' does not have.");
  prepared.initial.orientation_rad = Triple(options.orientation_rad, "--orientation");
  prepared.initial.velocity_fixed_mps = Triple(options.initial_velocity_mps, "--initial-velocity");
  prepared.velocity_given = !options.initial_velocity_mps.empty();
  if (options.test_id && options.test_id->empty()) throw UsageError("--test-id must not be empty.");
  if (options.position && options.position->empty()) throw UsageError("--position must not be empty.");
  auto check_option = [](const char* option, const std::optional<std::string>& value) {
    if (!value) return;
    try {
      util::CheckName(option, *value);
    } catch (const InputError& error) {
      throw UsageError(error.what());
    }
  };
  check_option("--test-id", options.test_id);
  check_option("--series", options.series);
  check_option("--variant", options.variant);
  // `compare` and `report` call the group of tests without a variant
  // "(none)": a variant of that name would be taken for it (docs/formats.md
  // "napkin compare").
  if (options.variant == kNoVariantGroup)
    throw UsageError("--variant '" + std::string(kNoVariantGroup) +
                     "' is the name compare and report give the tests without a variant; choose another "
                     "name (or give no --variant).");
  // Array and channel-map names taken from their file names are of unknown encoding.
  if (prepared.array) check_option("the array name", prepared.array->name);
  if (prepared.channel_map) check_option("the channel map name", prepared.channel_map->name);

  const Discovery discovery = DiscoverInputs(paths);
  if (options.test_id && discovery.inputs.size() + discovery.errors.size() > 1)
    throw UsageError("--test-id names one test, but the paths hold " +
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
    ++done;
    for (ImportResult& result : ImportOne(catalogue, input, prepared, options)) {
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
      if (progress) progress(done, total, report.results.back());
    }
  }
  return report;
}

}  // namespace napkin::ingest
