#pragma once
// ISO-MME (ISO/TS 13499) test folders (docs/formats.md "ISO-MME input"):
// <folder>/<name>.mme, <folder>/Channel/<name>.chn and one text file per
// channel, <folder>/Channel/<name>.001 ...: header lines "key" blank-padded,
// ':', value; then one sample per line. Channel codes have 16 characters:
// test object (1), position (1), main location (4), fine locations 1-3
// (2 each), physical dimension (2), direction (1), filter class (1), e.g.
// 11HEAD0000H3ACXA.
#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "engine/array_geometry.h"
#include "engine/kinematics.h"
#include "engine/signals.h"
#include "formats/channel_map.h"

namespace napkin::formats {

struct IsoMmeTest {
  std::filesystem::path folder;
  std::string name;                                            // stem of <name>.mme
  std::vector<std::pair<std::string, std::string>> test_info;  // the .mme header lines
  std::vector<RawChannel> channels;                            // in .chn order

  // The .mme "Test number", else the file name.
  std::string TestNumber() const;
};

// The CFC class of an ISO/TS 13499 filter-class letter (the code's 16th
// character): A = CFC 1000, B = CFC 600, C = CFC 180, D = CFC 60; nullopt for
// '0' (unfiltered) and any other letter (class not stated). Case-insensitive.
std::optional<double> IsoMmeFilterClassOfLetter(char letter);
// The inverse for the four standard classes (1e-9 relative tolerance); nullopt otherwise.
std::optional<char> IsoMmeFilterLetter(double cfc);

// Reads a test folder (or its .mme file). Accepts LF and CRLF, UTF-8 and
// ISO-8859-1. A channel's prefiltered_cfc is its "Channel frequency class"
// header when that is a positive number, else the class of its code's
// filter letter. Throws InputError naming the file and the problem (missing
// header key, NOVALUE or non-numeric sample, fewer or more samples than
// declared, ...).
IsoMmeTest ReadIsoMme(const std::filesystem::path& folder_or_mme);

// Reads a test folder into signals for `array`, slots chosen by `map`.
engine::TestSignals ReadIsoMmeSignals(const std::filesystem::path& folder_or_mme,
                                      const engine::ArrayGeometry& array, const ChannelMap& map);

// The channel code the writer gives a slot: the map's first pattern with '?'
// replaced ('1' for test object and position, '0' elsewhere).
std::string CodeForSlot(const ChannelMap& map, const std::string& slot);

// Writes raw signals as an ISO-MME folder `folder` (atomically), channel codes
// from `map`, so that ReadIsoMmeSignals(folder, array, map) gives the same
// samples back (and each column's prefiltered_cfc, as "Channel frequency
// class" and, for a standard class, the code's filter letter). `test_number`
// names the .mme/.chn files.
void WriteIsoMme(const engine::TestSignals& signals, const engine::ArrayGeometry& array,
                 const ChannelMap& map, const std::filesystem::path& folder, const std::string& test_number);

// Writes the derived channels of one test as an ISO-MME folder (`export
// --format isomme`): head CG acceleration (g), velocity, displacement,
// angular velocity and acceleration in body ("00") and fixed ("FX") axes,
// roll/pitch/yaw and DCOS angles (deg), orientation quaternion.
void WriteDerivedIsoMme(const engine::Kinematics& kinematics, const std::filesystem::path& folder,
                        const std::string& test_number);

}  // namespace napkin::formats
