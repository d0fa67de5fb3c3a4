#pragma once
// DTS SLICEWare CSV exports (docs/formats.md "DTS SLICEWare CSV"): rows of
// test and channel information, each `Name,value per channel,` (trailing
// commas), down to `Data Starts Here`; then a column row
// `Time,Chan 0:<serial>,...` and one row per sample, the time in seconds
// (negative before the trigger) and each channel in its engineering unit.
// Channels carry ISO/TS 13499 channel codes (`ISO Channel Code`), so they
// reach the array's slots through a channel map as ISO-MME channels do.
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "formats/channel_map.h"
#include "formats/test_info.h"

namespace napkin::formats {

struct DtsSliceExport {
  std::filesystem::path file;
  std::string test_id;  // `Test ID` ("" when the export gives none)
  TestInfo info;        // test_number (Test ID), title (Test Description), date (Test Date and Time)
  // One per data column, in column order: code, unit (`Engineering Unit`),
  // sampling from `Sample Rate (Hz)` and the time column, prefiltered_cfc
  // from `Software Filter (SAE Class)`, serial (`Sensor S/N`) and
  // hardware_filter_hz (`Hardware AA Filter (-3dB)`); position from the code.
  std::vector<RawChannel> channels;
};

// Whether `first_bytes` (the start of a file, a UTF-8 byte order mark allowed)
// begin a SLICEWare export: the first row's first cell is `Headers`.
bool LooksLikeDtsSliceCsv(std::string_view first_bytes);

// Reads an export. Accepts LF and CRLF, trailing commas, UTF-8 and
// Windows' ISO-8859-1 text. Throws InputError, one sentence naming the file,
// the row (file line) and the channel at fault: a required row missing (`ISO
// Channel Code`, `Engineering Unit`, `Sample Rate (Hz)`, `Data Starts Here`),
// a channel row with fewer values than channels, an unknown unit of a head
// accelerometer or angular-rate channel (codes ..HEAD......AC/AV..), a head
// channel code whose direction is no body axis (it maps to no slot),
// channels of different sample rates, a software filter that is no SAE
// class, a data row with too few values or a value that is no finite
// number, a time column that disagrees with the sample rate.
DtsSliceExport ReadDtsSliceCsv(const std::filesystem::path& path);

}  // namespace napkin::formats
