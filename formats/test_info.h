#pragma once
// Test-level information read from ISO-MME .mme files, UDS-1992 file
// headers and DTS SLICEWare exports, stored with each imported test
// (docs/formats.md "Test information"). Empty strings: the file records none.
#include <string>
#include <vector>

namespace napkin::formats {

// A sensor feeding a slot, as the file records it (DTS SLICEWare: `Sensor S/N`, `Hardware AA
// Filter (-3dB)`).
struct SensorInfo {
  std::string slot;
  std::string code;             // ISO/TS 13499 channel code
  std::string serial;           // "" when not recorded
  std::string hardware_filter;  // the anti-aliasing filter's -3 dB frequency in Hz, as written
};

struct TestInfo {
  std::string test_number;  // ISO-MME "Test number"; UDS-1992 TSTNO; DTS Test ID
  std::string title;        // ISO-MME "Title"; UDS-1992 TITLE; DTS Test Description
  std::string vehicle;      // ISO-MME "Name of test object N"; UDS-1992 MAKE and MODEL
  std::string dummy;        // ISO-MME and DTS code fine location 3 ("H3"); UDS-1992 OCCTYP and DUMSIZ
  std::string date;         // ISO-MME "Date of the test"; DTS Test Date and Test Time; none in UDS-1992
  std::string laboratory;   // ISO-MME "Laboratory name"; UDS-1992 TSTSRC
  // The head's sensors in slot order, when the files record a serial or a hardware filter.
  std::vector<SensorInfo> sensors;
};

}  // namespace napkin::formats
