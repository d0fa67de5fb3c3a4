#include "tests/support/isomme_generator.h"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <numbers>
#include <stdexcept>

namespace napkin::test_support {
namespace {

namespace fs = std::filesystem;

// Header line as ISO/TS 13499 files lay it out: key padded to 28, ':', value, CRLF.
void AppendLine(std::string& out, const std::string& key, const std::string& value) {
  out += key;
  if (key.size() < 28) out.append(28 - key.size(), ' ');
  out += ':';
  out += value;
  out += "\r\n";
}

void WriteBytes(const fs::path& path, const std::string& bytes) {
  std::ofstream file(path, std::ios::binary);
  file << bytes;
  if (!file) throw std::runtime_error("cannot write " + path.string());
}

std::string Exact(double value) {
  char buffer[40];
  std::snprintf(buffer, sizeof(buffer), "%.17g", value);
  return buffer;
}

struct Channel {
  std::string code;
  std::string name;
  std::string unit_latin1;  // as written
  std::vector<double> values;
};

// Body regions and vehicle locations that fill a test besides the heads
// (ISO/TS 13499 main locations and physical dimensions).
struct Filler {
  const char* location;   // main location + fine locations 1-2 (8 characters)
  const char* dimension;  // physical dimension (2 characters)
  const char* directions;
  const char* unit_latin1;
  const char* name;
};
constexpr Filler kDummyFillers[] = {
    {"HEAD0000", "AC", "R", "g", "Head resultant acceleration"},
    {"NECKUP00", "FO", "XYZ", "N", "Upper neck force"},
    {"NECKUP00", "MO", "XYZ", "Nm", "Upper neck moment"},
    {"CHST0000", "AC", "XYZR", "g", "Chest acceleration"},
    {"CHST0000", "DS", "X", "mm", "Chest deflection"},
    {"THSP0000", "AC", "XYZ", "g", "Thoracic spine acceleration"},
    {"PELV0000", "AC", "XYZ", "g", "Pelvis acceleration"},
    {"FEMRLE00", "FO", "Z", "N", "Left femur force"},
    {"FEMRRI00", "FO", "Z", "N", "Right femur force"},
    {"TIBILEUP", "FO", "XZ", "N", "Left upper tibia force"},
    {"TIBIRIUP", "MO", "XY", "Nm", "Right upper tibia moment"},
    {"KNSLLE00", "DS", "X", "mm", "Left knee slider"},
    {"LUSP0000", "FO", "XZ", "N", "Lumbar spine force"},
};
constexpr Filler kVehicleFillers[] = {
    {"BPILLELO", "AC", "XYZ", "g", "B-pillar acceleration"},
    {"SEATLE00", "AC", "X", "g", "Seat acceleration"},
    {"VEHC0000", "AC", "XYZ", "g", "Vehicle CG acceleration"},
    {"VEHC0000", "VE", "X", "km/h", "Vehicle velocity"},
    {"SEBE0000", "FO", "0", "N", "Seat belt force"},
    {"STCL0000", "DS", "X", "mm", "Steering column displacement"},
    {"DOORLE00", "AN", "Y", "\xB0", "Door angle"},
};

}  // namespace

GeneratedIsoMme WriteMultiDummyIsoMme(const fs::path& folder, const MultiDummyIsoMmeSpec& spec) {
  GeneratedIsoMme generated;
  generated.folder = folder;
  generated.title = "Frontal 56 km/h full width, driver and passenger";
  generated.laboratory = "Prüfstand München";
  generated.vehicle = "Kompaktwagen Ä4";
  generated.date = "2019-05-21";
  const int n = spec.samples;
  auto time = [&](int k) { return spec.t0_s + k * spec.dt_s; };

  std::vector<Channel> channels;
  const char* dummy_codes[] = {"H3", "HF", "TH", "Q6"};
  const char axes[3] = {'X', 'Y', 'Z'};
  for (std::size_t d = 0; d < spec.head_positions.size(); ++d) {
    GeneratedHead head;
    head.position = spec.head_positions[d];
    head.dummy_code = dummy_codes[d % 4];
    head.acc_g.resize(n, 3);
    head.omega_degps.resize(n, 3);
    for (int a = 0; a < 3; ++a) {
      for (int k = 0; k < n; ++k) {
        // A half-sine pulse of 40 ms from t = 0 with a dummy- and axis-specific amplitude,
        // and a smooth rotation: distinct numbers per head and axis.
        const double t = time(k);
        const double pulse = t >= 0.0 && t <= 0.04 ? std::sin(std::numbers::pi * t / 0.04) : 0.0;
        head.acc_g(k, a) = (20.0 + 15.0 * static_cast<double>(d)) * (a == 0 ? -2.0 : 0.5 + a) * pulse;
        head.omega_degps(k, a) = (300.0 + 100.0 * static_cast<double>(d)) * (a - 1.0) * pulse * t;
      }
    }
    for (int a = 0; a < 3; ++a) {
      const std::string axis(1, axes[a]);
      Channel acc{head.position + "HEAD0000" + head.dummy_code + "AC" + axis + "A",
                  "Head CG acceleration " + axis,
                  "g",
                  {}};
      acc.values.assign(head.acc_g.col(a).data(), head.acc_g.col(a).data() + n);
      Channel rate{head.position + "HEAD0000" + head.dummy_code + "AV" + axis + "D",
                   "Head angular velocity " + axis,
                   "\xB0/s",
                   {}};
      rate.values.assign(head.omega_degps.col(a).data(), head.omega_degps.col(a).data() + n);
      channels.push_back(std::move(acc));
      channels.push_back(std::move(rate));
    }
    generated.heads.push_back(std::move(head));
  }

  // Fill up to channel_count with the other body regions of each dummy, then the vehicle's.
  std::vector<Channel> fillers;
  for (const std::string& position : spec.head_positions)
    for (const Filler& filler : kDummyFillers)
      for (const char* direction = filler.directions; *direction != '\0'; ++direction) {
        const std::size_t d = static_cast<std::size_t>(&position - spec.head_positions.data());
        fillers.push_back(
            {position + filler.location + dummy_codes[d % 4] + filler.dimension + *direction + "A",
             std::string(filler.name) + " " + *direction,
             filler.unit_latin1,
             {}});
      }
  for (int repeat = 0; static_cast<int>(channels.size() + fillers.size()) < spec.channel_count; ++repeat)
    for (const Filler& filler : kVehicleFillers)
      for (const char* direction = filler.directions; *direction != '\0'; ++direction) {
        // Vehicle 1 (test object 1, position 0), then barrier-side objects 2, 3 ...
        const std::string object = std::to_string(1 + repeat);
        fillers.push_back({object + "0" + filler.location + "00" + filler.dimension + *direction + "C",
                           std::string(filler.name) + " " + *direction,
                           filler.unit_latin1,
                           {}});
      }
  for (Channel& filler : fillers) {
    if (static_cast<int>(channels.size()) >= spec.channel_count) break;
    filler.values.resize(static_cast<std::size_t>(n));
    const double scale = 1.0 + static_cast<double>(channels.size());
    for (int k = 0; k < n; ++k) filler.values[static_cast<std::size_t>(k)] = scale * std::cos(0.01 * k);
    channels.push_back(std::move(filler));
  }
  if (static_cast<int>(channels.size()) != spec.channel_count)
    throw std::invalid_argument("MultiDummyIsoMmeSpec: channel_count is below the head channels' count");

  fs::create_directories(folder / "Channel");
  std::string mme;
  AppendLine(mme, "Data format edition number", "1.6");
  AppendLine(mme, "Laboratory name",
             "Pr\xFC"
             "fstand M\xFCnchen");
  AppendLine(mme, "Laboratory test ref. number", spec.test_number);
  AppendLine(mme, "Test number", spec.test_number);
  AppendLine(mme, "Title", generated.title);
  AppendLine(mme, "Date of the test", generated.date);
  AppendLine(mme, "Number of test objects", "1");
  AppendLine(mme, "Name of test object 1",
             "Kompaktwagen \xC4"
             "4");
  AppendLine(mme, "Velocity test object 1", "15.56");
  AppendLine(mme, "Number of dummies", std::to_string(spec.head_positions.size()));
  WriteBytes(folder / (spec.test_number + ".mme"), mme);

  std::string chn;
  AppendLine(chn, "Instrumentation standard", "SAE J211 / ISO 6487");
  AppendLine(chn, "Number of channels", std::to_string(channels.size()));
  for (std::size_t i = 0; i < channels.size(); ++i) {
    char key[40];
    std::snprintf(key, sizeof(key), "Name of channel %03zu", i + 1);
    AppendLine(chn, key, channels[i].code + " / " + channels[i].name);
  }
  WriteBytes(folder / "Channel" / (spec.test_number + ".chn"), chn);

  for (std::size_t i = 0; i < channels.size(); ++i) {
    const Channel& channel = channels[i];
    std::string text;
    AppendLine(text, "Name of the channel", channel.name);
    AppendLine(text, "Laboratory channel code", "LAB" + std::to_string(i + 1));
    AppendLine(text, "Channel code", channel.code);
    AppendLine(text, "Unit", channel.unit_latin1);
    AppendLine(text, "Channel frequency class", "1000");
    AppendLine(text, "Sampling interval", Exact(spec.dt_s));
    AppendLine(text, "Time of first sample", Exact(spec.t0_s));
    AppendLine(text, "Number of samples", std::to_string(channel.values.size()));
    for (const double value : channel.values) text += Exact(value) + "\r\n";
    char suffix[32];
    std::snprintf(suffix, sizeof(suffix), ".%03zu", i + 1);
    WriteBytes(folder / "Channel" / (spec.test_number + suffix), text);
    generated.codes.push_back(channel.code);
  }
  return generated;
}

}  // namespace napkin::test_support
