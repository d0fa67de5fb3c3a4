// The --sort and --limit values of `napkin query` (app/query.h).
#include <gtest/gtest.h>

#include "app/query.h"
#include "common/error.h"

namespace napkin::app {
namespace {

TEST(QueryFilters, SortKeysNameAFieldAndADirection) {
  const std::vector<db::QueryField> fields = db::QueryFields(db::QueryKind::kRotation);
  const db::SortKey plain = ParseSortKey("bric", fields);
  EXPECT_EQ(plain.field, "bric");
  EXPECT_FALSE(plain.descending);
  EXPECT_TRUE(ParseSortKey("max_rotation_deg:desc", fields).descending);
  EXPECT_TRUE(ParseSortKey("max_rotation_deg:DESC", fields).descending);
  EXPECT_FALSE(ParseSortKey("test_id:asc", fields).descending);
  EXPECT_THROW(ParseSortKey("hic15", fields), UsageError) << "not a rotation field";
  EXPECT_THROW(ParseSortKey("bric:", fields), UsageError);
  EXPECT_THROW(ParseSortKey("bric:up", fields), UsageError);
  EXPECT_THROW(ParseSortKey("", fields), UsageError);
}

TEST(QueryFilters, LimitsAreWholeNumbersFromZero) {
  EXPECT_EQ(ParseRowLimit("0"), 0);
  EXPECT_EQ(ParseRowLimit("10"), 10);
  for (const char* bad : {"-1", "", "1.5", "ten", "10 ", "99999999999999999999"})
    EXPECT_THROW(ParseRowLimit(bad), UsageError) << bad;
}

}  // namespace
}  // namespace napkin::app
