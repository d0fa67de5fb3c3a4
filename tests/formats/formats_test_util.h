#pragma once
// Helpers for the formats tests: deterministic signals and error-message checks.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>

#include "common/error.h"
#include "engine/array_geometry.h"
#include "engine/signals.h"

namespace napkin::test_support {

// Smooth, distinct, non-trivial samples for every slot of `array`; with
// `single_precision` each value is representable as a float (UDS-1992 REAL*4).
inline engine::TestSignals MakeSignals(const engine::ArrayGeometry& array, Eigen::Index samples, double dt_s,
                                       double t0_s, bool single_precision = false) {
  engine::TestSignals signals;
  signals.dt_s = dt_s;
  signals.t0_s = t0_s;
  signals.samples.resize(samples, static_cast<Eigen::Index>(array.sensors.size()));
  for (std::size_t c = 0; c < array.sensors.size(); ++c) {
    signals.slots.push_back(array.sensors[c].slot);
    for (Eigen::Index k = 0; k < samples; ++k) {
      const double t = t0_s + static_cast<double>(k) * dt_s;
      double value =
          (10.0 + static_cast<double>(c)) * std::sin(2.0 * 3.14159265358979 * (7.0 + c) * t + 0.3 * c) +
          1e-3 * static_cast<double>(k % 17) - 0.37 * static_cast<double>(c);
      if (single_precision) value = static_cast<double>(static_cast<float>(value));
      signals.samples(k, static_cast<Eigen::Index>(c)) = value;
    }
  }
  return signals;
}

inline void WriteBytes(const std::filesystem::path& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary) << bytes;
}

inline std::string ReadBytes(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

// Runs `action`, expecting an InputError whose one-sentence message contains
// every fragment (typically the file name and the problem).
inline void ExpectInputError(const std::function<void()>& action, const std::vector<std::string>& fragments) {
  try {
    action();
    ADD_FAILURE() << "no InputError; expected one mentioning " << fragments.front();
  } catch (const InputError& error) {
    const std::string message = error.what();
    for (const std::string& fragment : fragments)
      EXPECT_NE(message.find(fragment), std::string::npos)
          << "message: " << message << "\nmissing: " << fragment;
    EXPECT_EQ(message.back(), '.') << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  }
}

}  // namespace napkin::test_support
