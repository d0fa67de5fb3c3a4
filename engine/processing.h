#pragma once
// Processing configuration of a run and the signal conditioning it drives
// (docs/algorithms.md "Signal conditioning"; report section 3.4: time shift to the
// start of the pulse, truncation, bias removal, filtering). The JSON form
// lives in formats/processing_config_json.h; its canonical dump identifies
// the configuration of stored results.
#include <Eigen/Core>
#include <array>
#include <atomic>
#include <optional>
#include <string_view>

#include "engine/array_geometry.h"
#include "engine/cfc_filter.h"
#include "engine/channel_conditioning.h"
#include "engine/signals.h"
#include "engine/solver.h"
#include "engine/summary.h"
#include "engine/vocabulary.h"

namespace napkin::engine {

// Channel filtering, per sensor kind. A class of nullopt means "none".
struct FilterConfig {
  CfcVariant variant = CfcVariant::kSaeJ211;        // "sae" (J211/1) or "iso" (ISO 6487) design frequency
  std::optional<double> linear_cfc = kCfc1000;      // class for linear accelerometers (head: CFC 1000)
  std::optional<double> angular_rate_cfc = kCfc60;  // class for angular-rate sensors (CFC 60)
  double padding_s = 0.010;                         // reflected padding at each end (>= 10 ms recommended)
};

enum class BiasMode {
  // Subtract the mean of ALL samples with t < 0 (after the shift) when they
  // span >= auto_min_pre_impact_s; otherwise remove nothing. window_s is not
  // read (NHTSA's RmBias convention; docs/algorithms.md "Signal conditioning").
  kAuto,
  kWindow,  // subtract the mean over [window_start_s, window_end_s] (error if the window holds no sample)
  kNone,    // keep the recorded offsets
};

inline constexpr std::array<NamedValue<BiasMode>, 3> kBiasModeNames{
    {{BiasMode::kAuto, "auto"}, {BiasMode::kWindow, "window"}, {BiasMode::kNone, "none"}}};
inline constexpr std::array<BiasMode, 3> kBiasModes = ValuesOf(kBiasModeNames);

// The one spelling of each mode in processing configs ("auto", "window",
// "none"), and its inverse (nullopt for an unknown name).
constexpr const auto& NamesOf(BiasMode) { return kBiasModeNames; }

// Bias (zero offset) removal, applied to every channel after the time shift.
struct BiasConfig {
  BiasMode mode = BiasMode::kAuto;       // see BiasMode
  double window_start_s = -0.010;        // kWindow: first time of the pre-impact window (after the shift)
  double window_end_s = 0.0;             // kWindow: last time of the pre-impact window (after the shift)
  double auto_min_pre_impact_s = 0.001;  // kAuto: pre-impact data needed before the mean is subtracted
};

// Time base (report section 3.4: "time shifted to the beginning of the
// acceleration pulse and truncated").
struct TimeConfig {
  double shift_s = 0.0;  // subtracted from every time stamp: the sample at t = shift_s becomes t = 0
  std::optional<double>
      start_s;                  // keep samples with t >= start_s (after the shift); nullopt = from the first
  std::optional<double> end_s;  // keep samples with t <= end_s (after the shift); nullopt = to the last
};

// a3ms (docs/algorithms.md "Injury criteria"): the level exceeded for a
// cumulative 3 ms (the regulatory definition: FMVSS No. 208 "intervals whose
// cumulative duration is not more than 3 milliseconds", ECE R94 "3 ms
// cumulative"), or for 3 ms without interruption.
enum class A3msDefinition {
  kCumulative,  // the level the resultant is at or above for 3 ms in total
  kContinuous,  // the level the resultant stays at or above for one unbroken 3 ms
};

inline constexpr std::array<NamedValue<A3msDefinition>, 2> kA3msDefinitionNames{
    {{A3msDefinition::kCumulative, "cumulative"}, {A3msDefinition::kContinuous, "continuous"}}};
inline constexpr std::array<A3msDefinition, 2> kA3msDefinitions = ValuesOf(kA3msDefinitionNames);

// The one spelling of each definition in processing configs ("cumulative",
// "continuous"), and its inverse (nullopt for an unknown name).
constexpr const auto& NamesOf(A3msDefinition) { return kA3msDefinitionNames; }

struct A3msConfig {
  A3msDefinition definition = A3msDefinition::kCumulative;
};

struct HicConfig {
  bool from_time_zero = false;  // NHTSA program: integrate |a| and ignore samples before t = 0
};

struct BricConfig {
  Eigen::Vector3d critical_radps{66.25, 56.45, 42.87};  // omega_xC, omega_yC, omega_zC (Takhounts 2013)
};

// What ProcessTest does with a channel screening finds faulty (a `fault`,
// `polarity`, `axis_label`, `saturation` or `non_finite` error naming it;
// engine/salvage.h, docs/algorithms.md "Faulty channels").
enum class SalvageMode {
  kOff,      // the test fails with the finding's sentence (and says what salvage would do)
  kExclude,  // solve without the faulty channel(s), when the rest still determine the motion
  kRepair,   // invert a flipped, swap back a swapped channel; replace faulty samples by the
             // channel's rigid-body prediction from the others; solve the whole array
};
inline constexpr std::array<NamedValue<SalvageMode>, 3> kSalvageModeNames{
    {{SalvageMode::kOff, "off"}, {SalvageMode::kExclude, "exclude"}, {SalvageMode::kRepair, "repair"}}};
inline constexpr std::array<SalvageMode, 3> kSalvageModes = ValuesOf(kSalvageModeNames);
constexpr const auto& NamesOf(SalvageMode) { return kSalvageModeNames; }

// Thresholds of the data-screening checks (report sections 2.2 and 3.4:
// bias, spikes, saturation, self-consistency of the array).
struct ScreeningConfig {
  double residual_limit_g = 5.0;   // per-sample rigid-body residual norm above which samples are flagged
  double spike_size_g = 50.0;      // one-sample jump of a linear channel against both neighbours
  double spike_size_radps = 20.0;  // one-sample jump of an angular-rate channel against both neighbours
  int saturation_run_samples = 5;  // run of equal samples at a channel's extreme that flags clipping
  double bias_limit_g = 1.5;       // zero offset of a linear channel beyond which bias is reported
                                   // (above 1 g, so an unzeroed channel reading gravity is no fault)
  double bias_limit_radps = 0.5;   // pre-impact mean of an angular-rate channel beyond which bias is reported
  SalvageMode salvage = SalvageMode::kOff;  // what to do with a faulty channel
};

// Physical plausibility (docs/algorithms.md "Physical plausibility"): limits
// far beyond any real head impact. A raw channel, the solved head motion or
// the rigid-body residual beyond them fails the test with an `implausible`
// error finding naming the channel, time and value (a corrupt sample or a
// wrong unit, not a severe impact).
struct PlausibilityConfig {
  double max_acceleration_g = 2000.0;         // |a| of a linear channel and of the solved CG acceleration
  double max_angular_velocity_radps = 500.0;  // |w| of a rate channel, the solved and the initial velocity
  double max_residual_factor = 100.0;         // rigid-body residual beyond this multiple of residual_limit_g
  double max_initial_speed_mps = 1000.0;      // |v| of the initial velocity
};

// How `napkin run` stores a result's derived channels (the kinematics time
// histories; docs/formats.md "Derived-channel storage"). Summaries, HIC
// windows, findings and the conditioning record are always stored.
enum class DerivedStorage {
  kFloat64,  // IEEE-754 binary64: exports are bit-exact
  kFloat32,  // binary32 (round to nearest): 7 significant digits, half the bytes
  kNone,     // nothing stored: export and report recompute from the raw channels
};

inline constexpr std::array<NamedValue<DerivedStorage>, 3> kDerivedStorageNames{
    {{DerivedStorage::kFloat64, "float64"},
     {DerivedStorage::kFloat32, "float32"},
     {DerivedStorage::kNone, "none"}}};
inline constexpr std::array<DerivedStorage, 3> kDerivedStorages = ValuesOf(kDerivedStorageNames);

// The one spelling of each choice in processing configs ("float64",
// "float32", "none") and in the catalogue's encoding column, and its
// inverse (nullopt for an unknown name).
constexpr const auto& NamesOf(DerivedStorage) { return kDerivedStorageNames; }

struct StorageConfig {
  DerivedStorage derived_channels = DerivedStorage::kFloat32;  // "float32" by default
};

struct ProcessingConfig {
  SolverKind solver = SolverKind::kExact;  // "exact" (default) or "seed" (LC_COMP compatibility)
  FilterConfig filter;                     // channel filtering
  BiasConfig bias;                         // zero-offset removal
  TimeConfig time;                         // shift and crop
  GravityOptions gravity;                  // gravity compensation (off: report compatibility)
  HicConfig hic;                           // HIC options
  A3msConfig a3ms;                         // a3ms definition (cumulative by default)
  BricConfig bric;                         // BrIC critical values
  ScreeningConfig screening;               // screening thresholds
  PlausibilityConfig plausibility;         // limits of physical plausibility (errors)
  StorageConfig storage;                   // how results' derived channels are stored

  // Throws InputError naming the offending field (JSON key path, e.g.
  // "filter.linear_cfc") when a value is out of range.
  void Check() const;
};

// Solver options for one test under `config`.
SolveOptions MakeSolveOptions(const ProcessingConfig& config, const InitialState& initial);

// Conditions the raw signals of one test in place, in this order:
//  1. time shift (t0 -= time.shift_s);
//  2. bias removal on every channel (bias.mode), using the shifted times;
//  3. CFC filtering per sensor kind of `array` (columns whose slot is not in
//     the array are left unfiltered: the solvers do not read them). A column
//     whose signals.prefiltered_cfc is at or below the requested class is not
//     filtered again (its samples pass bit for bit); a narrower requested
//     class is applied;
//  4. crop to [time.start_s, time.end_s] (after filtering, so the filter
//     sees real data rather than padding at the crop edges).
// Returns what it did to each column, in column order. Throws InputError
// naming the slot and sample on a non-finite value, and on an empty bias
// window or a crop that leaves fewer than 2 samples; Cancelled once `cancel`
// is set (engine/cancellation.h). `filter_work` (null: the filters' own)
// lends the CFC filters their padded work buffer, kept for the next test
// (engine/pipeline.h Workspace).
std::vector<ChannelConditioning> ApplyConditioning(const ArrayGeometry& array, TestSignals& signals,
                                                   const ProcessingConfig& config,
                                                   const std::atomic<bool>* cancel = nullptr,
                                                   Eigen::VectorXd* filter_work = nullptr);

// Whether a channel already filtered at `prefiltered_cfc` needs no filter of
// class `requested_cfc`: the same or a narrower class was applied (1e-9
// relative tolerance). A filter of unknown class (kPrefilteredClassUnknown)
// covers none.
bool PrefilterCovers(double prefiltered_cfc, double requested_cfc);

// One info finding (check "prefiltered") per channel the file records as
// filtered: the filter napkin left out, or the narrower class it applied.
std::vector<Finding> ConditioningFindings(const std::vector<ChannelConditioning>& conditioning);

}  // namespace napkin::engine
