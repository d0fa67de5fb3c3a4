#pragma once
// The input formats napkin reads (docs/formats.md, one section each): the one
// table that says, for each, its name, how a test of it is recognised, which
// files a test spans, and its reader. Discovery (ingest/discovery.h), the
// dummy heads (ingest/dummy_heads.h), content hashes, zip archives, the
// inbox of `napkin serve`, `napkin transform` and the help texts all take
// what they need from it; adding a format is one row here, its reader and
// its fuzz target.
#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "common/error.h"
#include "engine/array_geometry.h"
#include "formats/channel_map.h"
#include "formats/test_info.h"

namespace napkin::ingest {

// kZipArchive: one test in a zip archive (ingest/zip_input.h).
enum class InputFormat { kCsv, kDtsSliceCsv, kIsoMme, kUds1992, kZipArchive };

// The files one test of a format spans.
enum class TestSpan {
  kFile,       // one file; the test is named after its stem (CSV, DTS SLICEWare CSV, zip)
  kFolder,     // a folder holding a file the format names (ISO-MME: the .mme file), with everything in it
  kFileGroup,  // the format's files of one folder and stem (UDS-1992: v0001.001 ... v0001.009 -> v0001)
};

// How a format's test becomes signals for the array's slots.
enum class ReaderKind {
  kSlotColumns,  // the file names the slots itself (napkin's CSV: a column per slot)
  kChannels,     // channels found by a channel map, one head per position (ISO-MME, UDS-1992, DTS)
  kArchive,      // a container of one test of another format (zip)
};

// One test found in the import paths.
struct ImportInput {
  InputFormat format = InputFormat::kCsv;
  // The default test id: file name without extension (kFile), folder name
  // (kFolder; the named file's stem when that file itself was given), the
  // group's shared stem (kFileGroup). A format whose files name the test
  // (DTS SLICEWare's Test ID) gives its id when read (ChannelRecording).
  std::string name;
  // The file or the test folder; for a kFileGroup "<folder>/<stem>.*" (its files are in `files`).
  std::filesystem::path source;
  std::vector<std::filesystem::path> files;  // kFileGroup members, sorted by name
};

// What a kChannels reader gives: the test's channels and what its files say about it.
struct ChannelRecording {
  std::string name;                                // the test's name in messages ("": the input's)
  std::optional<std::string> test_id;              // the id the files give the test (DTS Test ID)
  std::vector<formats::RawChannel> channels;       // with ISO/TS 13499 codes or UDS-1992 SENATT/AXIS
  std::vector<formats::TestInfo> info_of_channel;  // what the files say of the test, by channel
  std::vector<std::string> warnings;
};

struct InputFormatEntry {
  InputFormat format;
  std::string_view name;   // "csv", "dts-slice-csv", ...: metadata_json "format"
  std::string_view title;  // "DTS SLICEWare CSV": docs/formats.md's section, in sentences
  std::string_view kind;   // "DTS SLICEWare CSV export": one test of it, in lists (plural: + "s")
  std::string_view what;   // "a DTS SLICEWare CSV export (.csv)": what to give, in sentences
  TestSpan span;
  ReaderKind reader_kind;
  // A file that is a test of this format (kFolder: marks its folder as one), by its name.
  bool (*names_test)(const std::filesystem::path& file);
  // ... and by its first bytes, for formats sharing a name (nullptr: any content). Entries are
  // tried in table order; the first that takes a file has it.
  bool (*content_is)(std::string_view first_bytes);
  // A file a test of this format is made of (the members of a zip archive to unpack).
  bool (*is_part)(const std::filesystem::path& file);
  // kChannels: reads the test's channels (throws InputError naming the file).
  ChannelRecording (*read_channels)(const ImportInput& input);
  // kChannels: the channels' ISO/TS 13499 codes may define the array (ingest/array_from_codes.h).
  bool array_from_codes;
  // The files give the test its id (ChannelRecording::test_id), so the input's name is not it.
  bool names_its_test;
  // kChannels without a channel map: the slots the files' own order gives (UDS-1992: nine files
  // in the report's Table 2-1 order), or nullopt for the "default" map. nullptr: always the map.
  std::optional<std::vector<std::size_t>> (*assignment_by_order)(const ChannelRecording& recording,
                                                                 const engine::ArrayGeometry& array,
                                                                 const std::string& test_name);
  // The "default" map's refusal as this format says it (UDS-1992: why the map was used), or
  // nullptr for the map's own sentence.
  InputError (*default_map_refusal)(const InputError& refusal, std::size_t channel_count,
                                    const std::string& test_name);
};

// Every format, in the order files are tried: a file two formats name goes
// to the first whose content_is takes it.
std::span<const InputFormatEntry> InputFormats();
const InputFormatEntry& FormatEntry(InputFormat format);
const char* InputFormatName(InputFormat format);  // "csv", "dts-slice-csv", "iso-mme", "uds-1992", "zip"

// The format of `file` (a regular file whose name a format takes): read
// from its first bytes when formats share its name. nullopt: no format names
// it. Throws InputError naming the file when its first bytes cannot be read.
std::optional<InputFormat> FormatOfFile(const std::filesystem::path& file);
// Whether `file`'s name is one some format reads (before any is opened).
bool NamesSomeTest(const std::filesystem::path& file);
// The format whose tests are folders that `folder` is one of, by the files it holds.
std::optional<InputFormat> FormatOfFolder(const std::filesystem::path& folder);
// Whether a zip archive's member `name` is part of a test (ingest/zip_input.h).
bool IsTestPart(const std::filesystem::path& name);

// The files of one test: a kFileGroup's members, a kFolder's files (all of
// them, sorted), a kFile's file.
std::vector<std::filesystem::path> FilesOf(const ImportInput& input);

// "CSV files, DTS SLICEWare CSV exports, ISO-MME test folders, UDS-1992
// channel files and zip archives" (`kind` + "s", joined): for help texts.
std::string FormatList(std::string_view conjunction = "and");
// "no CSV file, ..., UDS-1992 channel file or zip archive" (`kind`, joined; archives left out
// where they cannot be: inside an archive).
std::string NoTestOfAnyFormat(bool archives = true);
// "a CSV file (.csv), ..., or a zip archive of one test (.zip)" (`what`, joined).
std::string WhatToGive();

}  // namespace napkin::ingest
