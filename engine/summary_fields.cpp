#include "engine/summary_fields.h"

#include <cmath>

#include "engine/injury_risk.h"
#include "engine/ubric.h"

namespace napkin::engine {
namespace {

using G = SummaryGroup;
using S = TestSummary;

// The curves of the risk fields (engine/injury_risk.h), each named here once.
constexpr RiskCurve kNcapHic15Ais3{"hic15", 3, "NCAP", NcapHic15Ais3Risk};
constexpr RiskCurve kPrasadMertzHic36Ais4{"hic36", 4, "Prasad–Mertz", PrasadMertzHic36Ais4Risk};
constexpr RiskCurve kTakhountsBricAis3{"bric", 3, "Takhounts", TakhountsBricAis3Risk};
constexpr RiskCurve kTakhountsBricAis4{"bric", 4, "Takhounts", TakhountsBricAis4Risk};

// A row's properties that most rows lack, set by name around the row.
constexpr SummaryField LogScale(SummaryField field) {
  field.log_scale = true;
  return field;
}
constexpr SummaryField InVerdict(SummaryField field) {
  field.in_verdict = true;
  return field;
}
// A criterion the row computes from the kinematics (SummaryField::compute);
// `field` is nullptr and its value lives in TestSummary::computed.
constexpr SummaryField Computed(SummaryField field, double (*compute)(const Kinematics&)) {
  field.compute = compute;
  return field;
}

constexpr SummaryField kSummaryFields[] = {
    InVerdict(LogScale({"hic15", G::kHic, "HIC15", "", "HIC, windows up to 15 ms",
                        [](S& s) -> double& { return s.hic15.value; }})),
    {"hic15_t1_s", G::kHic, "HIC15 window start", "s", "HIC15 window start (s)",
     [](S& s) -> double& { return s.hic15.t1_s; }},
    {"hic15_t2_s", G::kHic, "HIC15 window end", "s", "HIC15 window end (s)",
     [](S& s) -> double& { return s.hic15.t2_s; }},
    LogScale({"hic36", G::kHic, "HIC36", "", "HIC, windows up to 36 ms",
              [](S& s) -> double& { return s.hic36.value; }}),
    {"hic36_t1_s", G::kHic, "HIC36 window start", "s", "HIC36 window start (s)",
     [](S& s) -> double& { return s.hic36.t1_s; }},
    {"hic36_t2_s", G::kHic, "HIC36 window end", "s", "HIC36 window end (s)",
     [](S& s) -> double& { return s.hic36.t2_s; }},
    LogScale({"hic", G::kHic, "HIC", "", "HIC, no window limit", [](S& s) -> double& { return s.hic.value; },
              nullptr, "no window limit"}),
    {"hic_t1_s", G::kHic, "HIC window start", "s", "HIC window start (s)",
     [](S& s) -> double& { return s.hic.t1_s; }},
    {"hic_t2_s", G::kHic, "HIC window end", "s", "HIC window end (s)",
     [](S& s) -> double& { return s.hic.t2_s; }},
    LogScale({"peak_acc_g", G::kHic, "peak acceleration", "g",
              "peak resultant CG acceleration, fixed frame (g)",
              [](S& s) -> double& { return s.peak_acc_g; }}),
    LogScale({"a3ms_g", G::kHic, "a3ms", "g", "3 ms clip acceleration (g)",
              [](S& s) -> double& { return s.a3ms_g; }}),
    LogScale({"peak_omega_x_radps", G::kRotation, "peak |ω_x|", "rad/s", "peak |omega_x|, body axes (rad/s)",
              [](S& s) -> double& { return s.peak_omega_body_radps[0]; }}),
    LogScale({"peak_omega_y_radps", G::kRotation, "peak |ω_y|", "rad/s", "peak |omega_y|, body axes (rad/s)",
              [](S& s) -> double& { return s.peak_omega_body_radps[1]; }}),
    LogScale({"peak_omega_z_radps", G::kRotation, "peak |ω_z|", "rad/s", "peak |omega_z|, body axes (rad/s)",
              [](S& s) -> double& { return s.peak_omega_body_radps[2]; }}),
    LogScale({"peak_omega_radps", G::kRotation, "peak angular velocity", "rad/s",
              "peak resultant angular velocity (rad/s)", [](S& s) -> double& { return s.peak_omega_radps; }}),
    LogScale({"peak_alpha_radps2", G::kRotation, "peak angular acceleration", "rad/s²",
              "peak resultant angular acceleration (rad/s^2)",
              [](S& s) -> double& { return s.peak_alpha_radps2; }}),
    InVerdict(LogScale(
        {"bric", G::kRotation, "BrIC", "", "BrIC (dimensionless)", [](S& s) -> double& { return s.bric; }})),
    LogScale({"damage", G::kRotation, "DAMAGE", "", "DAMAGE (dimensionless)",
              [](S& s) -> double& { return s.damage; }}),
    {"final_quat_w", G::kRotation, "final quaternion w", "",
     "final orientation quaternion, fixed from body, w",
     [](S& s) -> double& { return s.final_quat_wxyz[0]; }},
    {"final_quat_x", G::kRotation, "final quaternion x", "", "final orientation quaternion, x",
     [](S& s) -> double& { return s.final_quat_wxyz[1]; }},
    {"final_quat_y", G::kRotation, "final quaternion y", "", "final orientation quaternion, y",
     [](S& s) -> double& { return s.final_quat_wxyz[2]; }},
    {"final_quat_z", G::kRotation, "final quaternion z", "", "final orientation quaternion, z",
     [](S& s) -> double& { return s.final_quat_wxyz[3]; }},
    {"final_roll_deg", G::kRotation, "final roll", "deg", "final roll (deg)",
     [](S& s) -> double& { return s.final_roll_pitch_yaw_deg[0]; }},
    {"final_pitch_deg", G::kRotation, "final pitch", "deg", "final pitch (deg)",
     [](S& s) -> double& { return s.final_roll_pitch_yaw_deg[1]; }},
    {"final_yaw_deg", G::kRotation, "final yaw", "deg", "final yaw (deg)",
     [](S& s) -> double& { return s.final_roll_pitch_yaw_deg[2]; }},
    {"final_pos_x_m", G::kRotation, "final position x", "m", "final CG position, fixed frame, x (m)",
     [](S& s) -> double& { return s.final_pos_fixed_m[0]; }},
    {"final_pos_y_m", G::kRotation, "final position y", "m", "final CG position, fixed frame, y (m)",
     [](S& s) -> double& { return s.final_pos_fixed_m[1]; }},
    {"final_pos_z_m", G::kRotation, "final position z", "m", "final CG position, fixed frame, z (m)",
     [](S& s) -> double& { return s.final_pos_fixed_m[2]; }},
    {"max_rotation_deg", G::kRotation, "max rotation", "deg",
     "largest angle from the initial orientation (deg)", [](S& s) -> double& { return s.max_rotation_deg; }},
    // A screening measure (beside the findings), not a result of the contract's views.
    {"max_residual_mps2", G::kQuality, "max residual", "m/s²", "largest solver residual (m/s^2)",
     [](S& s) -> double& { return s.max_residual_mps2; }},
    // Added by schema 3 (a column appended to the results table, hence last);
    // the views list it after the other HIC fields.
    LogScale({"hic_d", G::kHic, "HIC(d)", "", "FMVSS 201 free-motion headform HIC(d) = 0.75446 HIC36 + 166.4",
              [](S& s) -> double& { return s.hic_d; }}),
    // Added by schema 8 (columns appended to the results table); the curves
    // are engine/injury_risk.h, docs/algorithms.md "Injury risk".
    {"hic15_p_ais3", G::kRisk, nullptr, "",
     "P(AIS 3+ head injury) from HIC15, NHTSA NCAP lognormal curve (0..1)",
     [](S& s) -> double& { return s.hic15_p_ais3; }, &kNcapHic15Ais3},
    {"hic36_p_ais4", G::kRisk, nullptr, "", "P(AIS 4+ brain injury) from HIC36, Prasad-Mertz curve (0..1)",
     [](S& s) -> double& { return s.hic36_p_ais4; }, &kPrasadMertzHic36Ais4},
    {"bric_p_ais3", G::kRisk, nullptr, "", "P(AIS 3+ brain injury) from BrIC, Takhounts et al. 2013 (0..1)",
     [](S& s) -> double& { return s.bric_p_ais3; }, &kTakhountsBricAis3},
    {"bric_p_ais4", G::kRisk, nullptr, "", "P(AIS 4+ brain injury) from BrIC, Takhounts et al. 2013 (0..1)",
     [](S& s) -> double& { return s.bric_p_ais4; }, &kTakhountsBricAis4},
    // Added by schema 14 (a column appended to the results table); a criterion
    // its row computes (engine/ubric.h), shown after the other rotation fields.
    Computed(
        LogScale({"ubric", G::kRotation, "UBrIC", "",
                  "UBrIC, universal brain injury criterion, Gabler et al. 2018 (dimensionless)", nullptr}),
        UbricOf),
};

bool SameNumber(double a, double b) { return a == b || (std::isnan(a) && std::isnan(b)); }

}  // namespace

std::span<const SummaryField> SummaryFields() { return kSummaryFields; }

const SummaryField* FindSummaryField(std::string_view name) {
  for (const SummaryField& field : kSummaryFields)
    if (name == field.name) return &field;
  return nullptr;
}

std::vector<const SummaryField*> RiskFields() {
  std::vector<const SummaryField*> fields;
  for (const SummaryField& field : kSummaryFields)
    if (field.curve != nullptr) fields.push_back(&field);
  return fields;
}

std::string FieldLabel(const SummaryField& field) {
  if (field.curve == nullptr) return field.label;
  return "P(AIS " + std::to_string(field.curve->ais) + "+ | " +
         FieldLabel(*FindSummaryField(field.curve->criterion)) + ")";
}

std::string FieldTableLabel(const SummaryField& field) {
  if (field.curve != nullptr)
    return "P(AIS " + std::to_string(field.curve->ais) + "+) from " +
           FieldLabel(*FindSummaryField(field.curve->criterion)) + " (" + field.curve->source + ")";
  const std::string detail =
      std::string(field.detail) + (*field.detail && *field.unit ? ", " : "") + field.unit;
  return detail.empty() ? std::string(field.label) : std::string(field.label) + " (" + detail + ")";
}

std::vector<const SummaryField*> SummaryFieldsOf(std::initializer_list<SummaryGroup> groups) {
  std::vector<const SummaryField*> fields;
  for (const SummaryGroup group : groups)
    for (const SummaryField& field : kSummaryFields)
      if (field.group == group) fields.push_back(&field);
  return fields;
}

std::vector<std::string> SummaryFieldNames(SummaryGroup group) {
  std::vector<std::string> names;
  for (const SummaryField* field : SummaryFieldsOf({group})) names.emplace_back(field->name);
  return names;
}

std::vector<std::string> DifferingSummaryFields(const TestSummary& a, const TestSummary& b) {
  std::vector<std::string> differing;
  for (const SummaryField& field : kSummaryFields)
    if (!SameNumber(field.Get(a), field.Get(b))) differing.emplace_back(field.name);
  if (a.findings.size() != b.findings.size()) {
    differing.emplace_back("findings");
    return differing;
  }
  for (std::size_t i = 0; i < a.findings.size(); ++i) {
    const Finding& x = a.findings[i];
    const Finding& y = b.findings[i];
    const std::string prefix = "findings[" + std::to_string(i) + "].";
    if (x.check != y.check) differing.push_back(prefix + "check");
    if (x.channel != y.channel) differing.push_back(prefix + "channel");
    if (x.severity != y.severity) differing.push_back(prefix + "severity");
    if (x.detail != y.detail) differing.push_back(prefix + "detail");
  }
  return differing;
}

}  // namespace napkin::engine
