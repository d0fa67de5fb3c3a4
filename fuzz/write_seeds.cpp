// Writes the seed corpora of `make fuzz` (fuzz/seeds/<target>/) with napkin's
// own writers and presets, so every seed is a small valid input:
//   build/fuzz/fuzz/napkin_fuzz_write_seeds fuzz/seeds
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <utility>
#include <vector>

#include "engine/array_geometry.h"
#include "engine/processing.h"
#include "engine/signals.h"
#include "formats/array_json.h"
#include "formats/channel_map.h"
#include "formats/csv.h"
#include "formats/isomme.h"
#include "formats/json_file.h"
#include "formats/processing_config_json.h"
#include "formats/uds1992.h"
#include "fuzz/fuzz_inputs.h"

namespace fs = std::filesystem;
using namespace napkin;

namespace {

void Write(const fs::path& path, const std::string& bytes) {
  fs::create_directories(path.parent_path());
  std::ofstream(path, std::ios::binary) << bytes;
}

// A short smooth pulse on every slot of `array`: `samples` rows at 10 kHz.
engine::TestSignals PulseSignals(const engine::ArrayGeometry& array, int samples) {
  engine::TestSignals signals;
  signals.dt_s = 1e-4;
  signals.t0_s = -0.0005;
  for (const engine::Sensor& sensor : array.sensors) signals.slots.push_back(sensor.slot);
  signals.samples.resize(samples, static_cast<Eigen::Index>(array.sensors.size()));
  for (Eigen::Index k = 0; k < samples; ++k)
    for (Eigen::Index c = 0; c < signals.samples.cols(); ++c)
      signals.samples(k, c) = std::round(100.0 * (c + 1) * std::sin(0.3 * static_cast<double>(k))) / 4.0;
  return signals;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s <fuzz/seeds folder>\n", argv[0]);
    return 2;
  }
  const fs::path out = argv[1];
  for (const fuzz::FuzzTarget& target : fuzz::FuzzTargets()) fs::create_directories(out / target.name);
  const fs::path scratch = fs::temp_directory_path() / "napkin-fuzz-seeds";
  fs::remove_all(scratch);
  fs::create_directories(scratch);
  const engine::ArrayGeometry array = formats::LoadArray("denton-3222");
  const formats::ChannelMap map = formats::LoadChannelMap("nap-example");
  const engine::TestSignals signals = PulseSignals(array, 12);

  // CSV: napkin's writer, and a hand-written file with comments, CRLF, BOM and quotes.
  formats::WriteSignalsCsv(signals, out / "csv" / "denton-3222.csv");
  Write(out / "csv" / "commented.csv",
        "\xEF\xBB\xBF# lab export\r\n\"time_s\", \"a\" ,b\r\n0,1.5,-2\r\n0.001,1e1,0\r\n\r\n0.002,-0,3\r\n");

  // ISO-MME: one test folder; the channel files alone, and the folder joined for isomme_mme.
  const fs::path folder = scratch / "isomme";
  formats::WriteIsoMme(signals, array, map, folder, "SEED");
  std::string joined = formats::ReadWholeFile(folder / "SEED.mme");
  joined += fuzz::kIsoMmePartSeparator;
  joined += formats::ReadWholeFile(folder / "Channel" / "SEED.chn");
  for (std::size_t i = 1; i <= array.sensors.size(); ++i) {
    char name[32];
    std::snprintf(name, sizeof(name), "SEED.%03zu", i);
    const std::string channel = formats::ReadWholeFile(folder / "Channel" / name);
    joined += fuzz::kIsoMmePartSeparator;
    joined += channel;
    if (i <= 2) Write(out / "isomme_channel" / name, channel);
  }
  Write(out / "isomme_mme" / "denton-3222-nap-example", joined);
  Write(out / "isomme_mme" / "mme-only", formats::ReadWholeFile(folder / "SEED.mme"));

  // UDS-1992: one channel in each number form, 130 samples (two data records).
  for (const formats::UdsNumberForm form :
       {formats::UdsNumberForm::kIeee, formats::UdsNumberForm::kVax, formats::UdsNumberForm::kSun}) {
    formats::UdsChannel channel;
    channel.number_form = form;
    channel.test_number = 7;
    channel.test_name = "SEED";
    channel.curve_name = "HEADCGX";
    channel.senatt = "HEAD CG";
    channel.axis = "XL";
    channel.nfp = -5;
    for (int k = 0; k < 130; ++k) channel.values.push_back(std::round(40.0 * std::sin(0.1 * k)) / 8.0);
    const std::string name = std::string("seed-") + formats::UdsNumberFormName(form) + ".001";
    formats::WriteUds1992(channel, scratch / name);
    Write(out / "uds1992" / name, formats::ReadWholeFile(scratch / name));
  }

  // DTS SLICEWare CSV: a 6DX headform export as SLICEWare writes one (CRLF, a value per channel
  // and a trailing comma in every row), five samples at 20 kHz from -0.1 ms.
  {
    using Values = std::vector<std::string>;
    const auto same = [](const char* value) { return Values(6, value); };
    const Values serials = {"6DX0855-AV3", "6DX0855-AV2", "6DX0855-AV1",
                            "6DX0855-AC3", "6DX0855-AC2", "6DX0855-AC1"};
    const std::pair<const char*, Values> rows[] = {
        {"Headers", same("")},
        {"Test Date", same("2024-05-23")},
        {"Test Time", same("10:42:07")},
        {"Test ID", same("SEED-6DX")},
        {"Test Description", same("seed")},
        {"Sample Rate (Hz)", same("20000")},
        {"Hardware AA Filter (-3dB)", same("4300")},
        {"Data Channel Number", {"0", "1", "2", "3", "4", "5"}},
        {"ISO Channel Code",
         {"D0HEADCG0000AVZC", "D0HEADCG0000AVYC", "D0HEADCG0000AVXC", "D0HEADCG0000ACZA", "D0HEADCG0000ACYA",
          "D0HEADCG0000ACXA"}},
        {"Channel Description", same("Head")},
        {"Channel Location", same("Head CG")},
        {"Sensor S/N", serials},
        {"Software Filter (SAE Class)", same("None")},
        {"Software Filter (-3dB)", same("None")},
        {"Engineering Unit", {"deg/sec ", "deg/sec ", "deg/sec ", "g ", "g ", "g "}},
        {"User Comment", same("")},
        {"Number of Pre-Zero Data Pts", same("2")},
        {"Number of Post-Zero Data Pts", same("3")},
        {"Data Zero (CNTS)", same("32768")},
        {"Scale Factor (EU/CNT)", same("0.0123")},
        {"Scale Factor (mV/CNT)", same("0.0381")},
        {"Data Starts Here", same("")},
        {"Time",
         {"Chan 0:" + serials[0], "Chan 1:" + serials[1], "Chan 2:" + serials[2], "Chan 3:" + serials[3],
          "Chan 4:" + serials[4], "Chan 5:" + serials[5]}}};
    std::string text;
    for (const auto& [name, values] : rows) {
      text += name;
      for (const std::string& value : values) text += "," + value;
      text += ",\r\n";
    }
    const char* times[] = {"-0.0001", "-5e-05", "0", "5e-05", "0.0001"};
    for (int k = 0; k < 5; ++k) {
      text += times[k];
      for (int c = 0; c < 6; ++c) {
        char value[32];
        std::snprintf(value, sizeof(value), "%g", std::round(10000.0 * std::sin(0.5 * k + c)) / 1000.0);
        text += std::string(",") + value;
      }
      text += ",\r\n";
    }
    Write(out / "dts_slice_csv" / "6dx-headform.csv", text);
  }

  // JSON: the presets, and the canonical processing configuration (every key).
  const fs::path config = formats::DefaultConfigDir();
  for (const auto& [subdir, target] :
       {std::pair{"arrays", "array_json"}, std::pair{"processing", "processing_config_json"},
        std::pair{"channel-maps", "channel_map_json"}})
    for (const auto& entry : fs::directory_iterator(config / subdir))
      if (entry.path().extension() == ".json")
        Write(out / target / entry.path().filename(), formats::ReadWholeFile(entry.path()));
  engine::ProcessingConfig every_key;  // a non-default storage choice is written too
  every_key.storage.derived_channels = engine::DerivedStorage::kFloat64;
  Write(out / "processing_config_json" / "canonical.json",
        formats::ProcessingConfigToJson(every_key).dump(2) + "\n");

  // --where: the examples of docs/formats.md "Query filters".
  Write(out / "where" / "precedence", "hic15>700 and variant=foam-a or series=sled");
  Write(out / "where" / "parentheses",
        "(hic15 > 700 or (variant = \"foam-a\" and series != sled)) and hic36 <= 1e3");
  Write(out / "where" / "quoted", "series=\"x'); DROP TABLE tests;--\" or test_id = \"a\\\"b\\\\\"");
  Write(out / "where" / "numbers", "a3ms_g >= -1.5e2 AND hic15 != +0.5 Or test_id < 0012");

  fs::remove_all(scratch);
  return 0;
}
