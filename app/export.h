#pragma once
// One test's channels written in an output format (`napkin export`, GET
// /api/v1/tests/ID/channels, napkin.Catalogue.export; docs/formats.md
// "Derived channels" and the sections of each format). The formats are one
// table (osmium-tool's ExportFormat and its factory are the pattern): a row
// per format with its name, what it is, what it needs (a result's derived
// channels, a result's raw channels, or the test alone), whether it is a
// folder of files, and its writer. Every front end reads the same options
// with one parser (ParseExportRequest) and writes through the same writer, so
// a format's bytes are the same whichever front end asked.
#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "app/request_options.h"
#include "app/result_selection.h"
#include "db/catalogue.h"
#include "formats/lsdyna.h"
#include "formats/uds1992.h"

namespace napkin::app {

// What a format is written from.
enum class ExportInput {
  kDerived,           // the result's derived channels (stored, or recomputed: app/result_selection.h)
  kResultChannels,    // the raw channels the result was computed from (salvage's repairs in place)
  kRecordedChannels,  // the raw channels as recorded: the test alone, no result needed
};

struct ExportRequest;
// What a format is written from: the test, its result (none for the recorded
// channels) and the format's input read from them (app/export.cpp).
struct ExportSource;

struct ExportFormat {
  std::string_view name;         // --format, format=
  std::string_view description;  // one line, for the help and the docs
  ExportInput input = ExportInput::kDerived;
  // kDerived: the format needs the rotation (an acceleration-only test has none).
  bool needs_rotation = false;
  // A folder of files (--out names a folder; the service sends it as a zip archive).
  bool folder = false;
  std::string_view extension;     // of the one file (".csv"), empty for a folder
  std::string_view content_type;  // how the service sends it
  // Writes `source` to `out`: the file, or the folder to fill (it exists, empty).
  void (*write)(const ExportSource& source, const ExportRequest& request, const std::filesystem::path& out);
};

// Every format, in the order the help lists them.
std::span<const ExportFormat> ExportFormats();
// The format named `name`, or nullptr.
const ExportFormat* FindExportFormat(std::string_view name);
// The formats' names, in table order.
std::vector<std::string> ExportFormatNames();

struct ExportRequest {
  std::string test_id;
  const ExportFormat* format = nullptr;
  // Whose result: the latest; the command line's --config is a preset or JSON
  // file (Preset, as for `napkin run`), the service's and Python's config= a
  // stored config's name or hash prefix (Stored, as their channels).
  ResultChoice result = Latest{};
  formats::LsDynaOptions lsdyna;                                       // lsdyna: units, part
  formats::UdsNumberForm number_form = formats::UdsNumberForm::kIeee;  // uds: numform
  // isomme: the channel codes' position and dummy type (default: the test's
  // stored metadata "position" / "dummy_type", else 11 and 00).
  std::optional<std::string> position;
  std::optional<std::string> dummy_type;
};

// The export of test `test_id` (the command's --test, the service's route,
// Python's test_id) as the options ask, one parser for every front end:
// format (required), config, units (si or english; default si), part (a
// whole number of at least 1; default 1), numform (ieee, vax or sun; default
// ieee), position, dummy-type. Throws UsageError, one sentence naming the
// option as the front end spells it, for an unknown, repeated or malformed
// option.
ExportRequest ParseExportRequest(std::string test_id, const RequestOptions& options);

// Writes the export to `out`: the file ("-" is standard output), or for a
// folder format the folder whose files appear beside what it holds, none of
// them replaced unless `replace_existing` (util/atomic_file.h
// WriteDirectoryAtomically). Throws NotFoundError for a test the catalogue
// (Catalogue::path) does not hold, InputError for a test without the result the
// format needs, or without the rotation it needs, and for a folder format to
// standard output, each one sentence naming the test or format; and the
// writers' errors, naming the file.
void Export(db::Catalogue& catalogue, const ExportRequest& request, const std::filesystem::path& out,
            bool replace_existing = false);

// One file of an export, written in memory.
struct ExportedFile {
  std::string name;  // the file's name; for a folder format its path inside the folder ("Channel/T.chn")
  std::string bytes;
};

// The export as Export writes it (the same writer), in memory: the one file,
// named after the test (util::FileNameComponent) and the format's extension,
// or every file of the folder, in name order. Staged in a private folder under
// the temporary folder (util/temporary_directory.h), removed before it
// returns; the writers' sentences name the file as it is named here. Throws
// as Export.
std::vector<ExportedFile> ExportToMemory(db::Catalogue& catalogue, const ExportRequest& request);

}  // namespace napkin::app
