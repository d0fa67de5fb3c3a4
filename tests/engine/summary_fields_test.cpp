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

}  // namespace
}  // namespace napkin::engine
