#pragma once
// Synthetic tests with exact answers: signals an ideal array would record for
// an analytically known rigid-body motion, plus the true kinematics at every
// sample. Used by the tests, `napkin synth` and `make demo`.
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "engine/array_geometry.h"
#include "engine/kinematics.h"
#include "engine/signals.h"

namespace napkin::engine {

struct SyntheticTest {
  std::string name;
  ArrayGeometry array;   // the geometry the signals were generated with
  TestSignals signals;   // in the units the array gives each slot
  InitialState initial;  // orientation and velocity at the first sample
  Kinematics truth;      // exact kinematics at every sample (residual 0)
};

struct SynthOptions {
  double rate_hz = 10000.0;
  bool gravity = false;  // sensors also sense -R^T g_fixed, zeroed at t = 0
  Eigen::Vector3d g_fixed_mps2{0.0, 0.0, 9.80665};
};

// Report section 4.5: rotation about an axis parallel to fixed Y, 10 in from
// the CG, omega_Y(t) = 25 (1 - cos(2 pi t / 0.06)) rad/s for 0 <= t <= 60 ms,
// then 0; 100 ms; samples at t = 0, dt, ..., 0.1 s.
SyntheticTest SynthSeedFixedAxis(const ArrayGeometry& array, const Eigen::Vector3d& orientation_rad,
                                 const SynthOptions& options = {});

// Report section 4.4: 90 deg about body x (0-40 ms), rest, 90 deg about body
// y (50-90 ms), rest, 90 deg about body z (100-140 ms), each with
// theta(t) = 45 deg (1 - cos(pi t / 40 ms)); 150 ms.
SyntheticTest SynthSequential(const ArrayGeometry& array, const SynthOptions& options = {});

struct RandomMotionOptions {
  std::uint64_t seed = 1;
  double duration_s = 0.2;
  double peak_omega_radps = 40.0;  // order of the largest angular velocity
  double peak_acc_g = 80.0;        // order of the largest CG acceleration
  bool random_initial_orientation = true;
  bool random_initial_velocity = true;
  SynthOptions synth;
};

// A random smooth 3-D motion (several haversine pulses per axis), seeded.
SyntheticTest SynthRandomMotion(const ArrayGeometry& array, const RandomMotionOptions& options);

// A copy of `array` with every sensor moved by a random offset of length up to
// `max_offset_m` (seeded): the "true" geometry of a test whose nominal
// geometry is `array`.
ArrayGeometry DisplaceSensors(const ArrayGeometry& array, double max_offset_m, std::uint64_t seed);

// The scenarios of `napkin synth`.
enum class SynthScenario {
  kSeedFixedAxis,    // report 4.5 (SynthSeedFixedAxis at phi = theta = psi = 0.5 rad)
  kSeedSequential,   // report 4.4 (SynthSequential)
  kRandom,           // `count` random motions, seeds seed, seed + 1, ...
  kPaddingVariants,  // the same random impacts under three paddings
};
inline constexpr SynthScenario kSynthScenarios[] = {SynthScenario::kSeedFixedAxis,
                                                    SynthScenario::kSeedSequential, SynthScenario::kRandom,
                                                    SynthScenario::kPaddingVariants};
// "seed-fixed-axis", "seed-sequential", "random", "padding-variants".
const char* SynthScenarioName(SynthScenario scenario);
std::optional<SynthScenario> ParseSynthScenario(std::string_view name);
// True for the scenarios whose duration is chosen (random, padding-variants);
// the report's scenarios have a fixed duration.
bool HasChosenDuration(SynthScenario scenario);

struct ScenarioOptions {
  SynthScenario scenario = SynthScenario::kRandom;
  std::string id_prefix;    // the test id, or the prefix of numbered ids
  int count = 1;            // random: tests; padding-variants: repeats per variant
  std::uint64_t seed = 1;   // random generator seed of the first test
  double duration_s = 0.2;  // random, padding-variants
  SynthOptions synth;
};

// One test of a scenario, described but not yet generated (a scenario may
// hold more tests than fit in memory at once).
struct ScenarioTest {
  std::string external_id;             // id_prefix, or numbered: "<prefix>-0001", "<prefix>-foam-a-01"
  std::optional<std::string> variant;  // padding-variants: "production", "foam-a", "foam-b"
  std::optional<std::uint64_t> seed;   // random motions: the generator seed
  std::optional<double> load_factor;   // padding-variants: scale of the head's load
  RandomMotionOptions motion;          // random motions: what SynthRandomMotion gets
};

// The tests of `options.scenario` in the order they are made: the report's
// scenarios one test named id_prefix; random `count` tests numbered from 1
// (at least four digits); padding-variants for each padding (production
// trim 1.0, foam A 0.8, foam B 0.65 of the load) `count` repeats numbered
// from 1 (two digits), repeat r with seed + r - 1 in every variant.
std::vector<ScenarioTest> ScenarioTests(const ScenarioOptions& options);

// Generates `test` of `options.scenario` for `array`.
SyntheticTest SynthScenarioTest(const ArrayGeometry& array, const ScenarioOptions& options,
                                const ScenarioTest& test);

}  // namespace napkin::engine
