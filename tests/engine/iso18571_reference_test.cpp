// ISO/TS 18571 against an independent implementation: 24 curve pairs from
// napkin's synthetic tests (the padding series of `napkin demo`, random
// motions, the report's seed test), rated by napkin and compared with the
// scores another public implementation gave the same pairs
// (tests/fixtures/iso18571/README.md says which and how): overall within
// 0.005, each score within 0.01.
//
// Writing the pairs for the other implementation:
//   NAPKIN_ISO18571_WRITE_PAIRS=/tmp/pairs.txt napkin_engine_tests --gtest_filter=Iso18571Reference.*
// writes per pair a line "n dt" and n lines "reference candidate", and the
// pairs' names, one a line, to /tmp/pairs.txt.names.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "engine/iso18571.h"
#include "engine/units.h"
#include "synth/synthetic_tests.h"
#include "tests/support/reference_arrays.h"

namespace napkin::engine {
namespace {

struct CurvePair {
  std::string name;
  std::vector<double> reference;
  std::vector<double> candidate;
  double dt_s = 1e-4;
};

std::vector<double> Values(const Eigen::VectorXd& v) { return {v.data(), v.data() + v.size()}; }

// The pairs: every curve is a synthetic test's exact truth at 10 kHz over
// its whole record (0 to 0.1 s for the padding series).
const std::vector<CurvePair>& ReferencePairs() {
  static const std::vector<CurvePair> kPairs = [] {
    std::vector<CurvePair> pairs;
    // The padding series of `napkin demo` (seed 1, five repeats per padding).
    synth::ScenarioOptions options;
    options.scenario = synth::SynthScenario::kPaddingSeries;
    options.id_prefix = "ps";
    options.count = synth::kPaddingRepeats;
    const std::vector<synth::ScenarioTest> described = synth::ScenarioTests(options);
    std::vector<synth::SyntheticTest> tests;
    for (const synth::ScenarioTest& test : described)
      tests.push_back(synth::SynthScenarioTest(test_support::Ideal3222(), options, test));
    auto acc_g = [&](std::size_t i) {
      return Values(tests[i].truth.acc_fixed.rowwise().norm() / kStandardGravity);
    };
    auto omega = [&](std::size_t i) { return Values(tests[i].truth.omega_body.rowwise().norm()); };
    const std::size_t repeats = synth::kPaddingRepeats;
    // Each repeat against the first of its padding (resultant CG acceleration, g).
    for (std::size_t v = 0; v < 3; ++v) {
      for (std::size_t r = 1; r < repeats; ++r) {
        pairs.push_back(
            {described[v * repeats].external_id + " vs " + described[v * repeats + r].external_id + " |a|",
             acc_g(v * repeats), acc_g(v * repeats + r)});
      }
    }
    // Padding against padding (first repeats).
    for (auto [a, b] : {std::pair{0, 1}, std::pair{0, 2}, std::pair{1, 2}}) {
      pairs.push_back(
          {described[a * repeats].external_id + " vs " + described[b * repeats].external_id + " |a|",
           acc_g(a * repeats), acc_g(b * repeats)});
    }
    // Resultant angular velocity (rad/s), first two repeats of each padding.
    for (std::size_t v = 0; v < 3; ++v) {
      pairs.push_back(
          {described[v * repeats].external_id + " vs " + described[v * repeats + 1].external_id + " |omega|",
           omega(v * repeats), omega(v * repeats + 1)});
    }
    // Components: fixed-frame x acceleration and body-y angular velocity.
    pairs.push_back({"ps-production-01 vs ps-production-03 a_x", Values(tests[0].truth.acc_fixed.col(0)),
                     Values(tests[2].truth.acc_fixed.col(0))});
    pairs.push_back({"ps-production-01 vs ps-foam-b-01 omega_y", Values(tests[0].truth.omega_body.col(1)),
                     Values(tests[2 * repeats].truth.omega_body.col(1))});
    // Random motions (0.1 s): seed 1 against seeds 2 and 3, resultant acceleration.
    synth::RandomMotionOptions random;
    random.duration_s = 0.1;
    std::vector<std::vector<double>> motions;
    for (std::uint64_t seed : {1, 2, 3}) {
      random.seed = seed;
      const synth::SyntheticTest motion = synth::SynthRandomMotion(test_support::Ideal3222(), random);
      motions.push_back(Values(motion.truth.acc_fixed.rowwise().norm() / kStandardGravity));
    }
    pairs.push_back({"random-1 vs random-2 |a|", motions[0], motions[1]});
    pairs.push_back({"random-1 vs random-3 |a|", motions[0], motions[2]});
    // The report's seed test (section 4.5): its omega_y against itself 3 ms
    // later and 10 % larger.
    const synth::SyntheticTest seed =
        synth::SynthSeedFixedAxis(test_support::Ideal3222(), Eigen::Vector3d(0.5, 0.5, 0.5));
    const std::vector<double> w = Values(seed.truth.omega_fixed.col(1));
    std::vector<double> later(w.size(), 0.0), larger(w.size());
    for (std::size_t k = 0; k < w.size(); ++k) {
      if (k >= 30) later[k] = w[k - 30];
      larger[k] = 1.1 * w[k];
    }
    pairs.push_back({"seed omega_y vs 3 ms later", w, later});
    pairs.push_back({"seed omega_y vs 10 % larger", w, larger});
    return pairs;
  }();
  return kPairs;
}

struct Scores {
  double corridor, phase, magnitude, slope, overall;
  long shift;
};

// tests/fixtures/iso18571/independent_scores.csv: name, then the scores.
std::vector<std::pair<std::string, Scores>> IndependentScores() {
  std::ifstream in(std::string(NAPKIN_FIXTURES_DIR) + "/iso18571/independent_scores.csv");
  std::vector<std::pair<std::string, Scores>> rows;
  std::string line;
  std::getline(in, line);  // header
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::stringstream row(line);
    std::string name, cell;
    std::getline(row, name, ',');
    std::vector<double> cells;
    while (std::getline(row, cell, ',')) cells.push_back(std::stod(cell));
    if (cells.size() != 6)
      ADD_FAILURE() << "bad fixture row: " << line;
    else
      rows.push_back({name, {cells[0], cells[1], cells[2], cells[3], cells[4], std::lround(cells[5])}});
  }
  return rows;
}

TEST(Iso18571Reference, AgreesWithAnIndependentImplementation) {
  const std::vector<CurvePair>& pairs = ReferencePairs();
  if (const char* path = std::getenv("NAPKIN_ISO18571_WRITE_PAIRS")) {
    std::FILE* out = std::fopen(path, "w");
    ASSERT_NE(out, nullptr) << path;
    for (const CurvePair& pair : pairs) {
      std::fprintf(out, "%zu %.17g\n", pair.reference.size(), pair.dt_s);
      for (std::size_t k = 0; k < pair.reference.size(); ++k)
        std::fprintf(out, "%.17g %.17g\n", pair.reference[k], pair.candidate[k]);
    }
    std::fclose(out);
    std::ofstream names(std::string(path) + ".names");
    for (const CurvePair& pair : pairs) names << pair.name << '\n';
  }
  const auto expected = IndependentScores();
  ASSERT_EQ(expected.size(), pairs.size())
      << "tests/fixtures/iso18571/independent_scores.csv has one row per pair";
  ASSERT_GE(pairs.size(), 20u);
  double largest_overall = 0.0, largest_score = 0.0;
  std::string where_overall, where_score;
  for (std::size_t p = 0; p < pairs.size(); ++p) {
    const CurvePair& pair = pairs[p];
    ASSERT_EQ(expected[p].first, pair.name);
    const Scores& want = expected[p].second;
    const Iso18571Rating got = Iso18571Rate(pair.reference, pair.candidate, pair.dt_s);
    const double d_overall = std::abs(got.overall - want.overall);
    if (d_overall > largest_overall) {
      largest_overall = d_overall;
      where_overall = pair.name;
    }
    EXPECT_LE(d_overall, 0.005) << pair.name;
    for (auto [name, a, b] :
         {std::tuple{"corridor", got.corridor, want.corridor}, std::tuple{"phase", got.phase, want.phase},
          std::tuple{"magnitude", got.magnitude, want.magnitude},
          std::tuple{"slope", got.slope, want.slope}}) {
      EXPECT_LE(std::abs(a - b), 0.01) << pair.name << ": " << name << " " << a << " against " << b;
      if (std::abs(a - b) > largest_score) {
        largest_score = std::abs(a - b);
        where_score = pair.name + " (" + name + ")";
      }
    }
    EXPECT_EQ(std::abs(got.shift_samples), std::abs(want.shift)) << pair.name;
  }
  std::printf("largest difference: overall %.3g (%s), score %.3g (%s)\n", largest_overall,
              where_overall.c_str(), largest_score, where_score.c_str());
}

}  // namespace
}  // namespace napkin::engine
