// Every query kind of the one table (db/query_kinds.h) through the service, against the command
// line on the same catalogue (issue 43 point 1: the service routed its own list of kinds, without
// correlation and limits, and answered another kind "no route"): the same bytes for every kind,
// and for an unknown one the same sentence (python/tests/test_query_kinds_everywhere.py adds the
// Python module).
#include <gtest/gtest.h>

#include <cctype>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>
#include <vector>

#include "db/query_kinds.h"
#include "formats/csv.h"
#include "tests/cli/cli_test_util.h"
#include "tests/serve/serve_test_util.h"
#include "tests/support/test_support.h"

namespace napkin::test_support {
namespace {

using Json = nlohmann::json;

// A catalogue where every kind has rows: a padding series processed, one test with a constant
// offset on a channel (a bias finding: quality), the ratings of a variant (correlation).
class ServeQueryKinds : public ServedCatalogueSuite<ServeQueryKinds> {
 protected:
  static void SetUpTestSuite() {
    ASSERT_EQ(Napkin({"synth", "--scenario", "padding-series", "--count", "2"}).exit_code, 0);
    synth::SyntheticTest offset = SynthNapTest(43);
    offset.signals.samples.col(offset.signals.FindSlot("cg_z")).array() += 30.0;
    formats::WriteSignalsCsv(offset.signals, dir() / "offset.csv");
    const CommandResult import =
        Napkin({"import", "--array", "denton-3222", "--series", "offsets", (dir() / "offset.csv").string()});
    ASSERT_EQ(import.exit_code, 0) << import.err;
    const CommandResult run = Napkin({"run"});
    ASSERT_EQ(run.exit_code, 0) << run.err;
    const CommandResult correlate = Napkin(
        {"correlate", "--series", "padding-series", "--variant", "foam-a", "--channel", "acc_resultant_g"});
    ASSERT_EQ(correlate.exit_code, 0) << correlate.err;
    Serve({});
  }
};

// `text` with every byte but letters, digits and "-._~" percent-encoded (a path segment).
std::string PercentEncoded(const std::string& text) {
  std::string encoded;
  for (const char c : text) {
    if (std::isalnum(static_cast<unsigned char>(c)) ||
        std::string_view("-._~").find(c) != std::string_view::npos) {
      encoded += c;
    } else {
      char hex[4];
      std::snprintf(hex, sizeof hex, "%%%02X", static_cast<unsigned char>(c));
      encoded += hex;
    }
  }
  return encoded;
}

// Every kind of the query table (db/query_kinds.h) is answered as the command line answers it
// (issue 43 point 1: the service's own list of kinds lacked correlation and limits).
TEST_F(ServeQueryKinds, EveryQueryKindIsTheCommandLinesByteForByte) {
  for (const db::QueryKindSpec& kind : db::QueryKinds()) {
    std::vector<std::string> args = {"query", kind.name, "--format", "json"};
    std::string target = "/api/v1/query/" + kind.name;
    if (kind.takes_limits) {
      args.insert(args.end(), {"--limits", "fmvss208"});
      target += "?limits=fmvss208";
    }
    const CommandResult cli = Napkin(args);
    ASSERT_EQ(cli.exit_code, 0) << cli.err;
    ASSERT_GT(Json::parse(cli.out).size(), 0u) << "a kind with no rows tests little: " << kind.name;
    const httplib::Result result = Get(target);
    ASSERT_TRUE(result);
    EXPECT_EQ(result->status, 200) << kind.name << ": " << result->body.substr(0, 300);
    EXPECT_EQ(result->body, cli.out) << kind.name;
  }
  // A kind that takes limits needs them, in the command line's sentence; the service reads no file.
  const httplib::Result no_limits = Get("/api/v1/query/limits");
  EXPECT_EQ(no_limits->status, 400);
  // The option named as the service spells it (issue 43 point 8).
  std::string needs = CliSentence(Napkin({"query", "limits"}));
  ASSERT_NE(needs.find("--limits NAME"), std::string::npos) << needs;
  EXPECT_EQ(ErrorOf(no_limits), needs.replace(needs.find("--limits NAME"), 13, "parameter 'limits'"));
  const httplib::Result hic_limits = Get("/api/v1/query/hic?limits=fmvss208");
  EXPECT_EQ(hic_limits->status, 400);
  std::string applies = CliSentence(Napkin({"query", "hic", "--limits", "fmvss208"}));
  ASSERT_EQ(applies.rfind("--limits ", 0), 0u) << applies;
  EXPECT_EQ(ErrorOf(hic_limits), applies.replace(0, 8, "parameter 'limits'"));
  const fs::path file = SourceDir() / "config" / "limits" / "fmvss208.json";
  const httplib::Result from_file =
      Get(httplib::append_query_params("/api/v1/query/limits", {{"limits", file.string()}}));
  EXPECT_EQ(from_file->status, 400);
  EXPECT_NE(ErrorOf(from_file).find("parameter 'limits' must be a limits preset"), std::string::npos)
      << from_file->body;
}

// An unknown kind is an unknown resource (404), refused in the sentence of `napkin query` (and of
// napkin.Catalogue.query, python/tests): the one the query table gives.
TEST_F(ServeQueryKinds, AnUnknownKindIsRefusedWithTheCommandLinesSentence) {
  for (const std::string& kind : {std::string("everything"), std::string("hics"), std::string("HIC"),
                                  std::string("hic\n"), std::string("limits ")}) {
    const CommandResult cli = Napkin({"query", kind, "--format", "json"});
    EXPECT_EQ(cli.exit_code, 2) << cli.err;
    EXPECT_EQ(CliSentence(cli), db::UnknownQueryKindSentence(kind));
    const httplib::Result result = Get("/api/v1/query/" + PercentEncoded(kind));
    ASSERT_TRUE(result);
    EXPECT_EQ(result->status, 404) << result->body;
    EXPECT_EQ(ErrorOf(result), CliSentence(cli)) << kind;
  }
  EXPECT_EQ(
      ErrorOf(Get("/api/v1/query/everything")),
      "the query kind must be tests, hic, rotation, criteria, risk, quality, conditioning, correlation or "
      "limits; it is 'everything'.");
}

}  // namespace
}  // namespace napkin::test_support
