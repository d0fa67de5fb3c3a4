#pragma once
// Per-test summary: every field of the query contract (docs/formats.md
// "Per-test summary fields") plus the screening findings. The names, order
// and query groups of the numeric fields are in engine/summary_fields.h: a new
// criterion is a row there that computes it (SummaryField::compute), stored
// in TestSummary::computed, and a schema migration adding its column.
#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "engine/channel_conditioning.h"
#include "engine/kinematics.h"
#include "engine/vocabulary.h"

namespace napkin::engine {

struct HicWindow {
  double value = 0.0;
  double t1_s = 0.0;
  double t2_s = 0.0;
};

enum class Severity { kInfo, kWarning, kError };

// What a finding is about: the data-screening checks (engine/screening.h),
// the plausibility limits, and an array that cannot determine rotation
// (docs/algorithms.md "Acceleration-only arrays").
enum class Check {
  kMissing,      // a slot of the array with no channel
  kNonFinite,    // NaN or infinite samples
  kImplausible,  // beyond the plausibility limits
  kSaturation,   // a run of equal samples at a channel's extreme
  kSpike,        // one-sample jumps
  kBias,         // zero offset
  kFlat,         // a channel that never changes
  kPolarity,     // a channel whose sign is flipped
  kAxisLabel,    // two channels swapped
  kResidual,     // rigid-body residual
  kConsistency,  // too few redundant sensors to screen the array
  kRotation,     // the array cannot determine rotation
  kFault,        // one channel (or two) whose omission makes the array rigid (engine/salvage.h)
  kSalvage,      // what salvage did to a faulty channel (engine/salvage.h)
};

// The one spelling of each check in findings (summary JSON, the catalogue's
// `quality`, the report).
inline constexpr std::array<NamedValue<Check>, 14> kCheckNames{{{Check::kMissing, "missing"},
                                                                {Check::kNonFinite, "non_finite"},
                                                                {Check::kImplausible, "implausible"},
                                                                {Check::kSaturation, "saturation"},
                                                                {Check::kSpike, "spike"},
                                                                {Check::kBias, "bias"},
                                                                {Check::kFlat, "flat"},
                                                                {Check::kPolarity, "polarity"},
                                                                {Check::kAxisLabel, "axis_label"},
                                                                {Check::kResidual, "residual"},
                                                                {Check::kConsistency, "consistency"},
                                                                {Check::kRotation, "rotation"},
                                                                {Check::kFault, "fault"},
                                                                {Check::kSalvage, "salvage"}}};
constexpr const auto& NamesOf(Check) { return kCheckNames; }

struct Finding {
  std::string check;                   // NameOf(Check), e.g. "saturation", "polarity", "residual"
  std::optional<std::string> channel;  // slot name, or none for the whole test
  Severity severity = Severity::kInfo;
  std::string detail;  // one sentence
};

inline constexpr std::array<NamedValue<Severity>, 3> kSeverityNames{
    {{Severity::kInfo, "info"}, {Severity::kWarning, "warning"}, {Severity::kError, "error"}}};
inline constexpr std::array<Severity, 3> kSeverities = ValuesOf(kSeverityNames);

// The one spelling of each severity ("info", "warning", "error") in the
// summary JSON and the catalogue, and its inverse (nullopt for an unknown name).
constexpr const auto& NamesOf(Severity) { return kSeverityNames; }

// How a faulty channel failed (docs/algorithms.md "Faulty channels"): read from
// the recorded samples over the fault's interval against what the other
// channels imply there.
enum class FaultKind {
  kDropout,       // reads zero (or non-finite) where the others imply motion
  kStuck,         // a constant reading (a flat line) while the others move
  kClipped,       // a flat top at the channel's extreme (saturation)
  kSpike,         // isolated samples off the rigid body
  kFlipped,       // the whole channel sign flipped
  kSwapped,       // two channels of one kind exchanged
  kInconsistent,  // off the rigid body in some other way (a gain error, noise bursts)
};
inline constexpr std::array<NamedValue<FaultKind>, 7> kFaultKindNames{
    {{FaultKind::kDropout, "dropout"},
     {FaultKind::kStuck, "stuck"},
     {FaultKind::kClipped, "clipped"},
     {FaultKind::kSpike, "spike"},
     {FaultKind::kFlipped, "flipped"},
     {FaultKind::kSwapped, "swapped"},
     {FaultKind::kInconsistent, "inconsistent"}}};
inline constexpr std::array<FaultKind, 7> kFaultKinds = ValuesOf(kFaultKindNames);
constexpr const auto& NamesOf(FaultKind) { return kFaultKindNames; }

// What salvage did to a faulty channel.
enum class SalvageAction {
  kExcluded,     // left out of the array
  kInverted,     // its sign flipped back
  kSwappedBack,  // exchanged back with its partner
  kReplaced,     // faulty samples replaced by the rigid-body prediction
};
inline constexpr std::array<NamedValue<SalvageAction>, 4> kSalvageActionNames{
    {{SalvageAction::kExcluded, "excluded"},
     {SalvageAction::kInverted, "inverted"},
     {SalvageAction::kSwappedBack, "swapped back"},
     {SalvageAction::kReplaced, "replaced"}}};
inline constexpr std::array<SalvageAction, 4> kSalvageActions = ValuesOf(kSalvageActionNames);
constexpr const auto& NamesOf(SalvageAction) { return kSalvageActionNames; }

// What salvage did to one channel (docs/formats.md "Salvage record").
struct SalvagedChannel {
  std::string channel;
  FaultKind fault = FaultKind::kInconsistent;
  SalvageAction action = SalvageAction::kExcluded;
  std::optional<std::string> partner;  // the other channel of a swap
  double t1_s = 0.0;                   // the fault's interval: its first and last faulty sample
  double t2_s = 0.0;
  std::int64_t samples_replaced = 0;  // repair: samples replaced by the rigid-body prediction
  // repair: the whole repaired channel, in the unit and on the time base of
  // the recorded one (its good samples are the recorded ones); empty when
  // excluded. Not a summary field: stored beside the recorded channel and
  // exported (docs/formats.md "Salvage record").
  std::vector<double> repaired_samples;
};

// The audit trail of a salvaged test: the mode, every channel it excluded
// or repaired, and the RMS rigid-body residual of the exact solver before
// and after (infinite before when the recorded channels made it diverge).
struct SalvageAudit {
  std::string mode;  // NameOf(SalvageMode): "exclude" or "repair"
  std::vector<SalvagedChannel> channels;
  double rms_residual_before_mps2 = 0.0;
  double rms_residual_after_mps2 = 0.0;
  int channels_used = 0;   // the sensors the published result was solved from
  int channels_total = 0;  // the array's sensors
};

struct TestSummary {
  // query hic
  HicWindow hic15, hic36, hic;  // hic: no window limit
  double peak_acc_g = 0.0;      // resultant CG acceleration, fixed frame
  double a3ms_g = 0.0;
  double hic_d = 0.0;  // FMVSS 201 free-motion headform HIC(d), from hic36
  // query rotation
  Eigen::Vector3d peak_omega_body_radps = Eigen::Vector3d::Zero();  // max |omega_i|, body axes
  double peak_omega_radps = 0.0;                                    // resultant
  double peak_alpha_radps2 = 0.0;                                   // resultant
  double bric = 0.0;
  double damage = 0.0;
  Eigen::Vector4d final_quat_wxyz = Eigen::Vector4d(1, 0, 0, 0);
  Eigen::Vector3d final_roll_pitch_yaw_deg = Eigen::Vector3d::Zero();
  Eigen::Vector3d final_pos_fixed_m = Eigen::Vector3d::Zero();
  double max_rotation_deg = 0.0;  // largest angle between current and initial orientation
  // query risk (engine/injury_risk.h): probabilities 0..1
  double hic15_p_ais3 = 0.0;
  double hic36_p_ais4 = 0.0;
  double bric_p_ais3 = 0.0;  // NaN where bric is
  double bric_p_ais4 = 0.0;
  // The criteria a summary-field row computes itself (SummaryField::compute,
  // engine/summary_fields.h), by field name: a new criterion needs no member
  // here. SummaryField::Get and Set read and write them.
  std::map<std::string, double, std::less<>> computed;
  // quality
  double max_residual_mps2 = 0.0;
  std::vector<Finding> findings;
  // Set when salvage (ScreeningConfig::salvage) excluded or repaired a
  // faulty channel: the result comes from the salvaged signals.
  std::optional<SalvageAudit> salvage;
  // What conditioning did to each channel, in column order (not a summary field).
  std::vector<ChannelConditioning> conditioning;
};

// Fills the kinematic fields (peaks, final pose, max rotation, residual) of a
// summary from solved kinematics. Criteria (HIC, a3ms, BrIC, DAMAGE) are
// filled by the criteria module.
void SummarizeKinematics(const Kinematics& kinematics, TestSummary& summary);

}  // namespace napkin::engine
