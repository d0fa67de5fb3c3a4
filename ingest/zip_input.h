#pragma once
// A zip archive given to `napkin import` is one test (docs/formats.md "Zip
// archives"): the members a test of some input format is made of (ISO-MME,
// UDS-1992, CSV, DTS SLICEWare CSV: ingest/input_formats.h) are read in memory with
// formats::ZipArchive (every name and size checked first) and written into a
// private temporary folder (mode 0700) that the readers of formats/ read and
// that is removed when the ArchiveTest goes out of scope, whatever happens,
// SIGINT and SIGTERM included (TemporaryFolder).
#include <filesystem>
#include <memory>
#include <string>

#include "formats/zip_archive.h"
#include "ingest/discovery.h"
#include "ingest/temporary_folder.h"

namespace napkin::ingest {

class ArchiveTest {
 public:
  // Throws InputError (one sentence naming the archive, and the member at
  // fault as "ARCHIVE.zip:MEMBER") on a bad or corrupt archive, an unsafe
  // member name, a zip bomb, a member over a ceiling, a member twice or as
  // both a file and a folder, a member the file system cannot hold (a name
  // too long), or an archive that holds no test or several.
  explicit ArchiveTest(const std::filesystem::path& archive, const formats::ZipLimits& limits = {});
  ~ArchiveTest();
  ArchiveTest(const ArchiveTest&) = delete;
  ArchiveTest& operator=(const ArchiveTest&) = delete;

  // The one test inside, found as DiscoverInputs finds tests in a folder;
  // its paths lie in the temporary folder.
  const ImportInput& input() const { return input_; }

  // `message` with the temporary folder's paths written as
  // "<archive>:<member name>".
  std::string InArchiveTerms(const std::string& message) const;

 private:
  std::filesystem::path archive_;
  std::unique_ptr<TemporaryFolder> folder_;  // where the members are unpacked
  ImportInput input_;
};

}  // namespace napkin::ingest
