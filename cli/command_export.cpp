// `napkin export`: one test's channels in one of the output formats of
// app/export.h (the derived channels of its latest result, or of the result
// under --config, stored or recomputed for storage "none", as CSV, JSON,
// LS-DYNA keyword load curves, the legacy LC_FILE.DAT, an ISO-MME folder or
// the report's UDS-1992 output files; or its raw channels). Reads the
// catalogue only; the output is written atomically, a folder format's files
// beside what the folder holds (docs/formats.md "Output destinations").
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "app/db_protection.h"
#include "app/export.h"
#include "app/request_options.h"
#include "cli/catalogue_option.h"
#include "cli/command.h"
#include "cli/option_checks.h"
#include "common/error.h"
#include "formats/array_json.h"
#include "records/config_record.h"

namespace napkin::cli {
namespace {

class ExportCommand : public Command {
 public:
  CLI::App* Setup(CLI::App& app, const GlobalOptions& global) override {
    global_ = &global;
    CLI::App* sub = app.add_subcommand("export", "write one test's derived channels");
    sub->add_option("--test", test_id_, "test id")->required();
    std::string formats_help;
    for (const app::ExportFormat& format : app::ExportFormats())
      formats_help += (formats_help.empty() ? "" : "; ") + std::string(format.name) + ": " +
                      std::string(format.description);
    sub->add_option("--format", format_, formats_help)
        ->required()
        ->check(OneOfCheck("--format", app::ExportFormatNames()));
    sub->add_option("--out", out_, "file to write (a folder for isomme and uds; - is standard output)")
        ->required()
        ->check(PathCheck("--out"));
    // The values below go to app::ParseExportRequest as given, which checks them and supplies the
    // defaults, as for the service's and Python's export (app/request_options.h).
    sub->add_option("--numform", numform_, "uds number form: ieee (default), vax or sun");
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
    sub->add_option("--units", units_, "lsdyna units: si (m, s; default) or english (in, s)");
    sub->add_option("--part", part_, "lsdyna rigid part id (default: 1)");
    return sub;
  }

  int Run() override {
    app::RequestOptions options(app::FrontEnd::kCommandLine);
    options.Add("format", format_);
    for (const auto& [name, value] : {std::pair{"config", &config_},
                                      {"units", &units_},
                                      {"part", &part_},
                                      {"numform", &numform_},
                                      {"position", &position_},
                                      {"dummy-type", &dummy_type_}})
      if (*value) options.Add(name, **value);
    const app::ExportRequest request = app::ParseExportRequest(test_id_, options);
    // The --config file this command reads is never its output (docs/formats.md
    // "Output destinations"); an unknown preset is reported where it is used.
    if (config_) {
      try {
        app::ProtectInputFromOutput(records::ProcessingConfigPath(*config_, formats::DefaultConfigDir()),
                                    "the --config file");
      } catch (const InputError&) {
      }
    }
    db::Catalogue catalogue = OpenCatalogue(*global_, /*read_only=*/true);
    app::Export(catalogue, request, out_, force_);
    return kExitOk;
  }

 private:
  const GlobalOptions* global_ = nullptr;
  std::string test_id_;
  std::string format_;
  std::string out_;
  bool force_ = false;
  std::optional<std::string> config_;
  std::optional<std::string> units_;
  std::optional<std::string> part_;
  std::optional<std::string> numform_;
  std::optional<std::string> position_;
  std::optional<std::string> dummy_type_;
};

}  // namespace

std::unique_ptr<Command> MakeExportCommand() { return std::make_unique<ExportCommand>(); }

}  // namespace napkin::cli
