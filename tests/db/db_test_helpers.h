#pragma once
// Shared fixtures of the db tests: a catalogue with an array, a config and
// a few labelled tests.
#include <optional>
#include <string>

#include "db/catalogue.h"

namespace napkin::test_support {

inline db::ArrayRow IdealArray() {
  return db::ArrayRow{
      {}, "ideal-3222", R"({"name":"ideal-3222","length_unit":"in","sensors":[]})", "array-hash-ideal"};
}

inline db::ConfigRow DefaultConfig(const std::string& json = R"({"filter":"cfc1000","solver":"exact"})") {
  return db::ConfigRow{{}, "default", json, "config-hash-" + json, {}};
}

// A test with external id `external_id`, unique content hash and the given labels.
inline db::TestId AddTest(db::Catalogue& catalogue, db::ArrayId array, const std::string& external_id,
                          const std::optional<std::string>& series = std::nullopt,
                          const std::optional<std::string>& variant = std::nullopt) {
  db::TestRow test;
  test.external_id = external_id;
  test.series = series;
  test.variant = variant;
  test.array_id = array;
  test.source_path = "/data/" + external_id + ".csv";
  test.content_hash = "content-" + external_id;
  return catalogue.WriteTest(test);
}

}  // namespace napkin::test_support
