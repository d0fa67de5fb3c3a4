#include "ingest/input_formats.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cstring>

#include "formats/dts_slice_csv.h"
#include "formats/isomme.h"
#include "formats/json_file.h"
#include "formats/uds1992.h"
#include "util/text.h"

namespace napkin::ingest {
namespace fs = std::filesystem;

namespace {

// How many bytes of a file tell formats sharing a name apart.
constexpr std::size_t kFirstBytes = 4096;

bool HasExtension(const fs::path& path, std::string_view extension) {
  return util::EqualsIgnoreCase(path.extension().string(), extension);
}

// Numbered channel files: v0001.001 ... v0001.009 (UDS-1992; ISO-MME's channel files too).
bool HasNumberedExtension(const fs::path& path) {
  const std::string extension = path.extension().string();
  return extension.size() == 4 && extension.find_first_not_of("0123456789", 1) == std::string::npos;
}

bool IsCsvName(const fs::path& file) { return HasExtension(file, ".csv"); }
bool IsMmeName(const fs::path& file) { return HasExtension(file, ".mme"); }
bool IsZipName(const fs::path& file) { return HasExtension(file, ".zip"); }
bool IsIsoMmePart(const fs::path& file) {
  return IsMmeName(file) || HasExtension(file, ".chn") || HasNumberedExtension(file);
}
bool IsNoPart(const fs::path&) { return false; }

ChannelRecording ReadIsoMmeChannels(const ImportInput& input) {
  formats::IsoMmeTest test = formats::ReadIsoMme(input.source);
  ChannelRecording recording;
  recording.name = test.TestNumber();
  for (const formats::RawChannel& channel : test.channels)
    recording.info_of_channel.push_back(formats::IsoMmeTestInfo(test, channel));
  recording.channels = std::move(test.channels);
  return recording;
}

ChannelRecording ReadUdsChannels(const ImportInput& input) {
  ChannelRecording recording;
  for (const fs::path& file : input.files) {
    const formats::UdsChannel channel = formats::ReadUds1992(file);
    recording.warnings.insert(recording.warnings.end(), channel.warnings.begin(), channel.warnings.end());
    recording.info_of_channel.push_back(formats::UdsTestInfo(channel));
    recording.channels.push_back(formats::ToRawChannel(channel, file));
  }
  return recording;
}

// Report section 2.2: nine files in Table 2-1 order need no map.
std::optional<std::vector<std::size_t>> UdsTableTwoOneOrder(const ChannelRecording& recording,
                                                            const engine::ArrayGeometry& array,
                                                            const std::string& test_name) {
  if (!formats::InTableTwoOneOrder(recording.channels.size(), array)) return std::nullopt;
  return formats::TableTwoOneAssignment(array, test_name);
}

ChannelRecording ReadDtsChannels(const ImportInput& input) {
  formats::DtsSliceExport dts = formats::ReadDtsSliceCsv(input.source);
  ChannelRecording recording;
  recording.name = dts.test_id;
  if (!dts.test_id.empty()) recording.test_id = dts.test_id;
  for (const formats::RawChannel& channel : dts.channels) {
    formats::TestInfo info = dts.info;
    // The dummy's type is the code's fine location 3, as for ISO-MME (formats/isomme.h).
    if (channel.code.size() == 16 && channel.code.substr(10, 2) != "00")
      info.dummy = channel.code.substr(10, 2);
    recording.info_of_channel.push_back(std::move(info));
  }
  recording.channels = std::move(dts.channels);
  return recording;
}

// The table (docs/formats.md has a section per row). A DTS SLICEWare export is a .csv file
// told by its first row, so it comes before napkin's CSV, which takes any .csv file.
constexpr std::array<InputFormatEntry, 5> kFormats = {{
    {InputFormat::kDtsSliceCsv, "dts-slice-csv", "DTS SLICEWare CSV", "DTS SLICEWare CSV export",
     "a DTS SLICEWare CSV export (.csv)", TestSpan::kFile, ReaderKind::kChannels, IsCsvName,
     formats::LooksLikeDtsSliceCsv, IsCsvName, ReadDtsChannels, true, true, nullptr, nullptr},
    {InputFormat::kCsv, "csv", "CSV", "CSV file", "a CSV file (.csv)", TestSpan::kFile,
     ReaderKind::kSlotColumns, IsCsvName, nullptr, IsCsvName, nullptr, false, false, nullptr, nullptr},
    {InputFormat::kIsoMme, "iso-mme", "ISO-MME", "ISO-MME test folder", "an ISO-MME test folder or .mme file",
     TestSpan::kFolder, ReaderKind::kChannels, IsMmeName, nullptr, IsIsoMmePart, ReadIsoMmeChannels, true,
     false, nullptr, nullptr},
    {InputFormat::kUds1992, "uds-1992", "UDS-1992", "UDS-1992 channel file",
     "a UDS-1992 channel file (.001 ...)", TestSpan::kFileGroup, ReaderKind::kChannels, HasNumberedExtension,
     nullptr, HasNumberedExtension, ReadUdsChannels, false, false, UdsTableTwoOneOrder,
     formats::DefaultMapError},
    {InputFormat::kZipArchive, "zip", "zip archive", "zip archive", "a zip archive of one test (.zip)",
     TestSpan::kFile, ReaderKind::kArchive, IsZipName, nullptr, IsNoPart, nullptr, false, false, nullptr,
     nullptr},
}};

// The first bytes of regular file `file`, judged on the descriptor opened (O_NONBLOCK: a FIFO
// put there since it was looked at never blocks).
std::string FirstBytes(const fs::path& file) {
  const auto refuse = [&](int error) {
    throw InputError("'" + util::EscapeControl(file.string()) + "' cannot be read (" + std::strerror(error) +
                     ").");
  };
  const int fd = ::open(file.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) refuse(errno);
  struct Closer {
    int fd;
    ~Closer() { ::close(fd); }
  } closer{fd};
  struct stat status {};
  if (::fstat(fd, &status) != 0) refuse(errno);
  if (!S_ISREG(status.st_mode))
    throw InputError("'" + util::EscapeControl(file.string()) + "' is " +
                     formats::FileTypeName(status.st_mode) +
                     ", not a regular file; napkin reads only regular files.");
  std::string bytes(kFirstBytes, '\0');
  std::size_t filled = 0;
  while (filled < bytes.size()) {
    const ssize_t n = ::read(fd, bytes.data() + filled, bytes.size() - filled);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) refuse(errno);
    if (n == 0) break;
    filled += static_cast<std::size_t>(n);
  }
  bytes.resize(filled);
  return bytes;
}

std::string Joined(const std::vector<std::string>& items, std::string_view conjunction) {
  // Appended piece by piece, not `" " + temporary` (GCC 12's false -Wrestrict, util/text.h InQuotes).
  std::string list;
  for (std::size_t i = 0; i < items.size(); ++i) {
    if (i + 1 == items.size() && i > 0) {
      list += ' ';
      list += conjunction;
      list += ' ';
    } else if (i > 0) {
      list += ", ";
    }
    list += items[i];
  }
  return list;
}

}  // namespace

std::span<const InputFormatEntry> InputFormats() { return kFormats; }

const InputFormatEntry& FormatEntry(InputFormat format) {
  for (const InputFormatEntry& entry : kFormats)
    if (entry.format == format) return entry;
  throw std::logic_error("napkin: input format " + std::to_string(static_cast<int>(format)) +
                         " is not in the table.");
}

const char* InputFormatName(InputFormat format) { return FormatEntry(format).name.data(); }

bool NamesSomeTest(const fs::path& file) {
  return std::any_of(kFormats.begin(), kFormats.end(),
                     [&](const InputFormatEntry& entry) { return entry.names_test(file); });
}

std::optional<InputFormat> FormatOfFile(const fs::path& file) {
  std::optional<std::string> first_bytes;
  for (const InputFormatEntry& entry : kFormats) {
    if (!entry.names_test(file)) continue;
    if (entry.content_is == nullptr) return entry.format;
    if (!first_bytes) first_bytes = FirstBytes(file);
    if (entry.content_is(*first_bytes)) return entry.format;
  }
  return std::nullopt;
}

std::optional<InputFormat> FormatOfFolder(const fs::path& folder) {
  std::error_code error;
  for (const InputFormatEntry& entry : kFormats) {
    if (entry.span != TestSpan::kFolder) continue;
    for (const auto& item : fs::directory_iterator(folder, error))
      if (item.is_regular_file(error) && entry.names_test(item.path())) return entry.format;
  }
  return std::nullopt;
}

bool IsTestPart(const fs::path& name) {
  return std::any_of(kFormats.begin(), kFormats.end(),
                     [&](const InputFormatEntry& entry) { return entry.is_part(name); });
}

std::vector<fs::path> FilesOf(const ImportInput& input) {
  switch (FormatEntry(input.format).span) {
    case TestSpan::kFileGroup:
      return input.files;
    case TestSpan::kFile:
      return {input.source};
    case TestSpan::kFolder:
      break;
  }
  std::vector<fs::path> files;
  std::error_code error;
  for (fs::recursive_directory_iterator it(input.source, error), end; !error && it != end;
       it.increment(error))
    if (it->is_regular_file(error)) files.push_back(it->path());
  std::sort(files.begin(), files.end());
  return files;
}

std::string FormatList(std::string_view conjunction) {
  std::vector<std::string> kinds;
  for (const InputFormatEntry& entry : kFormats) kinds.push_back(std::string(entry.kind) + "s");
  return Joined(kinds, conjunction);
}

std::string NoTestOfAnyFormat(bool archives) {
  std::vector<std::string> kinds;
  for (const InputFormatEntry& entry : kFormats)
    if (archives || entry.reader_kind != ReaderKind::kArchive) kinds.emplace_back(entry.kind);
  return "no " + Joined(kinds, "or");
}

std::string WhatToGive() {
  std::vector<std::string> what;
  for (const InputFormatEntry& entry : kFormats) what.emplace_back(entry.what);
  return Joined(what, "or");
}

}  // namespace napkin::ingest
