#include "ingest/import.h"

#include <cmath>
#include <exception>
#include <new>
#include <nlohmann/json.hpp>
#include <utility>

#include "common/error.h"
#include "db/sqlite.h"
#include "formats/array_json.h"
#include "formats/channel_map.h"
#include "formats/csv.h"
#include "formats/isomme.h"
#include "formats/uds1992.h"
#include "ingest/content_hash.h"
#include "ingest/store.h"
#include "records/array_record.h"

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
  auto skipped = [&] {
    result.outcome = ImportOutcome::kSkipped;
    result.message = test_id + ": already imported (same content), skipped.";
    return result;
  };
  try {
    const std::string content_hash = InputContentHash(input);
    if (catalogue.ExistsTestByHash(content_hash)) return skipped();
    if (const std::optional<db::TestId> existing = catalogue.FindTestByExternalId(test_id)) {
      const db::TestRecord record = catalogue.ReadTest(*existing);
      // Another import of the same input (a concurrent process) stored it
      // between the two look-ups: present, not failed.
      if (record.content_hash == content_hash) return skipped();
      throw InputError("test '" + test_id + "' from '" + input.source.string() +
                       "' differs from the catalogue's test of that id (imported from '" +
                       record.source_path + "'); import it with another --test-id.");
    }

    // Read and check everything before writing anything.
    ReadTest read = ReadInput(input, prepared, test_id);
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

    // The store skips content another process stored meanwhile.
    if (!StoreTest(catalogue, prepared.array, prepared.array_record, record, read.signals)) return skipped();

    result.outcome = ImportOutcome::kImported;
    result.message = test_id + ": imported from " + record.source_path + ".";
    for (std::string& warning : read.warnings) result.warnings.push_back(NamingSource(warning, input));
  } catch (const InputError& error) {
    result.outcome = ImportOutcome::kFailed;
    result.message = NamingSource(error.what(), input);
  } catch (const db::DatabaseError&) {
    throw;  // the catalogue itself failed: that concerns every test, not this one
  } catch (const std::bad_alloc&) {
    // One test's failure of any kind is recorded against it and the batch goes on (README "import").
    result.outcome = ImportOutcome::kFailed;
    result.message = "test '" + test_id + "' from " + input.source.string() +
                     " needs more memory than is available (std::bad_alloc); it was not imported.";
  } catch (const std::exception& error) {
    result.outcome = ImportOutcome::kFailed;
    result.message = "test '" + test_id + "' from " + input.source.string() + " could not be read (" +
                     error.what() + "); it was not imported.";
  }
  return result;
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
  prepared.array = formats::LoadArray(options.array);
  prepared.array_record = records::MakeArrayRecord(prepared.array);
  if (!options.channel_map.empty()) prepared.channel_map = formats::LoadChannelMap(options.channel_map);
  prepared.default_map = formats::LoadChannelMap("default");
  prepared.initial.orientation_rad = Triple(options.orientation_rad, "--orientation");
  prepared.initial.velocity_fixed_mps = Triple(options.initial_velocity_mps, "--initial-velocity");
  if (options.test_id && options.test_id->empty()) throw UsageError("--test-id must not be empty.");

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

}  // namespace napkin::ingest
