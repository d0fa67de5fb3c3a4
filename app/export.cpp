#include "app/export.h"

#include <stdlib.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <nlohmann/json.hpp>
#include <system_error>

#include "common/error.h"
#include "engine/kinematics.h"
#include "formats/csv.h"
#include "formats/derived_json.h"
#include "formats/isomme.h"
#include "formats/json_file.h"
#include "formats/uds_export.h"
#include "records/array_record.h"
#include "records/config_record.h"
#include "util/atomic_file.h"
#include "util/temporary_directory.h"
#include "util/text.h"

namespace napkin::app {

struct ExportSource {
  explicit ExportSource(db::Catalogue& catalogue_) : catalogue(catalogue_) {}
  db::Catalogue& catalogue;
  db::TestId test{};
  std::optional<db::ConfigId> config;            // none: the recorded channels of a test without a result
  std::optional<engine::Kinematics> kinematics;  // ExportInput::kDerived
  std::optional<ResultChannels> channels;        // the raw-channel inputs
};

namespace {

void WriteCsvExport(const ExportSource& source, const ExportRequest&, const std::filesystem::path& out) {
  formats::WriteDerivedCsv(*source.kinematics, out);
}

void WriteJsonExport(const ExportSource& source, const ExportRequest& request,
                     const std::filesystem::path& out) {
  formats::WriteDerivedJson(*source.kinematics, request.test_id, out);
}

void WriteLsDynaExport(const ExportSource& source, const ExportRequest& request,
                       const std::filesystem::path& out) {
  formats::WriteLsDynaKeyword(*source.kinematics, out, request.lsdyna);
}

void WriteLcFileExport(const ExportSource& source, const ExportRequest&, const std::filesystem::path& out) {
  formats::WriteLcFile(*source.kinematics, out);
}

// The channel codes' position and dummy type (the request's, else the test's
// metadata "position" / "dummy_type"), the filters the result's config
// applied, and whether the array has angular-rate sensors (docs/formats.md
// "ISO-MME export").
void WriteIsoMmeExport(const ExportSource& source, const ExportRequest& request,
                       const std::filesystem::path& out) {
  formats::IsoMmeExportOptions options;
  const db::TestRow record = source.catalogue.ReadTest(source.test);
  const nlohmann::json metadata = nlohmann::json::parse(record.metadata_json, nullptr, false);
  auto stored = [&](const char* key) -> std::optional<std::string> {
    if (!metadata.is_object() || !metadata.contains(key)) return std::nullopt;
    const nlohmann::json& value = metadata.at(key);
    if (value.is_string()) return value.get<std::string>();
    if (value.is_number_integer()) return std::to_string(value.get<long long>());
    return std::nullopt;
  };
  options.position = request.position.value_or(stored("position").value_or(options.position));
  options.dummy_type = request.dummy_type.value_or(stored("dummy_type").value_or(options.dummy_type));
  const engine::ProcessingConfig processing =
      records::DecodeConfigRecord(source.catalogue.ReadConfig(*source.config));
  options.linear_cfc = processing.filter.linear_cfc;
  options.angular_rate_cfc = processing.filter.angular_rate_cfc;
  for (const engine::Sensor& sensor :
       records::DecodeArrayRecord(source.catalogue.ReadArray(record.array_id)).sensors)
    if (sensor.kind == engine::SensorKind::kAngularRate) options.angular_rate_sensors = true;
  // The test id names the files: made safe (no separator, control character,
  // "." or ".."; docs/formats.md "Names, limits and escaping").
  formats::WriteDerivedIsoMme(*source.kinematics, out, util::FileNameComponent(request.test_id), options);
}

// FCUT: the class the result's channels are filtered at (docs/formats.md "UDS-1992 export").
void WriteUdsExport(const ExportSource& source, const ExportRequest& request,
                    const std::filesystem::path& out) {
  const db::TestRow record = source.catalogue.ReadTest(source.test);
  const std::optional<engine::TestSummary> summary =
      source.catalogue.ReadSummary(source.test, *source.config);
  const formats::UdsExportFilters filters = formats::UdsFiltersOfResult(
      summary ? summary->conditioning : std::vector<engine::ChannelConditioning>{},
      records::DecodeArrayRecord(source.catalogue.ReadArray(record.array_id)),
      records::DecodeConfigRecord(source.catalogue.ReadConfig(*source.config)).filter);
  formats::WriteDerivedUds(*source.kinematics, out, util::FileNameComponent(request.test_id),
                           request.number_form, filters);
}

// docs/formats.md "Salvage record": the raw channels as napkin's CSV input,
// '#' lines first naming the test, the result's config, the array to read
// it with and what salvage did to each channel.
void WriteChannelsExport(const ExportSource& source, const ExportRequest& request,
                         const std::filesystem::path& out) {
  const db::TestRow test_row = source.catalogue.ReadTest(source.test);
  std::string what = "the channels as recorded";
  if (request.format->input == ExportInput::kResultChannels) {
    const db::ConfigRow config_row = source.catalogue.ReadConfig(*source.config);
    what = "the channels of its result under config " + config_row.name + " (hash " +
           config_row.config_hash.substr(0, 12) + ")";
  }
  std::vector<std::string> comments = {
      "napkin export --format " + std::string(request.format->name) + ": test " + request.test_id + ", " +
          what,
      "array: " + source.catalogue.ReadArray(test_row.array_id).name + " (napkin transform --array ...)"};
  comments.insert(comments.end(), source.channels->notes.begin(), source.channels->notes.end());
  formats::WriteSignalsCsv(source.channels->signals, out, comments);
}

constexpr std::array<ExportFormat, 8> kExportFormats{{
    {"csv", "the derived channels as CSV, 12 significant digits (docs/formats.md \"Derived channels\")",
     ExportInput::kDerived, false, false, ".csv", "text/csv", WriteCsvExport},
    {"json", "the derived channels as one JSON object of columns, full precision", ExportInput::kDerived,
     false, false, ".json", "application/json", WriteJsonExport},
    {"lsdyna", "LS-DYNA keyword load curves of the CG velocity and angular velocity", ExportInput::kDerived,
     true, false, ".k", "text/plain", WriteLsDynaExport},
    {"lcfile", "the report's legacy LC_FILE.DAT load curves", ExportInput::kDerived, true, false, ".dat",
     "text/plain", WriteLcFileExport},
    {"isomme", "an ISO-MME test folder of the derived channels", ExportInput::kDerived, false, true, "",
     "application/zip", WriteIsoMmeExport},
    {"uds", "the report's UDS-1992 output files (a folder)", ExportInput::kDerived, true, true, "",
     "application/zip", WriteUdsExport},
    {"channels", "the raw channels the result was computed from, repaired ones in place, as napkin CSV",
     ExportInput::kResultChannels, false, false, ".csv", "text/csv", WriteChannelsExport},
    {"recorded", "the raw channels as recorded, as napkin CSV", ExportInput::kRecordedChannels, false, false,
     ".csv", "text/csv", WriteChannelsExport},
}};

// The formats an acceleration-only test can be exported in: "csv, json or isomme".
std::string FormatsWithoutRotation() {
  std::vector<std::string> names;
  for (const ExportFormat& format : kExportFormats)
    if (format.input == ExportInput::kDerived && !format.needs_rotation) names.emplace_back(format.name);
  return ChoiceList(names);
}

// The test, its result and the format's input.
ExportSource ReadSource(db::Catalogue& catalogue, const ExportRequest& request) {
  ExportSource source(catalogue);
  const ExportFormat& format = *request.format;
  if (format.input == ExportInput::kRecordedChannels) {
    // The recorded channels need no result (its salvage record, when there is one, only adds notes).
    const std::optional<db::TestId> test = catalogue.FindTestByExternalId(request.test_id);
    if (!test)
      throw NotFoundError("test '" + request.test_id + "' is not in catalogue '" + catalogue.path() + "'.");
    source.test = *test;
    source.config = FindResult(catalogue, *test, request.result);
    source.channels = ReadResultChannels(catalogue, *test, source.config, /*recorded=*/true);
    return source;
  }
  const TestResult result = ResultOf(catalogue, request.test_id, request.result);
  source.test = result.test;
  source.config = result.config;
  if (format.input == ExportInput::kResultChannels) {
    source.channels = ReadResultChannels(catalogue, result.test, result.config);
    return source;
  }
  // Stored, or recomputed (storage "none"; docs/formats.md "Derived-channel storage").
  source.kinematics = ReadResultKinematics(catalogue, result.test, result.config);
  // docs/formats.md "Derived channels": an acceleration-only test exports without rotation only.
  if (format.needs_rotation && !engine::HasRotation(*source.kinematics))
    throw InputError("test '" + request.test_id +
                     "' has no rotation (its array cannot determine it), which " + "format " +
                     std::string(format.name) + " needs; format " + FormatsWithoutRotation() +
                     " gives its CG acceleration.");
  return source;
}

// A folder of this process's own under the temporary folder, removed with everything in it when
// this goes: nothing else writes there (mkdtemp: mode 0700, a new name).
class PrivateFolder {
 public:
  PrivateFolder() {
    std::string pattern = (util::TemporaryDirectory() / "napkin-export-XXXXXX").string();
    if (::mkdtemp(pattern.data()) == nullptr)
      throw InputError("cannot create a folder in " + util::TemporaryDirectory().string() + " (" +
                       std::error_code(errno, std::generic_category()).message() + ").");
    path_ = pattern;
  }
  ~PrivateFolder() {
    std::error_code ignored;
    std::filesystem::remove_all(path_, ignored);
  }
  PrivateFolder(const PrivateFolder&) = delete;
  PrivateFolder& operator=(const PrivateFolder&) = delete;
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

}  // namespace

std::span<const ExportFormat> ExportFormats() { return kExportFormats; }

const ExportFormat* FindExportFormat(std::string_view name) {
  for (const ExportFormat& format : kExportFormats)
    if (format.name == name) return &format;
  return nullptr;
}

std::vector<std::string> ExportFormatNames() {
  std::vector<std::string> names;
  for (const ExportFormat& format : kExportFormats) names.emplace_back(format.name);
  return names;
}

ExportRequest ParseExportRequest(std::string test_id, const RequestOptions& options) {
  options.CheckKnown({"format", "config", "units", "part", "numform", "position", "dummy-type"});
  ExportRequest request;
  request.test_id = std::move(test_id);
  const std::string format = options.Required("format", ChoiceList(ExportFormatNames()));
  request.format = FindExportFormat(format);
  if (request.format == nullptr)
    throw UsageError(NotOneOfProblem(options.Name("format"), ExportFormatNames(), format) + ".");
  if (const std::optional<std::string> config = options.One("config")) {
    if (options.front_end() == FrontEnd::kCommandLine)
      request.result = Preset{*config};
    else
      request.result = Stored{*config, options.Name("config")};
  }
  std::vector<std::string> unit_systems;
  for (const formats::LsDynaUnits system : formats::kLsDynaUnits)
    unit_systems.emplace_back(engine::NameOf(system));
  request.lsdyna.units = *engine::ParseName<formats::LsDynaUnits>(
      options.OneOf("units", unit_systems, engine::NameOf(formats::LsDynaUnits::kSi)));
  request.lsdyna.part_id = options.WholeNumber("part", 1, 1);
  const std::string numform = options.OneOf("numform", {"ieee", "vax", "sun"}, "ieee");
  request.number_form = numform == "vax"   ? formats::UdsNumberForm::kVax
                        : numform == "sun" ? formats::UdsNumberForm::kSun
                                           : formats::UdsNumberForm::kIeee;
  request.position = options.One("position");
  request.dummy_type = options.One("dummy-type");
  return request;
}

void Export(db::Catalogue& catalogue, const ExportRequest& request, const std::filesystem::path& out,
            bool replace_existing) {
  const ExportFormat& format = *request.format;
  if (format.folder && out == util::kStandardOutputName)
    throw UsageError("format " + std::string(format.name) +
                     " writes a folder of files, which cannot go to standard output ('-'); name a folder.");
  const ExportSource source = ReadSource(catalogue, request);
  if (!format.folder) {
    format.write(source, request, out);
    return;
  }
  // The files appear beside what `out` holds, none replaced unless asked
  // (docs/formats.md "Output destinations").
  util::WriteDirectoryAtomically(
      out, [&](const std::filesystem::path& staging) { format.write(source, request, staging); },
      replace_existing);
}

std::vector<ExportedFile> ExportToMemory(db::Catalogue& catalogue, const ExportRequest& request) {
  const PrivateFolder folder;
  const std::filesystem::path out =
      folder.path() / (util::FileNameComponent(request.test_id) + std::string(request.format->extension));
  try {
    Export(catalogue, request, out);
  } catch (const InputError& error) {
    // A writer's sentence names the file it writes: here by its name, not the private folder's path.
    const std::string prefix = folder.path().string() + "/";
    std::string sentence = error.what();
    if (sentence.find(prefix) == std::string::npos) throw;
    for (std::size_t at = sentence.find(prefix); at != std::string::npos; at = sentence.find(prefix, at))
      sentence.erase(at, prefix.size());
    if (dynamic_cast<const UsageError*>(&error) != nullptr) throw UsageError(sentence);
    throw InputError(sentence);
  }
  std::vector<ExportedFile> files;
  if (!request.format->folder) {
    files.push_back({out.filename().string(), formats::ReadWholeFile(out)});
    return files;
  }
  for (const std::filesystem::directory_entry& entry : std::filesystem::recursive_directory_iterator(out))
    if (entry.is_regular_file())
      files.push_back(
          {entry.path().lexically_relative(out).generic_string(), formats::ReadWholeFile(entry.path())});
  std::sort(files.begin(), files.end(),
            [](const ExportedFile& a, const ExportedFile& b) { return a.name < b.name; });
  return files;
}

}  // namespace napkin::app
