// `napkin export`: one test's derived channels (the kinematics its latest
// result, or the result under --config, stored, or recomputed for storage
// "none") as the derived-channel CSV, LS-DYNA keyword load curves, the legacy
// LC_FILE.DAT, or an ISO-MME folder, or the report's UDS-1992 output files. Reads the catalogue only; the
// output is written atomically, a folder format's files beside what the folder
// holds (docs/formats.md "Output destinations").
#include <fmt/core.h>

#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "app/db_protection.h"
#include "app/result_selection.h"
#include "cli/catalogue_option.h"
#include "cli/command.h"
#include "cli/option_checks.h"
#include "common/error.h"
#include "engine/kinematics.h"
#include "formats/array_json.h"
#include "formats/csv.h"
#include "formats/isomme.h"
#include "formats/lsdyna.h"
#include "formats/uds_export.h"
#include "records/array_record.h"
#include "records/config_record.h"
#include "util/atomic_file.h"
#include "util/text.h"

namespace napkin::cli {
namespace {

class ExportCommand : public Command {
 public:
  CLI::App* Setup(CLI::App& app, const GlobalOptions& global) override {
    global_ = &global;
    CLI::App* sub = app.add_subcommand("export", "write one test's derived channels");
    sub->add_option("--test", test_id_, "test id")->required();
    sub->add_option("--format", format_,
                    "csv, lsdyna, lcfile, isomme or uds (derived channels); channels (the raw channels the "
                    "result was computed from, repaired ones in place, as napkin CSV) or recorded (the raw "
                    "channels as recorded)")
        ->required()
        ->check(OneOfCheck("--format", {"csv", "lsdyna", "lcfile", "isomme", "uds", "channels", "recorded"}));
    sub->add_option("--out", out_, "file to write (a folder for isomme and uds)")
        ->required()
        ->check(PathCheck("--out"));
    sub->add_option("--numform", numform_, "uds number form: ieee, vax or sun")
        ->check(OneOfCheck("--numform", {"ieee", "vax", "sun"}))
        ->capture_default_str();
    sub->add_option("--position", position_,
                    "isomme: test object and seat position of the channel codes (default: the test's "
                    "stored position, else 11)");
    sub->add_option("--dummy-type", dummy_type_,
                    "isomme: dummy type of the channel codes, e.g. H3 (default: the test's stored dummy "
                    "type, else 00)");
    sub->add_option(
           "--config", config_,
           "processing config preset or JSON file whose result to export (default: the latest result)")
        ->check(PathCheck("--config"));
    // docs/formats.md "Output destinations": --out - is standard output (one
    // file); a folder format writes beside what --out holds.
    sub->add_flag("--force", force_,
                  "isomme, uds: replace files of the same names in the --out folder (default: refuse)");
    std::vector<std::string> unit_systems;
    unit_systems.reserve(formats::kLsDynaUnits.size());
    for (const formats::LsDynaUnits system : formats::kLsDynaUnits)
      unit_systems.emplace_back(engine::NameOf(system));
    sub->add_option("--units", units_, "lsdyna units: si (m, s) or english (in, s)")
        ->check(OneOfCheck("--units", unit_systems))
        ->capture_default_str();
    sub->add_option("--part", part_, "lsdyna rigid part id")
        ->check(WholeNumberCheck("--part", 1))
        ->capture_default_str();
    return sub;
  }

  int Run() override {
    const bool folder_format = format_ == "isomme" || format_ == "uds";
    if (folder_format && out_ == util::kStandardOutputName)
      throw UsageError("--format " + format_ +
                       " writes a folder of files, which cannot go to standard output " +
                       "(--out -); name a folder.");
    // The --config file this command reads is never its output (docs/formats.md
    // "Output destinations"); an unknown preset is reported where it is used.
    if (!config_.empty()) {
      try {
        app::ProtectInputFromOutput(records::ProcessingConfigPath(config_, formats::DefaultConfigDir()),
                                    "the --config file");
      } catch (const InputError&) {
      }
    }
    db::Catalogue catalogue = OpenCatalogue(*global_, /*read_only=*/true);
    // The recorded channels need no result (its salvage record, when there is
    // one, only adds notes).
    if (format_ == "recorded") {
      const std::optional<db::TestId> test = catalogue.FindTestByExternalId(test_id_);
      if (!test)
        throw NotFoundError("test '" + test_id_ + "' is not in catalogue '" + global_->db_path + "'.");
      const std::optional<db::ConfigId> config =
          config_.empty() ? app::FindResult(catalogue, *test, app::Latest{})
                          : app::FindResult(catalogue, *test, app::Preset{config_});
      WriteChannels(catalogue, *test, config);
      return kExitOk;
    }
    // --config is a preset or file here, as for `napkin run` (app/result_selection.h "Preset").
    const app::TestResult result =
        config_.empty() ? app::ResultOf(catalogue, test_id_, app::Latest{}, global_->db_path)
                        : app::ResultOf(catalogue, test_id_, app::Preset{config_}, global_->db_path);
    const db::TestId test = result.test;
    const db::ConfigId config = result.config;
    if (format_ == "channels") {
      WriteChannels(catalogue, test, config);
      return kExitOk;
    }
    // Stored, or recomputed (storage "none"; docs/formats.md "Derived-channel storage").
    const std::optional<engine::Kinematics> kinematics = app::ReadResultKinematics(catalogue, test, config);

    // docs/formats.md "Derived channels": an acceleration-only test exports as csv or isomme only.
    if (format_ != "csv" && format_ != "isomme" && !engine::HasRotation(*kinematics))
      throw InputError("test '" + test_id_ +
                       "' has no rotation (its array cannot determine it), which --format " + format_ +
                       " needs; --format csv or isomme gives its CG acceleration.");
    if (format_ == "csv") {
      formats::WriteDerivedCsv(*kinematics, out_);
    } else if (format_ == "lsdyna") {
      formats::LsDynaOptions options;
      options.part_id = part_;
      const std::optional<formats::LsDynaUnits> units = engine::ParseName<formats::LsDynaUnits>(units_);
      if (!units) throw InputError("unknown lsdyna units \"" + units_ + "\" (use si or english).");
      options.units = *units;
      formats::WriteLsDynaKeyword(*kinematics, out_, options);
    } else if (format_ == "lcfile") {
      formats::WriteLcFile(*kinematics, out_);
    } else if (format_ == "uds") {
      const formats::UdsNumberForm form = numform_ == "vax"   ? formats::UdsNumberForm::kVax
                                          : numform_ == "sun" ? formats::UdsNumberForm::kSun
                                                              : formats::UdsNumberForm::kIeee;
      // FCUT: the class the result's channels are filtered at (docs/formats.md "UDS-1992 export").
      const db::TestRow record = catalogue.ReadTest(test);
      const std::optional<engine::TestSummary> summary = catalogue.ReadSummary(test, config);
      const formats::UdsExportFilters filters = formats::UdsFiltersOfResult(
          summary ? summary->conditioning : std::vector<engine::ChannelConditioning>{},
          records::DecodeArrayRecord(catalogue.ReadArray(record.array_id)),
          records::DecodeConfigRecord(catalogue.ReadConfig(config)).filter);
      // The files appear beside what --out holds, none replaced unless --force
      // (util/atomic_file.h WriteDirectoryAtomically).
      util::WriteDirectoryAtomically(
          out_,
          [&](const std::filesystem::path& staging) {
            formats::WriteDerivedUds(*kinematics, staging, util::FileNameComponent(test_id_), form, filters);
          },
          force_);
    } else {
      // The test id names the files: made safe (no separator, control
      // character, "." or ".."; docs/formats.md "Names, limits and escaping").
      const formats::IsoMmeExportOptions options = IsoMmeOptions(catalogue, test, config);
      util::WriteDirectoryAtomically(
          out_,
          [&](const std::filesystem::path& staging) {
            formats::WriteDerivedIsoMme(*kinematics, staging, util::FileNameComponent(test_id_), options);
          },
          force_);
    }
    return kExitOk;
  }

 private:
  // docs/formats.md "Salvage record": the raw channels as napkin's CSV input,
  // '#' lines first naming the test, the result's config, the array to read
  // it with and what salvage did to each channel.
  void WriteChannels(db::Catalogue& catalogue, db::TestId test, std::optional<db::ConfigId> config) {
    const bool recorded = format_ == "recorded";
    const app::ResultChannels channels = app::ReadResultChannels(catalogue, test, config, recorded);
    const db::TestRow test_row = catalogue.ReadTest(test);
    std::string what = "the channels as recorded";
    if (!recorded) {
      const db::ConfigRow config_row = catalogue.ReadConfig(*config);
      what = "the channels of its result under config " + config_row.name + " (hash " +
             config_row.config_hash.substr(0, 12) + ")";
    }
    std::vector<std::string> comments = {
        "napkin export --format " + format_ + ": test " + test_id_ + ", " + what,
        "array: " + catalogue.ReadArray(test_row.array_id).name + " (napkin transform --array ...)"};
    comments.insert(comments.end(), channels.notes.begin(), channels.notes.end());
    formats::WriteSignalsCsv(channels.signals, out_, comments);
  }

  // The channel codes' position and dummy type (options, else the test's
  // metadata "position" / "dummy_type"), the filters the result's config
  // applied, and whether the array has angular-rate sensors.
  formats::IsoMmeExportOptions IsoMmeOptions(db::Catalogue& catalogue, db::TestId test, db::ConfigId config) {
    formats::IsoMmeExportOptions options;
    const db::TestRow record = catalogue.ReadTest(test);
    const nlohmann::json metadata = nlohmann::json::parse(record.metadata_json, nullptr, false);
    auto stored = [&](const char* key) -> std::optional<std::string> {
      if (!metadata.is_object() || !metadata.contains(key)) return std::nullopt;
      const nlohmann::json& value = metadata.at(key);
      if (value.is_string()) return value.get<std::string>();
      if (value.is_number_integer()) return std::to_string(value.get<long long>());
      return std::nullopt;
    };
    options.position = position_.value_or(stored("position").value_or(options.position));
    options.dummy_type = dummy_type_.value_or(stored("dummy_type").value_or(options.dummy_type));
    const engine::ProcessingConfig processing = records::DecodeConfigRecord(catalogue.ReadConfig(config));
    options.linear_cfc = processing.filter.linear_cfc;
    options.angular_rate_cfc = processing.filter.angular_rate_cfc;
    for (const engine::Sensor& sensor :
         records::DecodeArrayRecord(catalogue.ReadArray(record.array_id)).sensors)
      if (sensor.kind == engine::SensorKind::kAngularRate) options.angular_rate_sensors = true;
    return options;
  }

  const GlobalOptions* global_ = nullptr;
  std::string test_id_;
  std::string format_;
  std::string out_;
  bool force_ = false;
  std::string config_;
  std::string units_ = engine::NameOf(formats::LsDynaUnits::kSi);
  int part_ = 1;
  std::string numform_ = "ieee";
  std::optional<std::string> position_;
  std::optional<std::string> dummy_type_;
};

}  // namespace

std::unique_ptr<Command> MakeExportCommand() { return std::make_unique<ExportCommand>(); }

}  // namespace napkin::cli
