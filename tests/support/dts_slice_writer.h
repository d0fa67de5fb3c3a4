#pragma once
// DTS SLICEWare CSV exports written for the tests, in the layout of a real
// export (docs/formats.md "DTS SLICEWare CSV"): the information rows with a
// value per channel and trailing commas, `Data Starts Here`, the column row
// `Time,Chan 0:<serial>,...` and the samples (shortest exact decimals, so
// they read back bit for bit). napkin itself writes no such files.
#include <filesystem>
#include <string>
#include <vector>

#include "engine/array_geometry.h"
#include "engine/signals.h"

namespace napkin::test_support {

struct DtsChannel {
  std::string code;                      // ISO/TS 13499 code, e.g. D0HEADCG0000ACXA
  std::string unit = "g ";               // `Engineering Unit`, as SLICEWare writes it (a trailing blank)
  std::string serial;                    // `Sensor S/N`
  std::string software_filter = "None";  // `Software Filter (SAE Class)`
  std::vector<double> values;
};

struct DtsExport {
  std::string test_id = "DTS-1";
  std::string description = "synthetic head impact";
  double sample_rate_hz = 20000.0;
  double t0_s = 0.0;                     // the first row's time (negative: pre-trigger samples)
  std::string hardware_filter = "4300";  // `Hardware AA Filter (-3dB)` of every channel
  std::vector<DtsChannel> channels;
  bool crlf = true;  // SLICEWare is a Windows program
};

// The export's text. Rows are `Name,value per channel,`.
std::string DtsExportText(const DtsExport& dts);
void WriteDtsExport(const DtsExport& dts, const std::filesystem::path& path);

// The 6DX headform's six channels in its order (AV Z, AV Y, AV X, AC Z, AC Y,
// AC X), from signals of the 6aw-cg array (rad/s written in deg/sec).
DtsExport SixDxExport(const engine::TestSignals& signals, const engine::ArrayGeometry& array);

}  // namespace napkin::test_support
