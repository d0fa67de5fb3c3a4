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

#include "engine/array_geometry.h"
#include "engine/signals.h"
#include "formats/channel_map.h"

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
  // FCUT: the channel's digital filter class (Hz; the SAE J211 CFC is the
  // passband frequency in Hz), 0 = unfiltered. A positive FCUT is the
  // channel's prefiltered_cfc (docs/formats.md "UDS-1992 input").
  double filter_cutoff_hz = 0.0;
  std::vector<double> values;  // NLP - NFP + 1 samples (REAL*4 precision)

  int nlp() const { return nfp + static_cast<int>(values.size()) - 1; }
};

// Reads one file. Throws InputError with one sentence naming the file and the
// problem (truncated record, wrong FILEVER, unknown NUMFORM, NLP < NFP, ...).
UdsChannel ReadUds1992(const std::filesystem::path& path);

// Writes one file in `channel.number_form` (atomically). Throws InputError
// when a value cannot be represented (e.g. beyond the VAX F-float range).
void WriteUds1992(const UdsChannel& channel, const std::filesystem::path& path);

// The channel as a RawChannel (unit from YUNITS, t0 = NFP * DEL,
// prefiltered_cfc = FCUT when positive).
RawChannel ToRawChannel(const UdsChannel& channel, const std::filesystem::path& path);

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
// channel map, slots are matched by SENATT/AXIS; without, exactly nine files
// are required and assigned in name order to the report's Table 2-1 slots
// (cg_x, cg_y, cg_z, yarm_z, yarm_x, xarm_z, xarm_y, zarm_x, zarm_y).
engine::TestSignals ReadUdsTest(const std::vector<std::filesystem::path>& files,
                                const engine::ArrayGeometry& array, const ChannelMap* map,
                                const std::string& test_name);

}  // namespace napkin::formats
