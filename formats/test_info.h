#pragma once
// Test-level information read from ISO-MME .mme files and UDS-1992 file
// headers, stored with each imported test (docs/formats.md "Test
// information"). Empty strings: the file records none.
#include <string>

namespace napkin::formats {

struct TestInfo {
  std::string test_number;  // ISO-MME "Test number"; UDS-1992 TSTNO
  std::string title;        // ISO-MME "Title"; UDS-1992 TITLE
  std::string vehicle;      // ISO-MME "Name of test object N"; UDS-1992 MAKE and MODEL
  std::string dummy;        // ISO-MME code fine location 3 ("H3"); UDS-1992 OCCTYP and DUMSIZ
  std::string date;         // ISO-MME "Date of the test"; none in UDS-1992
  std::string laboratory;   // ISO-MME "Laboratory name"; UDS-1992 TSTSRC
};

}  // namespace napkin::formats
