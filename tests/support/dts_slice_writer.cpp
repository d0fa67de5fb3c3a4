#include "tests/support/dts_slice_writer.h"

#include <cmath>
#include <fstream>
#include <functional>
#include <numbers>
#include <stdexcept>

#include "util/text.h"

namespace napkin::test_support {

std::string DtsExportText(const DtsExport& dts) {
  const std::string newline = dts.crlf ? "\r\n" : "\n";
  std::string text;
  const std::size_t channels = dts.channels.size();
  const auto row = [&](const std::string& name, const std::function<std::string(std::size_t)>& value) {
    text += name + ",";
    for (std::size_t c = 0; c < channels; ++c) text += value(c) + ",";
    text += newline;
  };
  const auto same = [](std::string value) { return [value](std::size_t) { return value; }; };
  row("Headers", same(""));
  row("Test Date", same("2024-05-23"));
  row("Test Time", same("10:42:07"));
  row("Test ID", same(dts.test_id));
  row("Test Description", same(dts.description));
  row("Sample Rate (Hz)", same(util::FormatNumber(dts.sample_rate_hz)));
  row("Hardware AA Filter (-3dB)", same(dts.hardware_filter));
  row("Data Channel Number", [](std::size_t c) { return std::to_string(c); });
  row("ISO Channel Code", [&](std::size_t c) { return dts.channels[c].code; });
  row("Channel Description", [&](std::size_t c) { return "Head " + dts.channels[c].code.substr(12, 3); });
  row("Channel Location", same("Head CG"));
  row("Sensor S/N", [&](std::size_t c) { return dts.channels[c].serial; });
  row("Software Filter (SAE Class)", [&](std::size_t c) { return dts.channels[c].software_filter; });
  row("Software Filter (-3dB)", same("None"));
  row("Engineering Unit", [&](std::size_t c) { return dts.channels[c].unit; });
  row("User Comment", same(""));
  const std::size_t samples = channels == 0 ? 0 : dts.channels.front().values.size();
  const long pre_zero = std::lround(-dts.t0_s * dts.sample_rate_hz);
  row("Number of Pre-Zero Data Pts", same(std::to_string(pre_zero)));
  row("Number of Post-Zero Data Pts", same(std::to_string(static_cast<long>(samples) - pre_zero)));
  row("Data Zero (CNTS)", same("32768"));
  row("Scale Factor (EU/CNT)", same("0.0123"));
  row("Scale Factor (mV/CNT)", same("0.0381"));
  row("Data Starts Here", same(""));
  text += "Time,";
  for (std::size_t c = 0; c < channels; ++c)
    text += "Chan " + std::to_string(c) + ":" + dts.channels[c].serial + ",";
  text += newline;
  for (std::size_t k = 0; k < samples; ++k) {
    util::AppendNumber(text, dts.t0_s + static_cast<double>(k) / dts.sample_rate_hz);
    for (std::size_t c = 0; c < channels; ++c) {
      text += ',';
      util::AppendNumber(text, dts.channels[c].values.at(k));
    }
    text += "," + newline;
  }
  return text;
}

void WriteDtsExport(const DtsExport& dts, const std::filesystem::path& path) {
  std::ofstream(path, std::ios::binary) << DtsExportText(dts);
}

DtsExport SixDxExport(const engine::TestSignals& signals, const engine::ArrayGeometry& array) {
  DtsExport dts;
  dts.sample_rate_hz = std::round(1.0 / signals.dt_s);
  dts.t0_s = signals.t0_s;
  const struct {
    const char* slot;
    const char* code;
    const char* serial;
  } order[] = {{"ars_z", "D0HEADCG0000AVZC", "6DX0855-AV3"}, {"ars_y", "D0HEADCG0000AVYC", "6DX0855-AV2"},
               {"ars_x", "D0HEADCG0000AVXC", "6DX0855-AV1"}, {"cg_z", "D0HEADCG0000ACZA", "6DX0855-AC3"},
               {"cg_y", "D0HEADCG0000ACYA", "6DX0855-AC2"},  {"cg_x", "D0HEADCG0000ACXA", "6DX0855-AC1"}};
  for (const auto& [slot, code, serial] : order) {
    const std::optional<std::size_t> sensor = array.FindSlot(slot);
    if (!sensor) throw std::invalid_argument(std::string("SixDxExport: the array has no slot ") + slot);
    DtsChannel channel;
    channel.code = code;
    channel.serial = serial;
    const bool rate = array.sensors[*sensor].kind == engine::SensorKind::kAngularRate;
    channel.unit = rate ? "deg/sec " : "g ";
    const double scale = rate ? array.sensors[*sensor].si_per_unit * 180.0 / std::numbers::pi : 1.0;
    for (Eigen::Index k = 0; k < signals.samples.rows(); ++k)
      channel.values.push_back(signals.samples(k, static_cast<Eigen::Index>(*sensor)) * scale);
    dts.channels.push_back(std::move(channel));
  }
  return dts;
}

}  // namespace napkin::test_support
