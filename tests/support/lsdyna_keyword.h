#pragma once
// Reading back the LS-DYNA keyword files napkin writes (docs/formats.md), card by
// card, for the formats and CLI export tests. Header-only: it uses
// util::ParseDouble, so only test targets linking napkin_formats include it.
#include <gtest/gtest.h>

#include <array>
#include <cstddef>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "util/text.h"

namespace napkin::test_support {

// The number in columns [start, start + width) of a fixed-width card; records
// a test failure (and returns 0) when the card is short or the field is not a number.
inline double KeywordField(const std::string& line, std::size_t start, std::size_t width) {
  if (start + width > line.size()) {
    ADD_FAILURE() << "short card (field [" << start << ", " << start + width << ")): \"" << line << "\"";
    return 0.0;
  }
  const std::optional<double> value = util::ParseDouble(line.substr(start, width));
  EXPECT_TRUE(value) << "field [" << start << ", " << start + width << ") of \"" << line << "\"";
  return value.value_or(0.0);
}

struct ParsedKeyword {
  std::map<int, std::vector<std::pair<double, double>>> curves;  // LCID -> points
  std::vector<std::array<double, 8>> motions;                    // BOUNDARY_PRESCRIBED_MOTION_RIGID card 1
};

// Parses the keyword file as fixed-width cards: 10-column fields for the
// curve header and motion cards, 20-column fields for the points. Records a
// test failure for anything off the layout napkin writes (first line
// *KEYWORD, last keyword *END, the card widths, the constant header fields,
// any other keyword).
inline ParsedKeyword ParseKeyword(const std::filesystem::path& path) {
  std::ifstream in(path);
  std::string line;
  ParsedKeyword parsed;
  std::string keyword;
  int lcid = 0;
  bool header_read = false;
  std::getline(in, line);
  EXPECT_EQ(line, "*KEYWORD");
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '$') continue;
    EXPECT_LE(line.size(), 80u) << line;
    if (line[0] == '*') {
      keyword = line;
      header_read = false;
      continue;
    }
    if (keyword == "*DEFINE_CURVE") {
      if (!header_read) {
        EXPECT_EQ(line.size(), 70u) << line;
        lcid = static_cast<int>(KeywordField(line, 0, 10));
        EXPECT_EQ(KeywordField(line, 10, 10), 0.0);  // SIDR
        EXPECT_EQ(KeywordField(line, 20, 10), 1.0);  // SFA
        EXPECT_EQ(KeywordField(line, 30, 10), 1.0);  // SFO
        EXPECT_EQ(KeywordField(line, 40, 10), 0.0);  // OFFA
        EXPECT_EQ(KeywordField(line, 50, 10), 0.0);  // OFFO
        EXPECT_EQ(KeywordField(line, 60, 10), 0.0);  // DATTYP
        header_read = true;
      } else {
        EXPECT_EQ(line.size(), 40u) << line;
        parsed.curves[lcid].emplace_back(KeywordField(line, 0, 20), KeywordField(line, 20, 20));
      }
    } else if (keyword == "*BOUNDARY_PRESCRIBED_MOTION_RIGID") {
      EXPECT_EQ(line.size(), 80u) << line;
      std::array<double, 8> card{};
      for (std::size_t f = 0; f < card.size(); ++f) card[f] = KeywordField(line, 10 * f, 10);
      parsed.motions.push_back(card);
    } else {
      ADD_FAILURE() << "unexpected keyword " << keyword;
    }
  }
  EXPECT_EQ(keyword, "*END");
  return parsed;
}

// Trapezoidal integral of a load curve's (time, value) points.
inline double Trapezoid(const std::vector<std::pair<double, double>>& points) {
  double integral = 0.0;
  for (std::size_t i = 1; i < points.size(); ++i)
    integral += 0.5 * (points[i].second + points[i - 1].second) * (points[i].first - points[i - 1].first);
  return integral;
}

}  // namespace napkin::test_support
