// `napkin serve`'s read-only HTTP API end to end (docs/serve.md "HTTP API"):
// the built napkin binary serves a catalogue of synthetic tests processed by
// `napkin run` on a free loopback port; every answer is checked against the
// command line's output for the same request, byte for byte.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "app/export.h"
#include "formats/zip_archive.h"
#include "tests/serve/serve_test_util.h"
#include "tests/support/test_support.h"
#include "tests/support/zip_writer.h"

namespace napkin::test_support {
namespace {

using Json = nlohmann::json;

// One catalogue and one service for the suite: six tests of series padding-series
// (production, foam-a, foam-b; two each), processed.
class ServeApi : public ServedCatalogueSuite<ServeApi> {
 protected:
  static void SetUpTestSuite() {
    const CommandResult synth = Napkin({"synth", "--scenario", "padding-series", "--count", "2"});
    ASSERT_EQ(synth.exit_code, 0) << synth.err;
    const CommandResult run = Napkin({"run"});
    ASSERT_EQ(run.exit_code, 0) << run.err;
    Serve({"--threads", "4"});
  }
};

TEST_F(ServeApi, HealthzAnswersOk) {
  const httplib::Result result = Get("/healthz");
  ASSERT_TRUE(result);
  EXPECT_EQ(result->status, 200);
  EXPECT_EQ(Json::parse(result->body).at("status"), "ok");
}

TEST_F(ServeApi, QueryJsonIsTheCommandLinesByteForByte) {
  struct Case {
    std::string kind;
    std::vector<std::pair<std::string, std::string>> params;  // name, value (unencoded)
  };
  const std::vector<Case> cases = {
      {"hic", {}},
      {"hic", {{"where", "hic15>0 and variant=foam-a"}, {"sort", "hic15:desc"}}},
      {"hic", {{"sort", "hic15"}, {"limit", "3"}}},
      {"rotation", {{"where", "variant!=production"}}},
      {"criteria", {{"sort", "test_id:desc"}, {"limit", "2"}}},
      {"risk", {{"where", "series=padding-series"}, {"where", "variant=foam-b"}}},
  };
  for (const Case& c : cases) {
    std::vector<std::string> args = {"query", c.kind, "--format", "json"};
    httplib::Params params;
    for (const auto& [name, value] : c.params) {
      args.push_back("--" + name);
      args.push_back(value);
      params.emplace(name, value);
    }
    const CommandResult cli = Napkin(args);
    ASSERT_EQ(cli.exit_code, 0) << cli.err;
    ASSERT_GT(Json::parse(cli.out).size(), 0u) << "a case with no rows tests little: " << c.kind;
    const httplib::Result result = Get(httplib::append_query_params("/api/v1/query/" + c.kind, params));
    ASSERT_TRUE(result);
    EXPECT_EQ(result->status, 200) << result->body;
    EXPECT_EQ(result->get_header_value("Content-Type"), "application/json");
    EXPECT_EQ(result->body, cli.out) << c.kind;
  }
}

TEST_F(ServeApi, TestsListIsQueryTests) {
  const CommandResult cli = Napkin({"query", "tests", "--format", "json"});
  ASSERT_EQ(cli.exit_code, 0) << cli.err;
  const httplib::Result result = Get("/api/v1/tests");
  ASSERT_TRUE(result);
  EXPECT_EQ(result->status, 200);
  EXPECT_EQ(result->body, cli.out);
  EXPECT_EQ(Json::parse(result->body).size(), 6u);
}

// The command line's sentence, naming the option as the service spells it: "parameter 'where'",
// never "--where" (issue 43 point 8).
TEST_F(ServeApi, BadWhereSortOrLimitIsA400WithTheCommandLinesSentenceNamingTheParameter) {
  const std::vector<std::pair<std::string, std::string>> bad = {
      {"where", "hic15>>3"}, {"where", "nosuchfield=1"}, {"where", "((("},
      {"sort", "hic16"},     {"sort", "hic15:up"},       {"limit", "-1"}};
  for (const auto& [parameter, value] : bad) {
    const CommandResult cli = Napkin({"query", "hic", "--" + parameter, value, "--format", "json"});
    ASSERT_EQ(cli.exit_code, 2) << parameter << "=" << value;
    const httplib::Result result =
        Get(httplib::append_query_params("/api/v1/query/hic", {{parameter, value}}));
    ASSERT_TRUE(result);
    EXPECT_EQ(result->status, 400) << parameter << "=" << value;
    std::string expected = CliSentence(cli);
    const std::string option = "--" + parameter;
    ASSERT_EQ(expected.rfind(option + " ", 0), 0u) << expected;
    expected.replace(0, option.size(), "parameter '" + parameter + "'");
    EXPECT_EQ(ErrorOf(result), expected) << parameter << "=" << value;
    EXPECT_EQ(ErrorOf(result).find("--"), std::string::npos) << ErrorOf(result);
  }
  // A misspelt parameter: 400 too.
  const httplib::Result misspelt = Get("/api/v1/query/hic?whre=hic15>0");
  EXPECT_EQ(misspelt->status, 400);
  EXPECT_NE(ErrorOf(misspelt).find("unknown parameter 'whre'"), std::string::npos) << misspelt->body;
}

TEST_F(ServeApi, DeepWhereIsRefusedAndTheServiceGoesOn) {
  // 10,000 nested parentheses (within the URI limit: encoded, 3 bytes each, would not be).
  const std::string deep = std::string(2500, '(') + "hic15>0" + std::string(2500, ')');
  const httplib::Result result = Get("/api/v1/query/hic?where=" + deep);
  ASSERT_TRUE(result);
  EXPECT_GE(result->status, 400);
  EXPECT_LT(result->status, 500);
  EXPECT_TRUE(Json::parse(result->body).contains("error")) << result->body;
  const httplib::Result long_uri = Get("/api/v1/query/hic?where=" + std::string(10000, '('));
  ASSERT_TRUE(long_uri);
  EXPECT_EQ(long_uri->status, 414);
  EXPECT_EQ(Get("/healthz")->status, 200);
}

TEST_F(ServeApi, CompareIsTheCommandLinesByteForByte) {
  const CommandResult cli =
      Napkin({"compare", "--series", "padding-series", "--baseline", "production", "--format", "json"});
  ASSERT_EQ(cli.exit_code, 0) << cli.err;
  const httplib::Result result = Get("/api/v1/compare?series=padding-series&baseline=production");
  ASSERT_TRUE(result);
  EXPECT_EQ(result->status, 200) << result->body;
  EXPECT_EQ(result->body, cli.out);
  const httplib::Result no_series = Get("/api/v1/compare");
  EXPECT_EQ(no_series->status, 400);
  const CommandResult unknown_cli = Napkin({"compare", "--series", "nope", "--format", "json"});
  const httplib::Result unknown = Get("/api/v1/compare?series=nope");
  EXPECT_EQ(ErrorOf(unknown), CliSentence(unknown_cli));
}

// Every option `napkin compare` takes, and one parser's sentences (spelled as the service names them).
TEST_F(ServeApi, CompareTakesEveryOptionOfTheCommandLine) {
  for (const auto& [cli_options, query] : std::vector<std::pair<std::vector<std::string>, std::string>>{
           {{"--scale", "linear", "--equivalence", "5"}, "&scale=linear&equivalence=5"},
           {{"--limits", "fmvss208", "--metrics", "hic15,bric", "--metrics", "a3ms_g"},
            "&limits=fmvss208&metrics=hic15,bric&metrics=a3ms_g"},
           {{"--limits", "euro-ncap-aop-v9.3-frontal-head-hiii50m", "--config", "default", "--baseline",
             "foam-b"},
            "&limits=euro-ncap-aop-v9.3-frontal-head-hiii50m&config=default&baseline=foam-b"}}) {
    std::vector<std::string> args = {"compare", "--series", "padding-series", "--format", "json"};
    args.insert(args.end(), cli_options.begin(), cli_options.end());
    const CommandResult cli = Napkin(args);
    ASSERT_EQ(cli.exit_code, 0) << cli.err;
    const httplib::Result result = Get("/api/v1/compare?series=padding-series" + query);
    ASSERT_TRUE(result);
    EXPECT_EQ(result->status, 200) << result->body;
    EXPECT_EQ(result->body, cli.out) << query;
  }
  const CommandResult by_cli = Napkin({"compare", "--series", "padding-series", "--by", "colour"});
  EXPECT_EQ(CliSentence(by_cli), "--by must be variant or config; it is 'colour'.");
  EXPECT_EQ(ErrorOf(Get("/api/v1/compare?series=padding-series&by=colour")),
            "parameter 'by' must be variant or config; it is 'colour'.");
  EXPECT_EQ(
      ErrorOf(Get("/api/v1/compare?series=padding-series&config=a&config=b")),
      "by=variant compares the results of one config; give parameter 'config' once (or use by=config).");
  const httplib::Result both = Get(
      "/api/v1/compare?series=padding-series&limits=fmvss208&limits=euro-ncap-aop-v9.3-frontal-head-hiii50m");
  EXPECT_EQ(both->status, 400);
  EXPECT_EQ(ErrorOf(both).rfind("parameter 'limits': FMVSS 208 and Euro NCAP", 0), 0u) << both->body;
}

TEST_F(ServeApi, TestSummaryHoldsTheTestsQueryRows) {
  const std::string id = "padding-series-foam-a-01";
  const httplib::Result result = Get("/api/v1/tests/" + id);
  ASSERT_TRUE(result);
  ASSERT_EQ(result->status, 200) << result->body;
  const Json summary = Json::parse(result->body);
  EXPECT_EQ(summary.at("test_id"), id);
  for (const std::string& kind : std::vector<std::string>{"tests", "hic", "rotation", "criteria", "risk"}) {
    const CommandResult cli = Napkin({"query", kind, "--where", "test_id=" + id, "--format", "json"});
    ASSERT_EQ(cli.exit_code, 0) << cli.err;
    EXPECT_EQ(summary.at(kind), Json::parse(cli.out).at(0)) << kind;
  }
  EXPECT_TRUE(summary.at("quality").is_array());
}

TEST_F(ServeApi, UnknownTestAndPathLikeIdsAre404sNamingTheId) {
  const httplib::Result unknown = Get("/api/v1/tests/nope");
  ASSERT_TRUE(unknown);
  EXPECT_EQ(unknown->status, 404);
  EXPECT_EQ(ErrorOf(unknown), "test 'nope' is not in catalogue '" + db().string() + "'.");
  // Encoded slashes stay part of the id: looked up in the catalogue, never a file.
  const httplib::Result traversal = Get("/api/v1/tests/..%2F..%2Fetc%2Fpasswd");
  ASSERT_TRUE(traversal);
  EXPECT_EQ(traversal->status, 404);
  EXPECT_EQ(ErrorOf(traversal), "test '../../etc/passwd' is not in catalogue '" + db().string() + "'.");
  const httplib::Result channels = Get("/api/v1/tests/..%2F..%2Fetc%2Fpasswd/channels");
  EXPECT_EQ(channels->status, 404);
  EXPECT_EQ(channels->body.find("root:"), std::string::npos);
  const httplib::Result route = Get("/etc/passwd");
  EXPECT_EQ(route->status, 404);
  EXPECT_NE(ErrorOf(route).find("no route GET /etc/passwd"), std::string::npos);
}

// Each parameter is split at its first '=' only: the README's own filters hold one (issue 42, point
// 8: httplib split at the last, so where=hic15>=0 became where=0 and answered 400).
TEST_F(ServeApi, ParametersAreSplitAtTheirFirstEquals) {
  for (const std::string& where : {std::string("hic15>=0"), std::string("variant=foam-a"),
                                   std::string("series=padding-series and hic15>=0")}) {
    const CommandResult cli = Napkin({"query", "hic", "--where", where, "--format", "json"});
    ASSERT_EQ(cli.exit_code, 0) << cli.err;
    ASSERT_GT(Json::parse(cli.out).size(), 0u) << where;
    std::string target =
        "/api/v1/query/hic?where=" + where;  // '=' and '>' unencoded, as a browser sends them
    for (std::size_t at = target.find(' '); at != std::string::npos; at = target.find(' '))
      target.replace(at, 1, "%20");
    const httplib::Result result = Get(target);
    ASSERT_TRUE(result);
    EXPECT_EQ(result->status, 200) << where << ": " << result->body;
    EXPECT_EQ(result->body, cli.out) << where;
  }
  // The same value percent-encoded is the same request.
  EXPECT_EQ(Get("/api/v1/query/hic?where=variant%3Dfoam-a")->body,
            Get("/api/v1/query/hic?where=variant=foam-a")->body);
}

// Repeated where parameters count as the command line's repeated --where: the same limit on the
// comparisons (issue 42, point 10: httplib dropped a parameter repeated with the same value, so 501
// comparisons answered 200 where the command line refuses them).
TEST_F(ServeApi, RepeatedWhereParametersHaveTheCommandLinesLimits) {
  std::vector<std::string> args = {"query", "hic", "--format", "json"};
  std::string target = "/api/v1/query/hic?";
  for (int i = 0; i < 501; ++i) {
    args.insert(args.end(), {"--where", "hic15>0"});
    target += (i ? "&" : "") + std::string("where=hic15>0");
  }
  const CommandResult cli = Napkin(args);
  ASSERT_EQ(cli.exit_code, 2) << cli.err;
  const httplib::Result result = Get(target);
  ASSERT_TRUE(result);
  EXPECT_EQ(result->status, 400) << result->body.substr(0, 300);
  EXPECT_EQ(ErrorOf(result), CliSentence(cli));
  // Two repeated comparisons are still an answer.
  EXPECT_EQ(Get("/api/v1/query/hic?where=hic15>0&where=hic15>0")->body,
            Napkin({"query", "hic", "--where", "hic15>0", "--where", "hic15>0", "--format", "json"}).out);
}

// An encoded '/' stays inside the test id it is part of (issue 42, point 9: httplib routed the
// decoded path, so /api/v1/tests/ID%2Fchannels answered the channels of test ID).
TEST_F(ServeApi, AnEncodedSlashIsPartOfTheTestId) {
  const std::string id = "padding-series-production-02";
  const httplib::Result result = Get("/api/v1/tests/" + id + "%2Fchannels");
  ASSERT_TRUE(result);
  EXPECT_EQ(result->status, 404) << result->body.substr(0, 300);
  EXPECT_EQ(ErrorOf(result), "test '" + id + "/channels' is not in catalogue '" + db().string() + "'.");
  const httplib::Result nested = Get("/api/v1/tests/" + id + "/channels/more");
  EXPECT_EQ(nested->status, 404);
  EXPECT_NE(ErrorOf(nested).find("no route GET"), std::string::npos) << nested->body;
  EXPECT_EQ(Get("/api/v1/tests/" + id + "/channels")->status, 200);
}

// A Range header is ignored: every answer is the whole resource, never larger (issue 42, point 6:
// 200 ranges gave a 200-part multipart answer, 136 MB from 0.68 MB).
TEST_F(ServeApi, RangesAreIgnoredAndNoAnswerIsLargerThanTheResource) {
  const std::string target = "/api/v1/tests/padding-series-production-02/channels?format=json";
  const httplib::Result whole = Get(target);
  ASSERT_TRUE(whole);
  ASSERT_EQ(whole->status, 200);
  std::string ranges = "bytes=0-";
  for (int i = 1; i < 200; ++i) ranges += ",0-";
  for (const std::string& range : {ranges, std::string("bytes=0-9"), std::string("bytes=5-1,0-")}) {
    const httplib::Result answer = Get(target, {{"Range", range}});
    ASSERT_TRUE(answer);
    EXPECT_LE(answer->body.size(), whole->body.size()) << range.substr(0, 20);
    EXPECT_FALSE(answer->has_header("Content-Range")) << range.substr(0, 20);
    EXPECT_EQ(answer->status, 200) << range.substr(0, 20);
    EXPECT_EQ(answer->body, whole->body) << range.substr(0, 20);
  }
  // A Range that is not even well-formed is ignored as well (RFC 9110 14.2: a server may ignore
  // Range): the whole resource, once.
  std::string bad = "bytes=0-";
  for (int i = 1; i < 200; ++i) bad += ",0-";
  bad += ",9-1";
  const httplib::Result ignored = Get(target, {{"Range", bad}});
  ASSERT_TRUE(ignored);
  EXPECT_EQ(ignored->status, 200);
  EXPECT_EQ(ignored->body, whole->body);
}

// Small protocol points (issue 42, point 11): a decoded NUL in a test id is said whole, not cut; the
// report version of a series without tests is a 400 as its report is; the status names the port
// bound, not the 0 asked for.
TEST_F(ServeApi, ControlCharactersUnknownSeriesAndTheBoundPortAreSaid) {
  const httplib::Result nul = Get("/api/v1/tests/abc%00def");
  ASSERT_TRUE(nul);
  EXPECT_EQ(nul->status, 400);
  EXPECT_EQ(ErrorOf(nul), "test id \"abc\\x00def\" holds a control character, which no test id has.");
  const httplib::Result version = Get("/api/v1/report/version?series=nope");
  ASSERT_TRUE(version);
  EXPECT_EQ(version->status, 400) << version->body;
  EXPECT_EQ(ErrorOf(version), CliSentence(Napkin({"report", "--series", "nope", "--out", "-"})));
  EXPECT_EQ(Get("/api/v1/report/version?series=padding-series")->status, 200);
  const Json status = Json::parse(Get("/api/v1/status")->body);
  EXPECT_EQ(status.at("service").at("listen"), "127.0.0.1:" + std::to_string(serve_->port()));
}

TEST_F(ServeApi, ChannelsCsvIsExportsFileAndJsonHoldsTheSameNumbers) {
  const std::string id = "padding-series-production-02";
  const CommandResult cli = Napkin({"export", "--test", id, "--format", "csv", "--out", "channels.csv"});
  ASSERT_EQ(cli.exit_code, 0) << cli.err;
  const std::string csv = ReadText(dir_->path() / "channels.csv");
  const httplib::Result result = Get("/api/v1/tests/" + id + "/channels?format=csv");
  ASSERT_TRUE(result);
  EXPECT_EQ(result->status, 200);
  EXPECT_EQ(result->get_header_value("Content-Type"), "text/csv");
  EXPECT_EQ(result->body, csv);
  EXPECT_EQ(Get("/api/v1/tests/" + id + "/channels")->body, csv) << "csv is the default";

  const httplib::Result json_result = Get("/api/v1/tests/" + id + "/channels?format=json");
  ASSERT_EQ(json_result->status, 200);
  // Key order matters here: the CSV's column order.
  const nlohmann::ordered_json json = nlohmann::ordered_json::parse(json_result->body);
  EXPECT_EQ(json.at("test_id"), id);
  const nlohmann::ordered_json& channels = json.at("channels");
  // The CSV's header names the JSON's keys in order; its cells are the JSON's numbers to 12 digits.
  const std::string header = csv.substr(0, csv.find('\n'));
  std::string names;
  for (const auto& [name, values] : channels.items()) names += (names.empty() ? "" : ",") + name;
  EXPECT_EQ(names, header);
  const std::string second_line =
      csv.substr(csv.find('\n') + 1, csv.find('\n', csv.find('\n') + 1) - csv.find('\n') - 1);
  std::size_t column = 0;
  std::size_t start = 0;
  for (const auto& [name, values] : channels.items()) {
    const std::size_t end = std::min(second_line.find(',', start), second_line.size());
    const std::string cell = second_line.substr(start, end - start);
    if (!cell.empty()) {
      const double expected = std::stod(cell);
      EXPECT_NEAR(values.at(0).get<double>(), expected, 1e-11 * std::max(1.0, std::abs(expected))) << name;
    }
    start = end + 1;
    ++column;
  }
  EXPECT_GT(column, 2u);
  EXPECT_EQ(Get("/api/v1/tests/" + id + "/channels?format=xml")->status, 400);
  EXPECT_EQ(Get("/api/v1/tests/nope/channels")->status, 404);
}

// Every format of `napkin export` (app/export.h's table): the bytes the command writes, a folder
// format as a zip archive of the folder's files.
TEST_F(ServeApi, ChannelsAnswerEveryExportFormatWithTheCommandsBytes) {
  const std::string id = "padding-series-foam-b-01";
  for (const app::ExportFormat& format : app::ExportFormats()) {
    const std::string name(format.name);
    SCOPED_TRACE(name);
    const fs::path out = dir_->path() / ("export-" + name);
    const CommandResult cli = Napkin({"export", "--test", id, "--format", name, "--out", out.string(),
                                      "--units", "english", "--part", "7", "--numform", "vax"});
    ASSERT_EQ(cli.exit_code, 0) << cli.err;
    const httplib::Result result =
        Get("/api/v1/tests/" + id + "/channels?format=" + name + "&units=english&part=7&numform=vax");
    ASSERT_TRUE(result);
    ASSERT_EQ(result->status, 200) << result->body.substr(0, 300);
    EXPECT_EQ(result->get_header_value("Content-Type"), std::string(format.content_type));
    if (!format.folder) {
      EXPECT_EQ(result->body, ReadText(out));
      continue;
    }
    const fs::path zip = dir_->path() / ("export-" + name + ".zip");
    std::ofstream(zip, std::ios::binary) << result->body;
    formats::ZipArchive archive(zip);
    const std::vector<ZipEntry> files = FolderEntries(out);
    ASSERT_EQ(archive.members().size(), files.size());
    ASSERT_GT(files.size(), 2u);
    for (std::size_t i = 0; i < files.size(); ++i) {
      EXPECT_EQ(archive.members()[i].name, files[i].name);
      EXPECT_EQ(archive.Read(archive.members()[i]), files[i].bytes) << files[i].name;
    }
    EXPECT_EQ(
        Get("/api/v1/tests/" + id + "/channels?format=" + name + "&units=english&part=7&numform=vax")->body,
        result->body)
        << "the same files give the same archive";
  }
  // One parser: the command line's sentences, spelled as the service names its parameters.
  EXPECT_EQ(ErrorOf(Get("/api/v1/tests/" + id + "/channels?format=lsdyna&units=mm")),
            "parameter 'units' must be si or english; it is 'mm'.");
  EXPECT_EQ(ErrorOf(Get("/api/v1/tests/" + id + "/channels?format=lsdyna&part=0")),
            "parameter 'part' must be at least 1; it is 0.");
  EXPECT_EQ(
      ErrorOf(Get("/api/v1/tests/" + id + "/channels?format=isomme&dummy_type=H3&dummy-type=H3")),
      "unknown parameter 'dummy-type' (this route takes format, config, units, part, numform, position, "
      "dummy_type).");
  const CommandResult missing_cli = Napkin({"export", "--test", "nope", "--format", "uds", "--out", "x"});
  EXPECT_EQ(ErrorOf(Get("/api/v1/tests/nope/channels?format=uds")), CliSentence(missing_cli));
}

TEST_F(ServeApi, StatusAndMetricsCountTheCatalogue) {
  const CommandResult cli = Napkin({"status", "--format", "json"});
  ASSERT_EQ(cli.exit_code, 0) << cli.err;
  const Json expected = Json::parse(cli.out);
  const httplib::Result result = Get("/api/v1/status");
  ASSERT_TRUE(result);
  ASSERT_EQ(result->status, 200);
  const Json status = Json::parse(result->body);
  // Field by field, every field of both: one reading (app/status.h), one rendering.
  EXPECT_EQ(status.at("catalogue"), expected);
  EXPECT_EQ(status.at("catalogue").at("done"), 6);
  EXPECT_EQ(status.at("catalogue").at("path"), db().string());
  // The config is chosen as on the command line: a preset the catalogue never ran has every test pending.
  const CommandResult salvage_cli = Napkin({"status", "--config", "salvage", "--format", "json"});
  ASSERT_EQ(salvage_cli.exit_code, 0) << salvage_cli.err;
  const Json salvage = Json::parse(Get("/api/v1/status?config=salvage")->body).at("catalogue");
  EXPECT_EQ(salvage, Json::parse(salvage_cli.out));
  EXPECT_EQ(salvage.at("pending"), 6);
  EXPECT_EQ(salvage.at("config").at("name"), "salvage");
  EXPECT_NE(salvage.at("config").at("hash"), status.at("catalogue").at("config").at("hash"));
  // A file is never read for a request: only a preset's name.
  const httplib::Result file = Get("/api/v1/status?config=" + db().string());
  EXPECT_EQ(file->status, 400);
  EXPECT_EQ(ErrorOf(file).rfind("parameter 'config' must be default or salvage; it is '", 0), 0u)
      << file->body;
  EXPECT_EQ(Get("/api/v1/status?colour=red")->status, 400);

  const httplib::Result metrics = Get("/metrics");
  ASSERT_EQ(metrics->status, 200);
  EXPECT_EQ(metrics->get_header_value("Content-Type"), "text/plain; version=0.0.4");
  EXPECT_NE(metrics->body.find("napkin_catalogue_tests{state=\"done\"} 6\n"), std::string::npos)
      << metrics->body;
  EXPECT_NE(metrics->body.find(
                "# TYPE napkin_http_requests_total counter\nnapkin_http_requests_total{code=\"200\"} "),
            std::string::npos)
      << metrics->body;
}

TEST_F(ServeApi, OversizedRequestsAndManyHeadersAre4xxAndTheServiceGoesOn) {
  httplib::Headers many;
  for (int i = 0; i < 1000; ++i) many.emplace("X-Header-" + std::to_string(i), "1");
  const httplib::Result headers = Get("/api/v1/tests", many);
  ASSERT_TRUE(headers);
  EXPECT_EQ(headers->status, 431);
  // A 1 MiB body: more than a GET route ever reads.
  const httplib::Result body =
      serve_->Client()->Post("/api/v1/tests", std::string(1 << 20, 'x'), "text/plain");
  if (body) {  // the server may close the connection while the body is still being sent
    EXPECT_GE(body->status, 400);
    EXPECT_LT(body->status, 500);
  }
  // Only GET is answered.
  const httplib::Result post = serve_->Client()->Post("/api/v1/tests", "", "text/plain");
  ASSERT_TRUE(post);
  EXPECT_EQ(post->status, 404);
  EXPECT_EQ(Get("/healthz")->status, 200);
}

TEST_F(ServeApi, ReportIsTheCommandLinesPageWithALiveScript) {
  const CommandResult cli = Napkin({"report", "--series", "padding-series", "--out", "-"});
  ASSERT_EQ(cli.exit_code, 0) << cli.err;
  const httplib::Result result = Get("/report?series=padding-series");
  ASSERT_TRUE(result);
  ASSERT_EQ(result->status, 200) << result->body;
  EXPECT_EQ(result->get_header_value("Content-Type"), "text/html; charset=utf-8");
  const httplib::Result version = Get("/api/v1/report/version?series=padding-series");
  ASSERT_EQ(version->status, 200);
  const std::string v = Json::parse(version->body).at("version");
  EXPECT_EQ(v.size(), 16u);
  EXPECT_EQ(Get("/api/v1/report/version?series=padding-series")->body, version->body)
      << "stable while nothing changes";
  // The page is the command line's, with the live note and its script before </body>.
  const std::string script_start = "<div id=\"napkin-live\"";
  std::string page = result->body;
  const std::size_t start = page.find(script_start);
  ASSERT_NE(start, std::string::npos) << page.substr(page.size() - std::min<std::size_t>(page.size(), 800));
  const std::size_t end = page.find("</script>\n", start) + std::string("</script>\n").size();
  const std::string live = page.substr(start, end - start);
  EXPECT_NE(live.find("var version = \"" + v + "\", series = \"padding-series\""), std::string::npos) << live;
  EXPECT_NE(live.find("/api/v1/report/version?series="), std::string::npos);
  page.erase(start, end - start);
  EXPECT_EQ(page, cli.out);
  EXPECT_EQ(page.rfind("</body>"), start);

  const CommandResult unknown_cli = Napkin({"report", "--series", "nope", "--out", "-"});
  const httplib::Result unknown = Get("/report?series=nope");
  EXPECT_EQ(unknown->status, 400);
  EXPECT_EQ(ErrorOf(unknown), CliSentence(unknown_cli));
  EXPECT_EQ(Get("/report")->status, 400);
}

// Bounded load: 8 loopback clients, 40 requests each, every answer the same rows.
TEST_F(ServeApi, ConcurrentClientsAllGetTheSameAnswer) {
  const std::string expected = Get("/api/v1/query/hic?limit=100")->body;
  std::vector<std::thread> clients;
  clients.reserve(8);
  std::atomic<int> good{0};
  for (int c = 0; c < 8; ++c)
    clients.emplace_back([&] {
      const std::unique_ptr<httplib::Client> client = serve_->Client();
      for (int i = 0; i < 40; ++i) {
        const httplib::Result result = client->Get("/api/v1/query/hic?limit=100");
        if (result && result->status == 200 && result->body == expected) ++good;
      }
    });
  for (std::thread& client : clients) client.join();
  EXPECT_EQ(good.load(), 8 * 40);
}

}  // namespace
}  // namespace napkin::test_support
