#pragma once
// Raw signals of one test: uniformly sampled channels, one column per slot.
#include <Eigen/Core>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace napkin::engine {

// A prefiltered_cfc of 0 (no class is 0 Hz): the file records the channel
// as filtered, at a class it does not name (docs/formats.md "UDS-1992 input").
inline constexpr double kPrefilteredClassUnknown = 0.0;

// A field added here is copied by engine/pipeline.cpp's CopyToCondition too.
struct TestSignals {
  double dt_s = 1e-4;              // sampling interval
  double t0_s = 0.0;               // time of the first sample
  std::vector<std::string> slots;  // column names (array slot names)
  // rows = samples, cols = channels; column-major so each channel is
  // contiguous. Values in the unit the array gives the slot (g, rad/s, ...).
  Eigen::MatrixXd samples;
  // Per column, the CFC class the file records the channel as already
  // filtered at (docs/formats.md: ISO-MME filter letter / "Channel frequency
  // class", UDS-1992 FCUT); nullopt = raw or not recorded,
  // kPrefilteredClassUnknown = filtered at a class the file does not name
  // (a UDS-1992 FCUT that is no SAE J211 cut-off). Empty (the usual case,
  // e.g. CSV) = no channel recorded as filtered.
  std::vector<std::optional<double>> prefiltered_cfc;
  // Per sample, the line of the file it was read from (the CSV reader sets
  // it), so that a sentence about a sample names the row the user can open;
  // empty where not known (other formats, signals read back from the
  // catalogue). Used only when it has one entry per sample.
  std::vector<std::int64_t> file_rows;

  Eigen::Index size() const { return samples.rows(); }
  // prefiltered_cfc of column `column`, nullopt when not recorded.
  std::optional<double> PrefilteredCfc(Eigen::Index column) const;
  double TimeAt(Eigen::Index k) const { return t0_s + static_cast<double>(k) * dt_s; }
  // The file line of sample `k` (file_rows), or nullopt.
  std::optional<std::int64_t> FileRowOf(Eigen::Index k) const;
  // Column index of `slot`, or -1.
  int FindSlot(const std::string& slot) const;
};

// State of the head at the first sample.
struct InitialState {
  // Report eq. 2.1-14/15: body-to-fixed R0 = Rx(phi) * Ry(theta) * Rz(psi).
  Eigen::Vector3d orientation_rad = Eigen::Vector3d::Zero();  // phi, theta, psi
  Eigen::Vector3d velocity_fixed_mps = Eigen::Vector3d::Zero();
  Eigen::Vector3d omega_body_radps = Eigen::Vector3d::Zero();  // usually at rest
};

}  // namespace napkin::engine
