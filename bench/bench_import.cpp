// Import of a real-sized laboratory test (issue 10 acceptance): a generated
// ISO-MME test of 120 channels and two dummies (tests/support/
// isomme_generator.h: CRLF, ISO-8859-1 units, 2,000 samples per channel),
// imported into a new catalogue as a folder and as a zip archive. Each
// iteration imports both heads; the catalogue is set up outside the timing.
#include <benchmark/benchmark.h>
#include <unistd.h>

#include <filesystem>
#include <string>

#include "db/catalogue.h"
#include "ingest/import.h"
#include "tests/support/isomme_generator.h"
#include "tests/support/zip_writer.h"

namespace napkin::ingest {
namespace {

namespace fs = std::filesystem;

// A private folder holding the generated test as a folder and as a zip.
const fs::path& GeneratedTestFolder() {
  static const fs::path kFolder = [] {
    fs::path root = fs::temp_directory_path() / ("napkin-bench-import-" + std::to_string(::getpid()));
    fs::create_directories(root);
    test_support::WriteMultiDummyIsoMme(root / "MD0001");
    test_support::WriteZip(root / "MD0001.zip", test_support::FolderEntries(root / "MD0001", "MD0001/"));
    std::atexit([] {
      std::error_code ignored;
      fs::remove_all(fs::temp_directory_path() / ("napkin-bench-import-" + std::to_string(::getpid())),
                     ignored);
    });
    return root;
  }();
  return kFolder;
}

void ImportTwoDummyIsoMme(benchmark::State& state, const std::string& input) {
  const fs::path& root = GeneratedTestFolder();
  ImportOptions options;
  options.array = "6aw-cg";
  int round = 0;
  for (auto _ : state) {
    state.PauseTiming();
    const fs::path db_path = root / ("bench-" + std::to_string(round++) + ".db");
    db::Catalogue catalogue = db::Catalogue::Open(db_path.string());
    state.ResumeTiming();
    const ImportReport report = ImportTests(catalogue, {(root / input).string()}, options);
    if (report.imported != 2) state.SkipWithError("the generated test did not import its two heads");
    state.PauseTiming();
    fs::remove(db_path);
    state.ResumeTiming();
  }
}

void BM_ImportTwoDummyIsoMmeFolder(benchmark::State& state) { ImportTwoDummyIsoMme(state, "MD0001"); }
void BM_ImportTwoDummyIsoMmeZip(benchmark::State& state) { ImportTwoDummyIsoMme(state, "MD0001.zip"); }

BENCHMARK(BM_ImportTwoDummyIsoMmeFolder)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ImportTwoDummyIsoMmeZip)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace napkin::ingest
