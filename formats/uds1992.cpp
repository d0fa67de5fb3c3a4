#include "formats/uds1992.h"

#include <algorithm>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstring>
#include <map>
#include <span>

#include "common/error.h"
#include "engine/cfc_filter.h"
#include "formats/json_file.h"
#include "util/atomic_file.h"
#include "util/text.h"

namespace napkin::formats {
namespace {

// Byte offsets in the 512-byte records (NHTSA UDS library field order and
// lengths: FILEVER*12, NCHAN, FILEFORM*10, NUMFORM*5, DIMSYS*3, TSTSRC*15,
// TSTNO, TSTNAM*12, TITLE*70, ...; ICHAN, CHANFORM*10, CURNO, CURNAM*12,
// SENATT*30, SENLOC*2, SENNUM, BANDNO, GAGNO, AXIS*2, YTYP*20, YUNITS*20,
// XTYP*20, XUNITS*20, STATUS*20, CURTYP*20, CURDSC*70, NFP, NLP, DEL, ...).
struct HeaderField {
  std::size_t offset;
  std::size_t length;
};
namespace file_header {
constexpr HeaderField kFilever{0, 12};
constexpr std::size_t kNchan = 12;
constexpr HeaderField kFileform{16, 10};
constexpr HeaderField kNumform{26, 5};
constexpr HeaderField kDimsys{31, 3};
constexpr HeaderField kTstsrc{34, 15};
constexpr std::size_t kTstno = 49;
constexpr HeaderField kTstnam{53, 12};
constexpr HeaderField kTitle{65, 70};
constexpr HeaderField kMake{217, 15};
constexpr HeaderField kModel{232, 25};
constexpr HeaderField kOcctyp{298, 6};
constexpr HeaderField kDumsiz{313, 2};
// Remaining blank-padded strings: TSTPRF, TSTREF, TSTCFN, CMPTYP, CMPDSC, MAKE,
// MODEL, BODY, ENGINE, OCCTYP, OCCSEX, DUMSIZ, RESTR1, RESTR2, AIS, HDR_RESV.
constexpr HeaderField kOtherStrings[] = {{135, 25}, {160, 10}, {170, 3}, {185, 2},  {187, 30}, {217, 15},
                                         {232, 25}, {261, 25}, {286, 4}, {298, 6},  {308, 1},  {313, 2},
                                         {315, 20}, {335, 20}, {379, 1}, {380, 132}};
}  // namespace file_header
namespace curve_header {
constexpr HeaderField kRecordHeader{0, 12};
constexpr std::size_t kIchan = 12;
constexpr HeaderField kChanform{16, 10};
constexpr std::size_t kCurno = 26;
constexpr HeaderField kCurnam{30, 12};
constexpr HeaderField kSenatt{42, 30};
constexpr HeaderField kSenloc{72, 2};
constexpr HeaderField kAxis{86, 2};
constexpr HeaderField kYtyp{88, 20};
constexpr HeaderField kYunits{108, 20};
constexpr HeaderField kXtyp{128, 20};
constexpr HeaderField kXunits{148, 20};
constexpr HeaderField kStatus{168, 20};
constexpr HeaderField kCurtyp{188, 20};
constexpr HeaderField kCurdsc{208, 70};
constexpr std::size_t kNfp = 278;
constexpr std::size_t kNlp = 282;
constexpr std::size_t kDel = 286;
constexpr std::size_t kInivel = 290;
constexpr std::size_t kPref = 294;  // then FCUT, FCOR, FSTP, SCLFAC, ID1-5, RD1-5
constexpr std::size_t kFcut = 298;
// CD1*20, CD2*70, CURV_RESV*68.
constexpr HeaderField kOtherStrings[] = {{354, 20}, {374, 70}, {444, 68}};
}  // namespace curve_header
constexpr HeaderField kRecordHeader{0, 12};
constexpr std::size_t kDataOffset = 12;

using Record = const std::uint8_t*;

// A CHARACTER field, blanks trimmed, in UTF-8: UDS-1992 text is ASCII or,
// in practice, ISO-8859-1 (docs/formats.md "Text encoding"); a field that is
// already valid UTF-8 (napkin's own exports) is kept as it is.
std::string ReadString(Record record, HeaderField field) {
  std::string text(reinterpret_cast<const char*>(record + field.offset), field.length);
  return util::ToUtf8(std::string(util::Trim(text)));
}

void WriteString(std::uint8_t* record, HeaderField field, std::string_view text) {
  std::memset(record + field.offset, ' ', field.length);
  std::memcpy(record + field.offset, text.data(), std::min(text.size(), field.length));
}

// The channel's text fields, header by header: ReadUds1992 reads and
// WriteUds1992 writes each of them through this one table (TSTSRC apart:
// written as NAPKIN when the channel names no laboratory).
struct TextField {
  HeaderField field;
  std::string UdsChannel::*member;
};
constexpr TextField kFileHeaderTexts[] = {
    {file_header::kDimsys, &UdsChannel::dimsys},    {file_header::kTstnam, &UdsChannel::test_name},
    {file_header::kTitle, &UdsChannel::title},      {file_header::kMake, &UdsChannel::make},
    {file_header::kModel, &UdsChannel::model},      {file_header::kOcctyp, &UdsChannel::occupant_type},
    {file_header::kDumsiz, &UdsChannel::dummy_size}};
constexpr TextField kCurveHeaderTexts[] = {{curve_header::kCurnam, &UdsChannel::curve_name},
                                           {curve_header::kSenatt, &UdsChannel::senatt},
                                           {curve_header::kSenloc, &UdsChannel::senloc},
                                           {curve_header::kAxis, &UdsChannel::axis},
                                           {curve_header::kYtyp, &UdsChannel::ytyp},
                                           {curve_header::kYunits, &UdsChannel::yunits},
                                           {curve_header::kXtyp, &UdsChannel::xtyp},
                                           {curve_header::kXunits, &UdsChannel::xunits},
                                           {curve_header::kCurdsc, &UdsChannel::curve_description}};

void ReadTexts(Record record, std::span<const TextField> fields, UdsChannel& channel) {
  for (const TextField& text : fields) channel.*text.member = ReadString(record, text.field);
}

void WriteTexts(std::uint8_t* record, std::span<const TextField> fields, const UdsChannel& channel) {
  for (const TextField& text : fields) WriteString(record, text.field, channel.*text.member);
}

bool BigEndian(UdsNumberForm form) { return form == UdsNumberForm::kSun; }

std::uint32_t ReadWord(Record record, std::size_t offset, UdsNumberForm form) {
  const std::uint8_t* b = record + offset;
  if (BigEndian(form))
    return (std::uint32_t{b[0]} << 24) | (std::uint32_t{b[1]} << 16) | (std::uint32_t{b[2]} << 8) | b[3];
  return (std::uint32_t{b[3]} << 24) | (std::uint32_t{b[2]} << 16) | (std::uint32_t{b[1]} << 8) | b[0];
}

void WriteWord(std::uint8_t* record, std::size_t offset, std::uint32_t word, UdsNumberForm form) {
  std::uint8_t* b = record + offset;
  if (BigEndian(form)) {
    b[0] = static_cast<std::uint8_t>(word >> 24);
    b[1] = static_cast<std::uint8_t>(word >> 16);
    b[2] = static_cast<std::uint8_t>(word >> 8);
    b[3] = static_cast<std::uint8_t>(word);
  } else {
    b[3] = static_cast<std::uint8_t>(word >> 24);
    b[2] = static_cast<std::uint8_t>(word >> 16);
    b[1] = static_cast<std::uint8_t>(word >> 8);
    b[0] = static_cast<std::uint8_t>(word);
  }
}

std::int32_t ReadInt(Record record, std::size_t offset, UdsNumberForm form) {
  return static_cast<std::int32_t>(ReadWord(record, offset, form));
}

// A REAL*4 in the file's number form; false for a VAX reserved operand.
bool ReadReal(Record record, std::size_t offset, UdsNumberForm form, double& value) {
  if (form == UdsNumberForm::kVax) return DecodeVaxF(record + offset, value);
  value = static_cast<double>(std::bit_cast<float>(ReadWord(record, offset, form)));
  return true;
}

bool WriteReal(std::uint8_t* record, std::size_t offset, double value, UdsNumberForm form) {
  const float single = static_cast<float>(value);
  if (form == UdsNumberForm::kVax) return std::isfinite(single) && EncodeVaxF(single, record + offset);
  if (!std::isfinite(single)) return false;
  WriteWord(record, offset, std::bit_cast<std::uint32_t>(single), form);
  return true;
}

// The decimal a REAL*4 stands for: DEL = 1e-4 is stored as 9.99999975e-05,
// which was meant as 0.0001 (shortest decimal that reads back to the same float).
double IntendedDecimalOfSingle(double stored) {
  const float single = static_cast<float>(stored);
  char buffer[32];
  const auto result = std::to_chars(buffer, buffer + sizeof(buffer), single);
  double value = stored;
  std::from_chars(buffer, result.ptr, value);
  return value;
}

// Input quoted in a message: control characters escaped, a huge value cut (util/text.h).
}  // namespace

const char* UdsNumberFormName(UdsNumberForm form) {
  switch (form) {
    case UdsNumberForm::kIeee:
      return "IEEE";
    case UdsNumberForm::kVax:
      return "VAX";
    case UdsNumberForm::kSun:
      return "SUN";
  }
  return "IEEE";
}

bool DecodeVaxF(const std::uint8_t bytes[4], double& value) {
  const std::uint32_t high_word = std::uint32_t{bytes[0]} | (std::uint32_t{bytes[1]} << 8);
  const std::uint32_t low_word = std::uint32_t{bytes[2]} | (std::uint32_t{bytes[3]} << 8);
  const bool negative = (high_word & 0x8000u) != 0;
  const int exponent = static_cast<int>((high_word >> 7) & 0xFFu);
  const std::uint32_t fraction = ((high_word & 0x7Fu) << 16) | low_word;
  if (exponent == 0) {
    value = 0.0;
    return !negative;  // sign 1 with exponent 0 is the reserved operand
  }
  // 0.1fff...f (binary) * 2^(exponent - 128) = (1 + f / 2^23) * 2^(exponent - 129); exact in double.
  const double magnitude = std::ldexp(1.0 + static_cast<double>(fraction) / 8388608.0, exponent - 129);
  value = negative ? -magnitude : magnitude;
  return true;
}

bool EncodeVaxF(float value, std::uint8_t bytes[4]) {
  std::uint32_t high_word = 0;
  std::uint32_t low_word = 0;
  if (value != 0.0f) {
    if (!std::isfinite(value)) return false;
    int exponent2 = 0;
    const double mantissa = std::frexp(std::abs(static_cast<double>(value)), &exponent2);  // [0.5, 1)
    const int exponent = exponent2 + 128;
    if (exponent > 255) return false;
    if (exponent >= 1) {
      // IEEE single has 24 significant bits like F_floating, so this is exact.
      const auto fraction = static_cast<std::uint32_t>(std::ldexp(mantissa - 0.5, 24));
      high_word =
          (value < 0.0f ? 0x8000u : 0u) | (static_cast<std::uint32_t>(exponent) << 7) | (fraction >> 16);
      low_word = fraction & 0xFFFFu;
    }
  }
  bytes[0] = static_cast<std::uint8_t>(high_word);
  bytes[1] = static_cast<std::uint8_t>(high_word >> 8);
  bytes[2] = static_cast<std::uint8_t>(low_word);
  bytes[3] = static_cast<std::uint8_t>(low_word >> 8);
  return true;
}

UdsChannel ReadUds1992(const std::filesystem::path& path) {
  const std::string file = path.string();
  const std::string bytes = ReadWholeFile(path);
  const auto* data = reinterpret_cast<const std::uint8_t*>(bytes.data());
  const std::size_t size = bytes.size();
  auto record_at = [&](std::size_t index, const std::string& what) -> Record {
    const std::size_t offset = index * kUdsRecordBytes;
    if (offset >= size)
      throw InputError(file + ": " + what + " (record " + std::to_string(index + 1) +
                       ") is missing; the file ends after " + std::to_string(size) + " bytes.");
    if (offset + kUdsRecordBytes > size)
      throw InputError(file + ": " + what + " (record " + std::to_string(index + 1) + ") is truncated (" +
                       std::to_string(size - offset) + " of 512 bytes).");
    return data + offset;
  };

  UdsChannel channel;
  const Record header = record_at(0, "the file header");
  const std::string filever = ReadString(header, file_header::kFilever);
  if (filever != "UDS-1992")
    throw InputError(file + ": FILEVER is " + util::QuotedLong(filever) +
                     ", not \"UDS-1992\" (not a UDS-1992 file).");
  const std::string numform = ReadString(header, file_header::kNumform);
  if (numform == "IEEE") {
    channel.number_form = UdsNumberForm::kIeee;
  } else if (numform == "VAX") {
    channel.number_form = UdsNumberForm::kVax;
  } else if (numform == "SUN") {
    channel.number_form = UdsNumberForm::kSun;
  } else {
    throw InputError(file + ": unknown NUMFORM " + util::QuotedLong(numform) +
                     " (expected IEEE, VAX or SUN).");
  }
  const UdsNumberForm form = channel.number_form;
  const std::int32_t nchan = ReadInt(header, file_header::kNchan, form);
  if (nchan < 1)
    throw InputError(file + ": NCHAN is " + std::to_string(nchan) +
                     "; napkin reads UDS-1992 files of one channel.");
  if (nchan > 1)
    channel.warnings.push_back(
        file + ": NCHAN is " + std::to_string(nchan) +
        "; the file holds one curve, read as its one channel (as NHTSA's reader does).");
  const std::string fileform = ReadString(header, file_header::kFileform);
  if (fileform != "Y")
    throw InputError(file + ": FILEFORM is " + util::QuotedLong(fileform) +
                     "; napkin reads uniformly sampled \"Y\" channels (X-Y curves are not supported).");
  ReadTexts(header, kFileHeaderTexts, channel);
  channel.test_number = ReadInt(header, file_header::kTstno, form);
  channel.test_source = ReadString(header, file_header::kTstsrc);

  std::size_t index = 1;
  Record curve = record_at(index, "the curve header");
  if (ReadString(curve, kRecordHeader) == "CMP-2 HDR") curve = record_at(++index, "the curve header");
  const std::string record_header = ReadString(curve, kRecordHeader);
  if (record_header != "CURVE HDR")
    throw InputError(file + ": record " + std::to_string(index + 1) + " starts with " +
                     util::QuotedLong(record_header) + " where the curve header (\"CURVE HDR\") belongs.");
  ReadTexts(curve, kCurveHeaderTexts, channel);
  const std::int32_t nfp = ReadInt(curve, curve_header::kNfp, form);
  const std::int32_t nlp = ReadInt(curve, curve_header::kNlp, form);
  if (nlp < nfp)
    throw InputError(file + ": NLP " + std::to_string(nlp) + " is less than NFP " + std::to_string(nfp) +
                     ".");
  double del = 0.0;
  if (!ReadReal(curve, curve_header::kDel, form, del) || !std::isfinite(del) || !(del > 0.0))
    throw InputError(file + ": DEL (the sampling interval) is not a finite positive number.");
  del = IntendedDecimalOfSingle(del);
  const std::string xunits = util::ToUpper(channel.xunits);
  if (xunits.find("MILLI") != std::string::npos || xunits == "MSEC" || xunits == "MS") del *= 1e-3;
  channel.del_s = del;
  channel.nfp = nfp;
  double inivel = 0.0;
  if (ReadReal(curve, curve_header::kInivel, form, inivel) && std::isfinite(inivel))
    channel.initial_velocity = inivel;
  for (const auto& [offset, field] :
       {std::pair<std::size_t, double*>{curve_header::kPref, &channel.prefilter_hz},
        {curve_header::kFcut, &channel.filter_cutoff_hz}}) {
    double hz = 0.0;
    if (ReadReal(curve, offset, form, hz) && std::isfinite(hz) && hz > 0.0)
      *field = IntendedDecimalOfSingle(hz);
  }
  if (channel.filter_cutoff_hz > 0.0 && !engine::J211ClassOfCutoff(channel.filter_cutoff_hz))
    channel.warnings.push_back(
        file + ": FCUT " + util::FormatNumber(channel.filter_cutoff_hz) +
        " Hz is no SAE J211 class cut-off (100, 300, 1000 or 1650 Hz), so the "
        "channel is taken as filtered at an unknown class and filtered as configured.");

  const std::size_t count = static_cast<std::size_t>(static_cast<std::int64_t>(nlp) - nfp + 1);
  const std::size_t records = (count + kUdsValuesPerRecord - 1) / kUdsValuesPerRecord;
  if (count > 100'000'000)
    throw InputError(file + ": NFP " + std::to_string(nfp) + " to NLP " + std::to_string(nlp) +
                     " declares an implausible number of samples.");
  // "data record 3" (r from 0), written only into a message: the reading loop does not allocate it.
  const auto record_name = [](std::size_t r) { return "data record " + std::to_string(r + 1); };
  // Every data record is present before the samples are allocated: a declared count is checked
  // against the file's size first (docs/formats.md "UDS-1992 input").
  auto data_record = [&](std::size_t r) -> Record {
    const std::size_t offset = (index + 1 + r) * kUdsRecordBytes;
    if (offset >= size)
      throw InputError(file + ": " + record_name(r) + " is missing (NFP " + std::to_string(nfp) + " to NLP " +
                       std::to_string(nlp) + " needs " + std::to_string(records) +
                       " data records, the file of " + std::to_string(size) + " bytes holds " +
                       std::to_string(size / kUdsRecordBytes - (index + 1)) + ").");
    if (offset + kUdsRecordBytes > size)
      throw InputError(file + ": " + record_name(r) + " is truncated (" + std::to_string(size - offset) +
                       " of 512 bytes).");
    return data + offset;
  };
  const std::size_t complete_data_records = size / kUdsRecordBytes - (index + 1);
  if (records > complete_data_records) data_record(complete_data_records);  // throws
  channel.values.resize(count);
  for (std::size_t r = 0; r < records; ++r) {
    const Record record = data_record(r);
    const std::string data_header = ReadString(record, kRecordHeader);
    if (data_header != "Y DATA")
      throw InputError(file + ": " + record_name(r) + " starts with " + util::QuotedLong(data_header) +
                       " instead of \"Y DATA\".");
    const std::size_t first = r * kUdsValuesPerRecord;
    const std::size_t last = std::min(count, first + kUdsValuesPerRecord);
    for (std::size_t i = first; i < last; ++i) {
      double value = 0.0;
      const bool ok = ReadReal(record, kDataOffset + 4 * (i - first), form, value);
      if (!ok || !std::isfinite(value))
        throw InputError(file + ": sample " + std::to_string(nfp + static_cast<std::int64_t>(i)) + " (" +
                         record_name(r) + ", value " + std::to_string(i - first + 1) + ") is " +
                         (ok ? "not a finite number" : "a VAX reserved operand") + ".");
      channel.values[i] = value;
    }
  }
  return channel;
}

void WriteUds1992(const UdsChannel& channel, const std::filesystem::path& path) {
  const std::string file = path.string();
  if (channel.values.empty()) throw InputError(file + ": cannot write a UDS-1992 channel without samples.");
  const UdsNumberForm form = channel.number_form;
  const std::size_t count = channel.values.size();
  const std::size_t records = (count + kUdsValuesPerRecord - 1) / kUdsValuesPerRecord;
  std::vector<std::uint8_t> bytes((2 + records) * kUdsRecordBytes, 0);

  std::uint8_t* header = bytes.data();
  WriteString(header, file_header::kFilever, "UDS-1992");
  WriteWord(header, file_header::kNchan, 1, form);
  WriteString(header, file_header::kFileform, "Y");
  WriteString(header, file_header::kNumform, UdsNumberFormName(form));
  WriteString(header, file_header::kTstsrc, "NAPKIN");
  WriteWord(header, file_header::kTstno, static_cast<std::uint32_t>(channel.test_number), form);
  for (const HeaderField field : file_header::kOtherStrings) WriteString(header, field, "");
  if (!channel.test_source.empty()) WriteString(header, file_header::kTstsrc, channel.test_source);
  WriteTexts(header, kFileHeaderTexts, channel);

  std::uint8_t* curve = bytes.data() + kUdsRecordBytes;
  WriteString(curve, curve_header::kRecordHeader, "CURVE HDR");
  WriteWord(curve, curve_header::kIchan, 1, form);
  WriteString(curve, curve_header::kChanform, "Y");
  WriteWord(curve, curve_header::kCurno, 1, form);
  WriteTexts(curve, kCurveHeaderTexts, channel);
  WriteString(curve, curve_header::kStatus, "");
  WriteString(curve, curve_header::kCurtyp, "TIME SERIES");
  for (const HeaderField field : curve_header::kOtherStrings) WriteString(curve, field, "");
  WriteWord(curve, curve_header::kNfp, static_cast<std::uint32_t>(channel.nfp), form);
  WriteWord(curve, curve_header::kNlp, static_cast<std::uint32_t>(channel.nlp()), form);
  if (!WriteReal(curve, curve_header::kDel, channel.del_s, form) ||
      !WriteReal(curve, curve_header::kInivel, channel.initial_velocity, form) ||
      !WriteReal(curve, curve_header::kPref, channel.prefilter_hz, form) ||
      !WriteReal(curve, curve_header::kFcut, channel.filter_cutoff_hz, form))
    throw InputError(file + ": DEL, INIVEL, PREF or FCUT cannot be stored as a " + UdsNumberFormName(form) +
                     " real.");

  for (std::size_t r = 0; r < records; ++r) {
    std::uint8_t* record = bytes.data() + (2 + r) * kUdsRecordBytes;
    WriteString(record, kRecordHeader, "Y DATA");
    const std::size_t first = r * kUdsValuesPerRecord;
    const std::size_t last = std::min(count, first + kUdsValuesPerRecord);
    for (std::size_t i = first; i < last; ++i)
      if (!WriteReal(record, kDataOffset + 4 * (i - first), channel.values[i], form))
        throw InputError(file + ": sample " + std::to_string(channel.nfp + static_cast<long long>(i)) + " (" +
                         util::FormatNumber(channel.values[i]) + ") cannot be stored as a " +
                         UdsNumberFormName(form) + " real.");
  }
  util::WriteFileAtomically(path, [&](util::AtomicFile& out) {
    out.Write(std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()));
  });
}

RawChannel ToRawChannel(const UdsChannel& channel, const std::filesystem::path& path) {
  RawChannel raw;
  raw.source = path.string();
  raw.name = !channel.curve_description.empty() ? channel.curve_description : channel.curve_name;
  raw.senatt = channel.senatt;
  raw.axis = channel.axis;
  raw.unit = channel.yunits;
  raw.dt_s = channel.del_s;
  raw.t0_s = static_cast<double>(channel.nfp) * channel.del_s;
  // FCUT is a cut-off frequency in Hz, not a class number (NHTSA's UDS_Vars.txt; docs/formats.md).
  if (channel.filter_cutoff_hz > 0.0)
    raw.prefiltered_cfc =
        engine::J211ClassOfCutoff(channel.filter_cutoff_hz).value_or(engine::kPrefilteredClassUnknown);
  raw.values = channel.values;
  raw.position = channel.senloc;
  // INIVEL is in the velocity unit of DIMSYS (docs/formats.md "UDS-1992 input").
  const std::string dimsys = util::ToUpper(channel.dimsys);
  const double mps_per_unit = dimsys == "SI" ? 1.0 : dimsys == "ENG" ? 0.44704 : 1.0 / 3.6;
  if (channel.initial_velocity != 0.0) raw.initial_velocity_mps = channel.initial_velocity * mps_per_unit;
  return raw;
}

TestInfo UdsTestInfo(const UdsChannel& channel) {
  auto joined = [](const std::string& a, const std::string& b) {
    return a.empty() ? b : b.empty() ? a : a + " " + b;
  };
  TestInfo info;
  if (channel.test_number != 0) info.test_number = std::to_string(channel.test_number);
  info.title = channel.title;
  info.vehicle = joined(channel.make, channel.model);
  info.dummy = joined(channel.occupant_type, channel.dummy_size);
  info.laboratory = channel.test_source;
  return info;
}

bool InTableTwoOneOrder(std::size_t file_count, const engine::ArrayGeometry& array) {
  if (file_count != 9) return false;
  return std::all_of(array.sensors.begin(), array.sensors.end(), [](const engine::Sensor& sensor) {
    return std::find(std::begin(engine::kNapSlots), std::end(engine::kNapSlots), sensor.slot) !=
           std::end(engine::kNapSlots);
  });
}

InputError DefaultMapError(const InputError& error, std::size_t file_count, const std::string& test_name) {
  std::string reason = error.what();
  const std::string prefix = "test " + test_name + ": ";
  if (reason.rfind(prefix, 0) == 0) reason.erase(0, prefix.size());
  if (!reason.empty() && reason.back() == '.') reason.pop_back();
  return InputError(prefix + std::to_string(file_count) +
                    " UDS-1992 files without a channel map (not nine in the report's Table 2-1 order) were "
                    "matched by SENATT/AXIS through the \"default\" map, and " +
                    reason + "; give --channel-map.");
}

std::vector<std::size_t> TableTwoOneAssignment(const engine::ArrayGeometry& array,
                                               const std::string& test_name) {
  std::vector<std::size_t> channel_of_sensor;
  for (const engine::Sensor& sensor : array.sensors) {
    const auto slot = std::find(std::begin(engine::kNapSlots), std::end(engine::kNapSlots), sensor.slot);
    if (slot == std::end(engine::kNapSlots))
      throw InputError("test " + test_name + ": slot " + util::QuotedLong(sensor.slot) + " of array " +
                       util::QuotedLong(array.name) +
                       " is not one of the nine Table 2-1 slots; give a channel map.");
    channel_of_sensor.push_back(static_cast<std::size_t>(slot - std::begin(engine::kNapSlots)));
  }
  return channel_of_sensor;
}

std::vector<std::pair<std::string, std::vector<std::filesystem::path>>> GroupUdsFilesByStem(
    const std::vector<std::filesystem::path>& files) {
  std::map<std::string, std::vector<std::filesystem::path>> groups;
  for (const std::filesystem::path& file : files) groups[file.stem().string()].push_back(file);
  std::vector<std::pair<std::string, std::vector<std::filesystem::path>>> result;
  for (auto& [stem, members] : groups) {
    std::sort(members.begin(), members.end(),
              [](const auto& a, const auto& b) { return a.filename().string() < b.filename().string(); });
    result.emplace_back(stem, std::move(members));
  }
  return result;
}

engine::TestSignals ReadUdsTest(const std::vector<std::filesystem::path>& files,
                                const engine::ArrayGeometry& array, const ChannelMap* map,
                                const std::string& test_name, std::vector<std::string>* warnings) {
  std::vector<std::filesystem::path> sorted = files;
  std::sort(sorted.begin(), sorted.end(),
            [](const auto& a, const auto& b) { return a.filename().string() < b.filename().string(); });
  std::vector<RawChannel> channels;
  channels.reserve(sorted.size());
  for (const std::filesystem::path& file : sorted) {
    const UdsChannel channel = ReadUds1992(file);
    if (warnings != nullptr)
      warnings->insert(warnings->end(), channel.warnings.begin(), channel.warnings.end());
    channels.push_back(ToRawChannel(channel, file));
  }

  // Report section 2.2: LC_COMP reads nine files in Table 2-1 order; other
  // groups without a map go through the default map, as ISO-MME folders do.
  if (map == nullptr && InTableTwoOneOrder(channels.size(), array))
    return AssembleSignals(channels, TableTwoOneAssignment(array, test_name), array, test_name);
  const ChannelMap default_map = map == nullptr ? LoadChannelMap("default") : ChannelMap{};
  const ChannelMap& used = map != nullptr ? *map : default_map;
  std::vector<std::size_t> channel_of_sensor;
  try {
    channel_of_sensor = AssignSlots(channels, array, used, test_name);
  } catch (const InputError& error) {
    if (map != nullptr) throw;
    throw DefaultMapError(error, channels.size(), test_name);
  }
  return AssembleSignals(channels, channel_of_sensor, array, test_name);
}

}  // namespace napkin::formats
