// The limits of `--where` (docs/formats.md "Query filters",
// db/where_expression.h): an expression within them runs on every query,
// whatever its shape, and selects the rows of the simple expression it is
// equivalent to; beyond them it is refused in one sentence (exit 2), never a
// crash (8,000 nested parentheses overflowed the parser's stack) nor SQLite's
// "parser stack overflow" or "Expression tree is too large" blamed on the
// catalogue with the C++ call quoted (1,001 `or` terms).
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <functional>
#include <random>
#include <set>

#include "app/where_parser.h"
#include "common/error.h"
#include "db/sqlite.h"
#include "formats/csv.h"
#include "tests/cli/cli_test_util.h"
#include "tests/support/test_support.h"

namespace napkin::app {

using namespace napkin::test_support;
namespace {

constexpr db::QueryKind kKinds[] = {db::QueryKind::kTests,    db::QueryKind::kHic,
                                    db::QueryKind::kRotation, db::QueryKind::kCriteria,
                                    db::QueryKind::kQuality,  db::QueryKind::kConditioning};

// "a or b or c" of `terms`, joined by `keyword`.
std::string Joined(const std::vector<std::string>& terms, const std::string& keyword) {
  std::string text;
  for (const std::string& term : terms) text += text.empty() ? term : fmt::format(" {} {}", keyword, term);
  return text;
}

// `test_id = q1 or test_id = q3` nested `levels` parentheses deep, each level
// an `or` inside an `and` (the SQL needs parentheses for each), written
// innermost last (right-nested) or innermost first (left-nested).
std::string RightNested(int levels) {
  std::string text = "test_id = q1 or test_id = q3";
  for (int level = 0; level < levels; ++level)
    text = fmt::format("test_id != zz{} and (test_id = zz or {})", level, text);
  return text;
}
std::string LeftNested(int levels) {
  std::string text = "test_id = q1 or test_id = q3";
  for (int level = 0; level < levels; ++level)
    text = fmt::format("test_id = zz or ({}) and test_id != zz", text);
  return text;
}

// The expensive shape for the SQL: at every level both operands of the
// `and` are as deeply nested as each other, so whichever is written first,
// the other opens its parentheses after `x AND`. Equivalent to
// `test_id = q1 or test_id = q3`.
std::string BothDeep(int levels) {
  if (levels == 0) return "test_id = q1 or test_id = q3";
  std::string chain = "test_id = q1 or test_id = q3";
  for (int level = 1; level < levels; ++level)
    chain = fmt::format("test_id != zz and (test_id = zz or {})", chain);
  return fmt::format("(test_id = zz or {}) and (test_id = zz or {})", BothDeep(levels - 1), chain);
}

std::size_t Comparisons(const std::string& text) {
  std::size_t count = 0;
  for (std::size_t at = text.find("test_id"); at != std::string::npos; at = text.find("test_id", at + 1))
    ++count;
  return count;
}

int Nesting(const std::string& text) {
  int depth = 0, deepest = 0;
  for (const char c : text) deepest = std::max(deepest, depth += c == '(' ? 1 : c == ')' ? -1 : 0);
  return deepest;
}

bool WithinLimits(const std::string& text) {
  return Comparisons(text) <= db::kMaxWhereComparisons && Nesting(text) <= db::kMaxWhereNesting;
}

class WhereLimits : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new TempDir();
    ASSERT_EQ(RunNapkin(dir_->path(), {"init"}).exit_code, 0);
    // q1 and q3 have results (and quality findings, conditioning records), q2 none.
    std::uint64_t seed = 31;
    for (const char* id : {"q1", "q2", "q3"}) {
      formats::WriteSignalsCsv(SynthNapTest(seed++).signals, *dir_ / (std::string(id) + ".csv"));
      const RunResult run = RunNapkin(dir_->path(), {"import", "--array", "denton-3222", "--series", "sled",
                                                     "--variant", "foam", std::string(id) + ".csv"});
      ASSERT_EQ(run.exit_code, 0) << run.err;
    }
    ProcessAndStore(*dir_ / "napkin.db", "q1");
    ProcessAndStore(*dir_ / "napkin.db", "q3");
  }
  static void TearDownTestSuite() {
    delete dir_;
    dir_ = nullptr;
  }

  // The test ids of query `kind` filtered by `where` (each parsed as --where).
  static std::multiset<std::string> Ids(db::Catalogue& catalogue, db::QueryKind kind,
                                        const std::vector<std::string>& where) {
    db::QueryRequest request;
    for (const std::string& text : where)
      request.where.push_back(ParseWhereExpression(text, db::QueryFields(kind)));
    const db::Table table = catalogue.Query(kind, request);
    std::multiset<std::string> ids;
    for (const auto& row : table.rows) ids.insert(std::get<std::string>(row.at(0)));
    return ids;
  }

  // Every query gives for `where` the rows of `test_id = q1 or test_id = q3`.
  static void ExpectRunsEverywhere(const std::vector<std::string>& where, const std::string& shape) {
    db::Catalogue catalogue = OpenForReading(*dir_ / "napkin.db");
    for (const db::QueryKind kind : kKinds) {
      SCOPED_TRACE(shape + ", query " + std::to_string(static_cast<int>(kind)));
      const std::multiset<std::string> expected = Ids(catalogue, kind, {"test_id = q1 or test_id = q3"});
      if (kind != db::QueryKind::kQuality) {  // findings may be none
        EXPECT_FALSE(expected.empty());
      }
      try {
        EXPECT_EQ(Ids(catalogue, kind, where), expected);
      } catch (const std::exception& error) {
        ADD_FAILURE() << error.what();
      }
    }
  }

  static TempDir* dir_;
};
TempDir* WhereLimits::dir_ = nullptr;

TEST_F(WhereLimits, ExpressionsAtTheLimitsRunOnEveryQuery) {
  ASSERT_EQ(Nesting(RightNested(db::kMaxWhereNesting)), db::kMaxWhereNesting);
  ExpectRunsEverywhere({RightNested(db::kMaxWhereNesting)}, "right-nested");
  ExpectRunsEverywhere({LeftNested(db::kMaxWhereNesting)}, "left-nested");
  // Redundant parentheses count too.
  ExpectRunsEverywhere(
      {fmt::format("{}test_id = q1 or test_id = q3{}", std::string(db::kMaxWhereNesting, '('),
                   std::string(db::kMaxWhereNesting, ')'))},
      "redundant parentheses");

  // The most comparisons, joined by `or`, by `and`, and over several --where.
  std::vector<std::string> any = {"test_id = q1", "test_id = q3"};
  while (any.size() < db::kMaxWhereComparisons) any.push_back("test_id = x" + std::to_string(any.size()));
  ExpectRunsEverywhere({Joined(any, "or")}, "or chain");
  std::vector<std::string> all;
  while (all.size() < db::kMaxWhereComparisons - 2)
    all.push_back("test_id != x" + std::to_string(all.size()));
  ExpectRunsEverywhere({Joined(all, "and") + " and (test_id = q1 or test_id = q3)"}, "and chain");
  std::vector<std::string> several(db::kMaxWhereComparisons - 2, "test_id != zz");
  several.push_back("test_id = q1 or test_id = q3");
  ExpectRunsEverywhere(several, "several --where");

  // Both operands deep at every level, as deep and as many as allowed.
  int levels = 1;
  while (WithinLimits(BothDeep(levels + 1))) ++levels;
  ASSERT_GE(levels, 15);
  ExpectRunsEverywhere({BothDeep(levels)}, "both deep, " + std::to_string(levels) + " levels");
  // The same under a chain as deep as the nesting allows.
  const std::string both = BothDeep(levels / 2);
  std::string under = both;
  auto under_chain = [](const std::string& inner) {
    return fmt::format("test_id != zz and (test_id = zz or {})", inner);
  };
  while (WithinLimits(under_chain(under))) under = under_chain(under);
  ExpectRunsEverywhere({under}, "both deep under a chain");
}

TEST_F(WhereLimits, RandomExpressionsWithinTheLimitsRun) {
  // Random trees of and/or over comparisons true for every test, under
  // `(test_id = q1 or test_id = q3) and`: the rows of q1 and q3.
  std::mt19937_64 random(20261126);
  const int most = static_cast<int>(db::kMaxWhereComparisons) - 2 - 4 * db::kMaxWhereNesting;
  for (int round = 0; round < 30; ++round) {
    int comparisons = 0;
    const int budget = std::uniform_int_distribution<int>(2, most)(random);
    std::function<std::string(int)> make = [&](int depth) -> std::string {
      const int width = std::uniform_int_distribution<int>(2, 4)(random);
      std::vector<std::string> operands;
      for (int i = 0; i < width; ++i) {
        if (depth < db::kMaxWhereNesting && comparisons + 8 < budget &&
            std::uniform_int_distribution<int>(0, 3)(random) > 0) {
          operands.push_back("(" + make(depth + 1) + ")");
        } else {
          ++comparisons;
          operands.push_back("test_id != zz");
        }
      }
      return Joined(operands, std::uniform_int_distribution<int>(0, 1)(random) == 0 ? "and" : "or");
    };
    const std::string text = "(test_id = q1 or test_id = q3) and (" + make(1) + ")";
    ASSERT_TRUE(WithinLimits(text)) << Comparisons(text) << " comparisons, nesting " << Nesting(text);
    ExpectRunsEverywhere({text}, "random, " + std::to_string(Comparisons(text)) + " comparisons, nesting " +
                                     std::to_string(Nesting(text)));
  }
}

// The one-line message of `text` as --where of query hic ("" when it parses).
std::string HicWhereError(const std::string& text) {
  try {
    ParseWhereExpression(text, db::QueryFields(db::QueryKind::kHic));
  } catch (const UsageError& error) {
    return error.what();
  }
  return "";
}

TEST(WhereLimitsParser, DeeperOrLongerExpressionsAreRefusedInOneSentence) {
  const int limit = db::kMaxWhereNesting;
  EXPECT_EQ(HicWhereError(std::string(limit, '(') + "hic15 > 1" + std::string(limit, ')')), "");
  const std::string deeper =
      HicWhereError(std::string(limit + 1, '(') + "hic15 > 1" + std::string(limit + 1, ')'));
  EXPECT_NE(deeper.find("the '(' at column " + std::to_string(limit + 1) + " nests parentheses deeper than " +
                        std::to_string(limit) + " levels"),
            std::string::npos)
      << deeper;

  std::vector<std::string> terms(db::kMaxWhereComparisons, "hic15 > 1");
  EXPECT_EQ(HicWhereError(Joined(terms, "or")), "");
  terms.push_back("hic15 > 1");
  const std::string longer = HicWhereError(Joined(terms, "or"));
  EXPECT_NE(longer.find("is one more than the " + std::to_string(db::kMaxWhereComparisons) +
                        " an expression may hold"),
            std::string::npos)
      << longer;
  for (const std::string& message : {deeper, longer}) {
    EXPECT_EQ(message.find('\n'), std::string::npos);
    EXPECT_LT(message.size(), 600u) << message;  // the expression is quoted cut to 60 bytes
  }
}

TEST_F(WhereLimits, SeveralExpressionsTogetherAreLimitedToo) {
  db::Catalogue catalogue = OpenForReading(*dir_ / "napkin.db");
  db::QueryRequest request;
  const std::vector<std::string> half(db::kMaxWhereComparisons / 2 + 1, "test_id != zz");
  for (int i = 0; i < 2; ++i)
    request.where.push_back(
        ParseWhereExpression(Joined(half, "and"), db::QueryFields(db::QueryKind::kTests)));
  try {
    catalogue.Query(db::QueryKind::kTests, request);
    ADD_FAILURE() << "no UsageError";
  } catch (const UsageError& error) {
    EXPECT_STREQ(error.what(), ("the --where expressions hold " + std::to_string(2 * half.size()) +
                                " comparisons together; a query takes at most " +
                                std::to_string(db::kMaxWhereComparisons) + ".")
                                   .c_str());
  }
}

// ---------------------------------------------------------------- the binary

TEST_F(WhereLimits, TheBinaryRefusesDeepAndLongExpressionsWithExitTwo) {
  const std::string before = DumpCatalogue(*dir_ / "napkin.db");
  // Crashed with SIGSEGV (the parser recursed 8,000 deep).
  const RunResult deep =
      RunNapkin(dir_->path(),
                {"query", "hic", "--where", std::string(8000, '(') + "hic15 > 1" + std::string(8000, ')')});
  EXPECT_EQ(deep.exit_code, 2) << deep.err.substr(0, 2000);
  ExpectOneSentenceError(deep, {"--where \"((((", "nests parentheses deeper than"});
  EXPECT_LT(deep.err.size(), 600u);

  // Reached SQLite: "catalogue 'napkin.db': SQLite error 'Expression tree is too large ..."
  // with the C++ call `sqlite3_prepare_v3(db_, sql_.data(), ...` quoted, exit 1.
  std::vector<std::string> terms(1001, "hic15 > 1");
  const RunResult longer = RunNapkin(dir_->path(), {"query", "hic", "--where", Joined(terms, "or")});
  EXPECT_EQ(longer.exit_code, 2) << longer.err.substr(0, 2000);
  ExpectOneSentenceError(longer, {"comparison", "500"});
  // and/or nested 30 deep: SQLite's "parser stack overflow".
  const RunResult nested = RunNapkin(dir_->path(), {"query", "tests", "--where", RightNested(30)});
  EXPECT_EQ(nested.exit_code, 0) << nested.err.substr(0, 2000);
  EXPECT_NE(nested.out.find("q1"), std::string::npos) << nested.out;
  for (const RunResult* run : {&deep, &longer, &nested}) {
    EXPECT_EQ(run->err.find("catalogue"), std::string::npos) << run->err.substr(0, 2000);
    EXPECT_EQ(run->err.find("SQLite"), std::string::npos) << run->err.substr(0, 2000);
    EXPECT_EQ(run->err.find("sqlite3_"), std::string::npos) << run->err.substr(0, 2000);
  }
  EXPECT_EQ(DumpCatalogue(*dir_ / "napkin.db"), before);
}

TEST_F(WhereLimits, AMalformedLongExpressionIsQuotedCut) {
  // 120 KB with the error at its end: stderr held all of it (120,263 bytes).
  const std::string text = "hic15 > 1 or variant = \"" + std::string(120'000, 'a') + "\" >";
  const RunResult run = RunNapkin(dir_->path(), {"query", "hic", "--where", text});
  EXPECT_EQ(run.exit_code, 2);
  ExpectOneSentenceError(run, {"--where \"hic15 > 1 or variant = \"aaa", "more bytes)\"",
                               "at column " + std::to_string(text.size()) + ", found '>'"});
  EXPECT_LT(run.err.size(), 600u) << run.err.substr(0, 2000);

  // A long unknown field name is cut too.
  const RunResult field =
      RunNapkin(dir_->path(), {"query", "hic", "--where", std::string(50'000, 'f') + " > 1"});
  EXPECT_EQ(field.exit_code, 2);
  ExpectOneSentenceError(field, {"unknown field 'fff", "more bytes)' at column 1"});
  EXPECT_LT(field.err.size(), 800u) << field.err.substr(0, 2000);

  // So are --sort and --limit, the other query options.
  for (const char* option : {"--sort", "--limit"}) {
    const RunResult run = RunNapkin(dir_->path(), {"query", "hic", option, std::string(50'000, 's')});
    EXPECT_EQ(run.exit_code, 2);
    ExpectOneSentenceError(run, {option, "sss", "more bytes)"});
    EXPECT_LT(run.err.size(), 1000u) << run.err.substr(0, 2000);
  }
}

// ------------------------------------------------------- the wrapper's errors

// Before: "... (1) in sqlite3_prepare_v3(db_, sql_.data(), static_cast<int>(sql_.size()), ...) while ...".
TEST(SqliteErrorText, NamesTheSqliteErrorTheFunctionAndTheSqlButNoSourceCode) {
  db::Connection connection = db::Connection::Open(":memory:");
  try {
    connection.Prepare("SELECT * FROM no_such_table");
    ADD_FAILURE() << "no DatabaseError";
  } catch (const db::DatabaseError& error) {
    const std::string message = error.what();
    EXPECT_EQ(
        message,
        "SQLite error 'no such table: no_such_table' (1) in sqlite3_prepare_v3 while running 'SELECT * FROM "
        "no_such_table'.");
    // The call as written in db/sqlite.cpp is kept for debugging only.
    EXPECT_NE(error.location().find("sqlite3_prepare_v3("), std::string::npos) << error.location();
  }
}

}  // namespace
}  // namespace napkin::app
