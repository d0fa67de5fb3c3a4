// `napkin export`: one test's stored derived channels (the kinematics its
// latest result, or the result under --config, wrote) as the derived-channel
// CSV, LS-DYNA keyword load curves, the legacy LC_FILE.DAT, or an ISO-MME
// folder. Reads the catalogue only; the output is written atomically.
#include <fmt/core.h>

#include <optional>
#include <string>
#include <vector>

#include "cli/catalogue_access.h"
#include "cli/command.h"
#include "common/error.h"
#include "formats/csv.h"
#include "formats/isomme.h"
#include "formats/lsdyna.h"
#include "formats/text.h"

namespace napkin::cli {
namespace {

class ExportCommand : public Command {
 public:
  CLI::App* Setup(CLI::App& app, const GlobalOptions& global) override {
    global_ = &global;
    CLI::App* sub = app.add_subcommand("export", "write one test's derived channels");
    sub->add_option("--test", test_id_, "test id")->required();
    sub->add_option("--format", format_, "csv, lsdyna, lcfile or isomme")
        ->required()
        ->check(CLI::IsMember({"csv", "lsdyna", "lcfile", "isomme"}));
    sub->add_option("--out", out_, "file to write (a folder for isomme)")->required();
    sub->add_option(
        "--config", config_,
        "processing config preset or JSON file whose result to export (default: the latest result)");
    std::vector<std::string> unit_systems;
    for (const formats::LsDynaUnits system : formats::kLsDynaUnits)
      unit_systems.emplace_back(formats::LsDynaUnitsName(system));
    sub->add_option("--units", units_, "lsdyna units: si (m, s) or english (in, s)")
        ->check(CLI::IsMember(unit_systems))
        ->capture_default_str();
    sub->add_option("--part", part_, "lsdyna rigid part id")
        ->check(CLI::PositiveNumber)
        ->capture_default_str();
    return sub;
  }

  int Run() override {
    db::Catalogue catalogue = OpenCatalogue(*global_, /*read_only=*/true);
    const std::optional<db::TestId> test = catalogue.FindTestByExternalId(test_id_);
    if (!test) throw InputError("test '" + test_id_ + "' is not in catalogue '" + global_->db_path + "'.");

    std::optional<db::ConfigId> config;
    if (config_.empty()) {
      config = catalogue.ReadLatestResultConfig(*test);
      if (!config) throw InputError("test '" + test_id_ + "' has no results yet; run `napkin run` first.");
    } else {
      const ResolvedConfig resolved = ResolveConfig(config_);
      config = catalogue.FindConfigByHash(resolved.record.config_hash);
      if (!config || !catalogue.ReadSummary(*test, *config))
        throw InputError("test '" + test_id_ + "' has no results for config '" + config_ +
                         "' yet; run `napkin run --config " + config_ + "` first.");
    }
    const std::optional<engine::Kinematics> kinematics = catalogue.ReadKinematics(*test, *config);
    if (!kinematics)
      throw InputError(
          "test '" + test_id_ +
          "' has a result without stored derived channels; run `napkin run --force` to recompute it.");

    if (format_ == "csv") {
      formats::WriteDerivedCsv(*kinematics, out_);
    } else if (format_ == "lsdyna") {
      formats::LsDynaOptions options;
      options.part_id = part_;
      const std::optional<formats::LsDynaUnits> units = formats::ParseLsDynaUnitsName(units_);
      if (!units) throw InputError("unknown lsdyna units \"" + units_ + "\" (use si or english).");
      options.units = *units;
      formats::WriteLsDynaKeyword(*kinematics, out_, options);
    } else if (format_ == "lcfile") {
      formats::WriteLcFile(*kinematics, out_);
    } else {
      // The test id names the files: made safe (no separator, control
      // character, "." or ".."; docs/formats.md "Names, limits and escaping").
      formats::WriteDerivedIsoMme(*kinematics, out_, formats::FileNameComponent(test_id_));
    }
    return kExitOk;
  }

 private:
  const GlobalOptions* global_ = nullptr;
  std::string test_id_;
  std::string format_;
  std::string out_;
  std::string config_;
  std::string units_ = formats::LsDynaUnitsName(formats::LsDynaUnits::kSi);
  int part_ = 1;
};

}  // namespace

std::unique_ptr<Command> MakeExportCommand() { return std::make_unique<ExportCommand>(); }

}  // namespace napkin::cli
