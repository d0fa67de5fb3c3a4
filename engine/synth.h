#pragma once
// Synthetic tests with exact answers: signals an ideal array would record for
// an analytically known rigid-body motion, plus the true kinematics at every
// sample. Used by the tests, `napkin synth` and `make demo`.
#include <cstdint>
#include <string>

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

}  // namespace napkin::engine
