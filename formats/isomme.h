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
#include "formats/test_info.h"

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

// The test-level information of `test` for the dummy whose head channel is
// `head_channel` (its code gives the test object, hence the vehicle, and the
// dummy type in fine location 3).
TestInfo IsoMmeTestInfo(const IsoMmeTest& test, const RawChannel& head_channel);

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

// What an ISO-MME export says about the channels (ISO/TS 13499 channel codes,
// docs/formats.md "ISO-MME export").
struct IsoMmeExportOptions {
  std::string position =
      "11";  // code characters 1-2: test object and seat position (11 driver, 13 passenger)
  std::string dummy_type = "00";  // fine location 3 (e.g. "H3"); "00" when not known
  // The CFC filters napkin applied (nullopt: none) to the linear
  // accelerometers, and to the angular-rate sensors when the array has them
  // (angular motion then comes from them; otherwise from the accelerometers).
  std::optional<double> linear_cfc;
  std::optional<double> angular_rate_cfc;
  bool angular_rate_sensors = false;
};

// ISO/TS 13499 filter class letter of a CFC: 0 (none), A (1000), B (600),
// C (180), D (60), X (another class).
char FilterClassLetter(std::optional<double> cfc);

// Writes the derived channels of one test as an ISO-MME folder (`export
// --format isomme`): head CG acceleration (g), velocity, displacement,
// angular velocity and acceleration in body (fine locations "0000") and
// fixed ("00GL") axes, roll/pitch/yaw ("00GL" AN) and DCOS ("00DC" AN) angles
// (deg), orientation quaternion ("00GL" QU). Every channel header carries
// `Channel frequency class`, `Reference channel` (implicit: the time base is
// `Time of first sample` and the exact decimal `Sampling interval`).
void WriteDerivedIsoMme(const engine::Kinematics& kinematics, const std::filesystem::path& folder,
                        const std::string& test_number, const IsoMmeExportOptions& options = {});

}  // namespace napkin::formats
