#pragma once
// Finding the tests in the paths given to `napkin import`: CSV files,
// ISO-MME test folders and UDS-1992 channel files grouped by folder and stem.
#include <filesystem>
#include <string>
#include <vector>

namespace napkin::ingest {

// kZipArchive: one test in a zip archive (ingest/zip_input.h).
enum class InputFormat { kCsv, kIsoMme, kUds1992, kZipArchive };
const char* InputFormatName(InputFormat format);  // "csv", "iso-mme", "uds-1992", "zip"

// One test found in the import paths.
struct ImportInput {
  InputFormat format = InputFormat::kCsv;
  // The default test id: file name without extension (CSV), folder name
  // (ISO-MME; the .mme file's stem when the .mme file itself was given), or
  // the shared stem of a UDS-1992 group (v0001.001 ... v0001.009 -> v0001).
  std::string name;
  // The CSV file or the ISO-MME test folder; for a UDS-1992 group
  // "<folder>/<stem>.*" (its files are in `files`).
  std::filesystem::path source;
  std::vector<std::filesystem::path> files;  // UDS-1992 group members, sorted by name
};

struct Discovery {
  std::vector<ImportInput> inputs;  // in path order; tests inside a folder sorted by name
  std::vector<std::string> errors;  // one sentence per path that holds no test
};

// Finds the tests in `paths`:
// - a file *.csv: one CSV test; *.mme: the ISO-MME test folder around it;
//   a file whose extension is three digits (.001): a UDS-1992 channel file,
//   grouped with the other given UDS-1992 files of its folder and stem;
//   *.zip: one test inside a zip archive (its name without .zip is the test id);
// - a folder holding a *.mme file: one ISO-MME test;
// - any other folder: every test inside it, searched recursively (CSV files,
//   ISO-MME test folders, UDS-1992 stem groups, zip archives; other files are
//   ignored).
// A path that does not exist, an unrecognised file or a folder without any
// test is reported in `errors`.
Discovery DiscoverInputs(const std::vector<std::string>& paths);

}  // namespace napkin::ingest
