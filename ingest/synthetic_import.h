#pragma once
// The work of `napkin synth` as functions: the tests of a scenario
// (synth::ScenarioTests) stored in the catalogue through StoreTest, one
// transaction per test, idempotent by content hash (SyntheticContentHash).
#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "db/catalogue.h"
#include "engine/array_geometry.h"
#include "synth/synthetic_tests.h"

namespace napkin::ingest {

struct SynthRequest {
  synth::SynthScenario scenario = synth::SynthScenario::kRandom;
  std::optional<int> count;          // random: tests; padding-series: repeats per variant
                                     // (default synth::DefaultCount: 1, 5)
  std::uint64_t seed = 1;            // generator seed of the first test
  std::string array = "ideal-3222";  // array preset or JSON file the signals are generated for
  std::string series;                // series label (default: the scenario name)
  std::string test_id;               // test id, or the prefix of numbered ids (default: the scenario name)
  std::optional<int> samples;        // random: samples per channel
  std::optional<double> duration_s;  // ... or duration (default 0.2 s)
  double rate_hz = 10000.0;          // sampling rate
};

// A request resolved and checked, before the catalogue is touched.
struct SynthPlan {
  engine::ArrayGeometry array;
  db::ArrayRow array_record;
  synth::ScenarioOptions scenario;
  std::string series;
  std::vector<synth::ScenarioTest> tests;  // described; each is generated when it is stored
};

// Loads the array and lists the scenario's tests. Throws InputError for an
// unknown array, or --samples / --duration given for a scenario of fixed
// duration.
SynthPlan PlanSynth(const SynthRequest& request);

struct SynthCounts {
  int added = 0;
  int present = 0;  // same content already in the catalogue
};

// Generates and stores each test of `plan` (metadata {"synthetic": {scenario,
// rate_hz, seed, duration_s, impact}} as far as they apply, impact =
// {speed_mps, trajectory_deg, contact_point_body_m, pulse_s, restitution,
// noise_g, noise_radps} for padding-series; source "synth:<scenario>").
// `progress`, when set, is called after each test with the tests stored or
// found present so far and their number.
SynthCounts StoreSynthTests(db::Catalogue& catalogue, const SynthPlan& plan,
                            const std::function<void(std::size_t done, std::size_t total)>& progress = {});

}  // namespace napkin::ingest
