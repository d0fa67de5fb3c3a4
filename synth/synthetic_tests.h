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
#include "engine/units.h"

namespace napkin::synth {

struct SyntheticTest {
  std::string name;
  engine::ArrayGeometry array;   // the geometry the signals were generated with
  engine::TestSignals signals;   // in the units the array gives each slot
  engine::InitialState initial;  // orientation and velocity at the first sample
  engine::Kinematics truth;      // exact kinematics at every sample (residual 0)
};

struct SynthOptions {
  double rate_hz = 10000.0;
  bool gravity = false;  // sensors also sense -R^T g_fixed, zeroed at t = 0
  Eigen::Vector3d g_fixed_mps2{0.0, 0.0, engine::kStandardGravity};
};

// Report section 4.5: rotation about an axis parallel to fixed Y, 10 in from
// the CG, omega_Y(t) = 25 (1 - cos(2 pi t / 0.06)) rad/s for 0 <= t <= 60 ms,
// then 0; 100 ms; samples at t = 0, dt, ..., 0.1 s.
SyntheticTest SynthSeedFixedAxis(const engine::ArrayGeometry& array, const Eigen::Vector3d& orientation_rad,
                                 const SynthOptions& options = {});

// Report section 4.4: 90 deg about body x (0-40 ms), rest, 90 deg about body
// y (50-90 ms), rest, 90 deg about body z (100-140 ms), each with
// theta(t) = 45 deg (1 - cos(pi t / 40 ms)); 150 ms.
SyntheticTest SynthSequential(const engine::ArrayGeometry& array, const SynthOptions& options = {});

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
SyntheticTest SynthRandomMotion(const engine::ArrayGeometry& array, const RandomMotionOptions& options);

// A copy of `array` with every sensor moved by a random offset of length up to
// `max_offset_m` (seeded): the "true" geometry of a test whose nominal
// geometry is `array`.
engine::ArrayGeometry DisplaceSensors(const engine::ArrayGeometry& array, double max_offset_m,
                                      std::uint64_t seed);

// One head impact of the padding series (docs/algorithms.md "Synthetic
// padding series"): a free Hybrid III-sized head, flying at `speed_mps`
// along `trajectory_deg` (in the fixed horizontal plane, from fixed X
// towards -Y: forward and to the left, the driver-side A-pillar of the
// report, section 3.3), meets the padding; the padding pushes on the head
// at `contact_point_body_m` with a haversine force pulse of `pulse_s`
// against the trajectory whose impulse is m (1 + restitution) speed. The
// force acts off the CG, so the head picks up angular velocity; a torsional
// spring-damper stands for the neck. The rigid body is integrated (RK4,
// 20 sub-steps per sample) and sensed by the array; white noise of
// `noise_g` (linear) and `noise_radps` (angular-rate channels) is added to
// the signals, never to the truth.
struct HeadImpact {
  double speed_mps = 15.0 * 0.44704;  // 15 mph (the report's B-pillar test, section 3.10)
  double trajectory_deg = 36.0;       // the report, section 3.3: 36 deg to the head's x axis
  Eigen::Vector3d contact_point_body_m{0.0, 0.0, 0.0};  // from the CG, body axes
  double pulse_s = 0.0115;                              // contact duration
  double restitution = 0.2;                             // rebound speed / impact speed
  double contact_start_s = 0.005;                       // free flight before contact
  double duration_s = 0.1;                              // record length (the report, section 3.4)
  double noise_g = 0.2;                                 // RMS white noise, linear channels
  double noise_radps = 0.05;                            // RMS white noise, angular-rate channels
  std::uint64_t noise_seed = 1;
  // The head and neck.
  double head_mass_kg = 4.54;                                 // Hybrid III 50th head (49 CFR 572.32)
  Eigen::Vector3d head_inertia_kgm2{0.0160, 0.0225, 0.0195};  // principal, body x, y, z
  double neck_stiffness_nm_per_rad = 40.0;
  double neck_damping_nms_per_rad = 0.8;
};

// The contact point of the nominal impact: on a 0.1 m sphere about the CG,
// 6 deg further round to the left than the trajectory and 8 deg above the
// CG (body z is down), so the force passes about 17 mm from the CG.
Eigen::Vector3d NominalContactPoint(double trajectory_deg);

// Generates `impact` for `array` (head initially aligned with the fixed axes,
// initial velocity speed along the trajectory).
SyntheticTest SynthHeadImpact(const engine::ArrayGeometry& array, const HeadImpact& impact,
                              const SynthOptions& options = {});

// A padding of the series: softer padding, same impact, longer and lower pulse.
struct PaddingVariant {
  const char* name;
  double pulse_s;      // nominal contact duration
  double restitution;  // nominal rebound speed / impact speed
};
inline constexpr PaddingVariant kPaddingVariants[] = {
    {"production", 0.0115, 0.20},  // production trim
    {"foam-a", 0.0130, 0.15},
    {"foam-b", 0.0145, 0.10},
};
// Repeats per variant of `napkin synth --scenario padding-series` by default.
inline constexpr int kPaddingRepeats = 5;

// The impact of one test of `variant`: the nominal impact with the
// test-to-test scatter of a test series drawn from `seed` (normal, truncated
// at 3 sigma): impact speed 1.5 %, trajectory 1.5 deg, contact point 2 mm
// per axis, pulse duration 2 %; noise seeded by `seed`.
HeadImpact ScatteredImpact(const PaddingVariant& variant, std::uint64_t seed);

// The scenarios of `napkin synth`.
enum class SynthScenario {
  kSeedFixedAxis,   // report 4.5 (SynthSeedFixedAxis at phi = theta = psi = 0.5 rad)
  kSeedSequential,  // report 4.4 (SynthSequential)
  kRandom,          // `count` random motions, seeds seed, seed + 1, ...
  kPaddingSeries,   // oblique head impacts, three paddings (SynthHeadImpact)
};
inline constexpr SynthScenario kSynthScenarios[] = {SynthScenario::kSeedFixedAxis,
                                                    SynthScenario::kSeedSequential, SynthScenario::kRandom,
                                                    SynthScenario::kPaddingSeries};
// "seed-fixed-axis", "seed-sequential", "random", "padding-series".
const char* SynthScenarioName(SynthScenario scenario);
std::optional<SynthScenario> ParseSynthScenario(std::string_view name);
// True for the scenarios whose duration is chosen (random); the others have
// a fixed duration.
bool HasChosenDuration(SynthScenario scenario);
// Tests (random) or repeats per variant (padding-series) when no count is given.
int DefaultCount(SynthScenario scenario);

struct ScenarioOptions {
  SynthScenario scenario = SynthScenario::kRandom;
  std::string id_prefix;    // the test id, or the prefix of numbered ids
  int count = 1;            // random: tests; padding-series: repeats per variant
  std::uint64_t seed = 1;   // generator seed of the first test
  double duration_s = 0.2;  // random
  SynthOptions synth;
};

// One test of a scenario, described but not yet generated (a scenario may
// hold more tests than fit in memory at once).
struct ScenarioTest {
  std::string external_id;             // id_prefix, or numbered: "<prefix>-0001", "<prefix>-foam-a-01"
  std::optional<std::string> variant;  // padding-series: "production", "foam-a", "foam-b"
  std::optional<std::uint64_t> seed;   // random, padding-series: the generator seed
  std::optional<HeadImpact> impact;    // padding-series: the test's impact (ScatteredImpact)
  RandomMotionOptions motion;          // random motions: what SynthRandomMotion gets
};

// The tests of `options.scenario` in the order they are made: the report's
// scenarios one test named id_prefix; random `count` tests numbered from 1
// (at least four digits); padding-series for each padding of
// kPaddingVariants `count` repeats numbered from 1 (two digits), the i-th
// test of the series (from 0) with seed + i.
std::vector<ScenarioTest> ScenarioTests(const ScenarioOptions& options);

// Generates `test` of `options.scenario` for `array`.
SyntheticTest SynthScenarioTest(const engine::ArrayGeometry& array, const ScenarioOptions& options,
                                const ScenarioTest& test);

}  // namespace napkin::synth
