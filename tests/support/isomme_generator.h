#pragma once
// A generated ISO-MME (ISO/TS 13499) test as real laboratories write them
// (docs/formats.md "ISO-MME (ISO/TS 13499) input", "Several dummies in one
// test"): many channels with codes of many body regions and of the vehicle,
// two (or more) dummies each with a head CG accelerometer triplet (g) and
// angular-rate triplet (ISO-8859-1 "°/s"), CRLF line ends, ISO-8859-1 text in
// the .mme. Reused by the plain-folder and the zipped import tests.
#include <Eigen/Core>
#include <filesystem>
#include <string>
#include <vector>

namespace napkin::test_support {

struct MultiDummyIsoMmeSpec {
  std::string test_number = "MD0001";
  std::vector<std::string> head_positions = {"11", "13"};  // test object + position
  int channel_count = 120;                                 // all channels, head channels included
  int samples = 2000;
  double dt_s = 1e-4;
  double t0_s = -0.01;
};

// What was written: for each head, its channels' values as written (the
// text reads back to exactly these doubles).
struct GeneratedHead {
  std::string position;
  std::string dummy_code;       // fine location 3 ("H3", "HF")
  Eigen::MatrixXd acc_g;        // samples x 3 (x, y, z), in g
  Eigen::MatrixXd omega_degps;  // samples x 3, in deg/s
};

struct GeneratedIsoMme {
  std::filesystem::path folder;  // the test folder (holds <test_number>.mme)
  std::vector<GeneratedHead> heads;
  std::vector<std::string> codes;  // every channel code, in .chn order
  std::string title;               // the .mme "Title" (UTF-8)
  std::string laboratory;          // the .mme "Laboratory name" (UTF-8)
  std::string vehicle;             // the .mme "Name of test object 1" (UTF-8)
  std::string date;                // the .mme "Date of the test"
};

// Writes the test folder `folder` (created) and returns what it holds.
GeneratedIsoMme WriteMultiDummyIsoMme(const std::filesystem::path& folder,
                                      const MultiDummyIsoMmeSpec& spec = {});

}  // namespace napkin::test_support
