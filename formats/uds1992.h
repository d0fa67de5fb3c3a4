#pragma once
// NHTSA UDS-1992 signal files (docs/formats.md "UDS-1992 input"): 512-byte records
// — file header (FILEVER "UDS-1992"), optional component-2 header ("CMP-2
// HDR"), curve header ("CURVE HDR"), then "Y DATA" records of 125 4-byte
// reals. Field layout per the NHTSA UDS library (S. G. Mentzer, UDS_SPEC_LIST
// and UDSIOX): strings are blank-padded CHARACTER fields, integers and reals
// 4 bytes in the file's NUMFORM (IEEE and VAX little-endian, SUN big-endian).
#include <array>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "common/error.h"
#include "engine/array_geometry.h"
#include "engine/signals.h"
#include "formats/channel_map.h"
#include "formats/test_info.h"

namespace napkin::formats {

enum class UdsNumberForm { kIeee, kVax, kSun };
const char* UdsNumberFormName(UdsNumberForm form);

inline constexpr std::size_t kUdsRecordBytes = 512;
inline constexpr std::size_t kUdsValuesPerRecord = 125;

// One UDS-1992 file = one channel.
struct UdsChannel {
  UdsNumberForm number_form = UdsNumberForm::kIeee;
  std::string dimsys = "MET";  // MET, SI or ENG
  int test_number = 0;         // TSTNO
  std::string test_name;       // TSTNAM
  std::string title;           // TITLE
  std::string test_source;     // TSTSRC (the laboratory)
  std::string make;            // MAKE
  std::string model;           // MODEL
  std::string occupant_type;   // OCCTYP (dummy type)
  std::string dummy_size;      // DUMSIZ
  std::string curve_name;      // CURNAM
  std::string senatt;          // sensor attachment, e.g. "HEAD CG"
  std::string senloc;          // SENLOC
  std::string axis;            // e.g. "XL"
  std::string ytyp = "ACCELERATION";
  std::string yunits = "G'S";
  std::string xtyp = "TIME";
  std::string xunits = "SECONDS";
  std::string curve_description;  // CURDSC
  int nfp = 0;                    // index of the first sample (sample i is at i * del)
  double del_s = 1e-4;            // sampling interval (stored as REAL*4)
  double initial_velocity = 0.0;  // INIVEL
  // PREF: cut-off (Hz) of the recorder's analog anti-aliasing prefilter; 0 = not stated.
  // Informative only: it does not make the channel CFC-filtered.
  double prefilter_hz = 0.0;
  // FCUT: the cut-off frequency (Hz) of the last filter applied to the data
  // (NHTSA-Tools doc/UDS_Vars.txt), 0 = unfiltered. A J211 cut-off (100, 300,
  // 1000, 1650 Hz) is that class's channel: prefiltered_cfc CFC 60, 180, 600,
  // 1000; any other positive FCUT is a filter of unknown class, with a
  // warning (docs/formats.md "UDS-1992 input").
  double filter_cutoff_hz = 0.0;
  std::vector<double> values;         // NLP - NFP + 1 samples (REAL*4 precision)
  std::vector<std::string> warnings;  // what the reader noticed but read anyway (NCHAN above 1, FCUT)

  int nlp() const { return nfp + static_cast<int>(values.size()) - 1; }
};

// Reads one file. Throws InputError with one sentence naming the file and the
// problem (truncated record, wrong FILEVER, unknown NUMFORM, NLP < NFP, ...).
// NCHAN above 1 (the test's channel count, as NHTSA's files often carry) is
// read as NHTSA's own reader does: the file's one curve, with a warning.
UdsChannel ReadUds1992(const std::filesystem::path& path);

// Writes one file in `channel.number_form` (atomically). Throws InputError
// when a value cannot be represented (e.g. beyond the VAX F-float range).
void WriteUds1992(const UdsChannel& channel, const std::filesystem::path& path);

// The channel as a RawChannel (unit from YUNITS, t0 = NFP * DEL, position
// from SENLOC, INIVEL converted to m/s: km/h for DIMSYS MET, m/s for SI,
// mph for ENG, prefiltered_cfc the SAE J211 class whose cut-off FCUT is,
// engine::kPrefilteredClassUnknown for another positive FCUT).
RawChannel ToRawChannel(const UdsChannel& channel, const std::filesystem::path& path);

// The test-level information of a UDS-1992 file header.
TestInfo UdsTestInfo(const UdsChannel& channel);

// Whether `file_count` files without a channel map are read in the report's
// Table 2-1 order: nine files, and every slot of `array` a Table 2-1 slot.
bool InTableTwoOneOrder(std::size_t file_count, const engine::ArrayGeometry& array);
// The error of the "default" map for a group of `file_count` files given
// without a map and not in Table 2-1 order: `error` (the map's sentence),
// saying why the map was used, as one sentence.
InputError DefaultMapError(const InputError& error, std::size_t file_count, const std::string& test_name);
// For each sensor of `array`, the index of its file in Table 2-1 order.
std::vector<std::size_t> TableTwoOneAssignment(const engine::ArrayGeometry& array,
                                               const std::string& test_name);

// VAX F_floating <-> value. The four bytes are as stored: two little-endian
// 16-bit words, the first holding sign (bit 15), excess-128 exponent (bits
// 14-7) and the high fraction bits (6-0), the second the low 16 fraction
// bits; value = 0.1f (binary, hidden bit) * 2^(exponent-128). 1.0 is stored as
// bytes 80 40 00 00 (the longword 0x00004080).
// Decoding returns false for the reserved operand (sign 1, exponent 0).
bool DecodeVaxF(const std::uint8_t bytes[4], double& value);
// Encoding returns false when |value| exceeds the F_floating range
// (about 1.7e38); values below the smallest normal number become 0.
bool EncodeVaxF(float value, std::uint8_t bytes[4]);

// Groups files of one test by stem: v0001.001 ... v0001.009 -> "v0001". Groups
// and the files in each are sorted by name.
std::vector<std::pair<std::string, std::vector<std::filesystem::path>>> GroupUdsFilesByStem(
    const std::vector<std::filesystem::path>& files);

// Reads the UDS-1992 files of one test into signals for `array`. With a
// channel map, slots are matched by SENATT/AXIS; without, nine files for an
// array of Table 2-1 slots are assigned in name order to the report's Table
// 2-1 slots (cg_x, cg_y, cg_z, yarm_z, yarm_x, xarm_z, xarm_y, zarm_x,
// zarm_y), and any other group is matched through the "default" map.
// The files' warnings are appended to `warnings` when given.
engine::TestSignals ReadUdsTest(const std::vector<std::filesystem::path>& files,
                                const engine::ArrayGeometry& array, const ChannelMap* map,
                                const std::string& test_name, std::vector<std::string>* warnings = nullptr);

}  // namespace napkin::formats
