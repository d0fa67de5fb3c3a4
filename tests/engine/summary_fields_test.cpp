// The summary-field table: every field of TestSummary once, and the equality
// that tests, merge checks and `napkin_catalogue_io verify` use.
#include "engine/summary_fields.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <limits>

namespace napkin::engine {
namespace {

using ::testing::ElementsAre;
using ::testing::IsEmpty;

// A summary whose fields all hold different values (1, 2, 3, ... in table
// order) and two findings.
TestSummary NumberedSummary() {
  TestSummary summary;
  double value = 1.0;
  for (const SummaryField& field : SummaryFields()) field.Set(summary, value++);
  summary.findings = {{"saturation", "cg_x", Severity::kWarning, "Clipped."},
                      {"residual", std::nullopt, Severity::kError, "Large."}};
  return summary;
}

TEST(SummaryFields, NamesAreUniqueAndEveryGroupIsUsed) {
  std::vector<std::string> names;
  for (const SummaryField& field : SummaryFields()) {
    EXPECT_EQ(std::count(names.begin(), names.end(), field.name), 0) << field.name;
    names.emplace_back(field.name);
  }
  for (const SummaryGroup group : {SummaryGroup::kHic, SummaryGroup::kRotation, SummaryGroup::kQuality})
    EXPECT_FALSE(SummaryFieldNames(group).empty());
}

TEST(SummaryFields, EachAccessorReachesItsOwnMember) {
  // Every field set to a distinct value reads back that value: no two
  // accessors share a member.
  const TestSummary summary = NumberedSummary();
  double value = 1.0;
  for (const SummaryField& field : SummaryFields()) EXPECT_EQ(field.Get(summary), value++) << field.name;
  EXPECT_EQ(summary.hic36.t2_s, 6.0);
  EXPECT_EQ(summary.final_roll_pitch_yaw_deg.z(), 25.0);
  EXPECT_EQ(summary.max_residual_mps2, 30.0);
}

TEST(SummaryFields, AChangeInAnyFieldIsNamed) {
  const TestSummary base = NumberedSummary();
  EXPECT_THAT(DifferingSummaryFields(base, base), IsEmpty());
  for (const SummaryField& field : SummaryFields()) {
    TestSummary changed = base;
    field.Set(changed, -1.0);
    EXPECT_THAT(DifferingSummaryFields(base, changed), ElementsAre(field.name));
  }
}

TEST(SummaryFields, NanEqualsNanAndNothingElse) {
  TestSummary a = NumberedSummary();
  TestSummary b = a;
  a.damage = b.damage = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THAT(DifferingSummaryFields(a, b), IsEmpty());
  b.damage = std::numeric_limits<double>::infinity();
  EXPECT_THAT(DifferingSummaryFields(a, b), ElementsAre("damage"));
}

TEST(SummaryFields, FindingsCompareMemberByMember) {
  const TestSummary base = NumberedSummary();
  TestSummary changed = base;
  changed.findings[0].channel = std::nullopt;
  changed.findings[1].severity = Severity::kWarning;
  changed.findings[1].detail = "Small.";
  EXPECT_THAT(DifferingSummaryFields(base, changed),
              ElementsAre("findings[0].channel", "findings[1].severity", "findings[1].detail"));
  changed = base;
  changed.findings[0].check = "bias";
  EXPECT_THAT(DifferingSummaryFields(base, changed), ElementsAre("findings[0].check"));
  changed.findings.pop_back();
  changed.hic.value = 0.0;
  EXPECT_THAT(DifferingSummaryFields(base, changed), ElementsAre("hic", "findings"));
}

// Labels and units are the table's (issue 31 point 2): the HTML report's
// criteria table and the verdict read them from here; these are the words
// they printed before the table carried them.
TEST(SummaryFields, LabelsAndUnitsOfTheReportAndTheVerdict) {
  struct Labels {
    const char* field;
    const char* label;        // FieldLabel: the verdict's
    const char* table_label;  // FieldTableLabel: the report's criteria table
  };
  for (const Labels& expected : {
           Labels{"hic15", "HIC15", "HIC15"},
           Labels{"hic", "HIC", "HIC (no window limit)"},
           Labels{"hic_d", "HIC(d)", "HIC(d)"},
           Labels{"peak_acc_g", "peak acceleration", "peak acceleration (g)"},
           Labels{"a3ms_g", "a3ms", "a3ms (g)"},
           Labels{"peak_alpha_radps2", "peak angular acceleration", "peak angular acceleration (rad/s²)"},
           Labels{"bric", "BrIC", "BrIC"},
           Labels{"hic15_p_ais3", "P(AIS 3+ | HIC15)", "P(AIS 3+) from HIC15 (NCAP)"},
           Labels{"hic36_p_ais4", "P(AIS 4+ | HIC36)", "P(AIS 4+) from HIC36 (Prasad–Mertz)"},
           Labels{"bric_p_ais4", "P(AIS 4+ | BrIC)", "P(AIS 4+) from BrIC (Takhounts)"},
       }) {
    const SummaryField* field = FindSummaryField(expected.field);
    ASSERT_NE(field, nullptr) << expected.field;
    EXPECT_EQ(FieldLabel(*field), expected.label);
    EXPECT_EQ(FieldTableLabel(*field), expected.table_label);
  }
  EXPECT_STREQ(FindSummaryField("peak_omega_radps")->unit, "rad/s");
  EXPECT_STREQ(FindSummaryField("damage")->unit, "");
  EXPECT_EQ(FindSummaryField("no_such_field"), nullptr);
}

// Every field has a label; exactly the risks have a curve, reading a field
// that is no risk itself.
TEST(SummaryFields, EveryRiskHasItsCurveAndNothingElseHasOne) {
  std::vector<std::string> risks;
  for (const SummaryField& field : SummaryFields()) {
    EXPECT_FALSE(FieldLabel(field).empty()) << field.name;
    EXPECT_EQ(field.curve != nullptr, field.group == SummaryGroup::kRisk) << field.name;
    if (field.curve == nullptr) continue;
    risks.emplace_back(field.name);
    const SummaryField* criterion = FindSummaryField(field.curve->criterion);
    ASSERT_NE(criterion, nullptr) << field.name;
    EXPECT_EQ(criterion->curve, nullptr) << field.name;
  }
  std::vector<std::string> listed;
  for (const SummaryField* field : RiskFields()) listed.emplace_back(field->name);
  EXPECT_EQ(listed, risks);
  EXPECT_THAT(listed, ElementsAre("hic15_p_ais3", "hic36_p_ais4", "bric_p_ais3", "bric_p_ais4"));
}

}  // namespace
}  // namespace napkin::engine
