// `napkin serve --inbox` end to end (docs/serve.md "Inbox"): tests written
// into the inbox appear in the API with the numbers `napkin import` and `napkin
// run` give for the same files; inotify and polling; a half-written file is
// not imported early; sidecars; a marker file; the inbox is never changed;
// kill -9 and restart: every test exactly once; SIGTERM while processing.
#include <gtest/gtest.h>
#include <sqlite3.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <sys/un.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <fstream>
#include <functional>
#include <map>
#include <nlohmann/json.hpp>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "formats/array_json.h"
#include "formats/csv.h"
#include "tests/cli/cli_test_util.h"
#include "tests/serve/serve_test_util.h"
#include "tests/support/dts_slice_writer.h"
#include "tests/support/test_support.h"

namespace napkin::test_support {
namespace {

using Json = nlohmann::json;

class ServeInbox : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_EQ(Napkin({"init"}).exit_code, 0);
    fs::create_directories(inbox_);
    WriteText(inbox_ / "napkin.json", R"({"array": "denton-3222"})");
  }

  CommandResult Napkin(std::vector<std::string> args, const fs::path& db = {}) {
    args.insert(args.begin(), {"--db", (db.empty() ? db_ : db).string()});
    return RunProgram(NAPKIN_BINARY, args, dir_.path());
  }
  std::unique_ptr<ServeProcess> Serve(std::vector<std::string> args) {
    args.insert(args.begin(), {"--listen", "127.0.0.1:0", "--inbox", inbox_.string()});
    return std::make_unique<ServeProcess>(dir_.path(), db_, args);
  }
  // A test's CSV, written whole into a file that does not yet exist.
  static void WriteTest(const fs::path& path, std::uint64_t seed) {
    fs::create_directories(path.parent_path());
    formats::WriteSignalsCsv(SynthNapTest(seed).signals, path);
  }
  // GET `target` (JSON) until `done` holds for it, at most `seconds`.
  static Json WaitFor(const ServeProcess& serve, const std::string& target,
                      const std::function<bool(const Json&)>& done, double seconds = 60) {
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
    Json last;
    while (std::chrono::steady_clock::now() < deadline) {
      const httplib::Result result = serve.Client()->Get(target.c_str());
      if (result && result->status == 200) {
        last = Json::parse(result->body);
        if (done(last)) return last;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
    ADD_FAILURE() << "timed out waiting on " << target << "; last answer " << last.dump() << "\nlog:\n"
                  << serve.log();
    return last;
  }
  static std::function<bool(const Json&)> Rows(std::size_t n) {
    return [n](const Json& json) { return json.size() == n; };
  }
  // Every file of the inbox with its bytes: the inbox is only read.
  std::map<std::string, std::string> InboxContents() const {
    std::map<std::string, std::string> files;
    for (const auto& entry : fs::recursive_directory_iterator(inbox_))
      files[entry.path().string()] = entry.is_regular_file() ? ReadText(entry.path()) : "<folder>";
    return files;
  }
  // `napkin import` and `napkin run` of the same files into another catalogue: its `query hic` JSON.
  std::string CliQueryHic(const std::vector<std::pair<std::string, fs::path>>& variant_and_file) {
    const fs::path cli_db = dir_ / "cli.db";
    for (const auto& [variant, file] : variant_and_file) {
      const CommandResult import = Napkin(
          {"import", "--array", "denton-3222", "--series", "sled", "--variant", variant, file.string()},
          cli_db);
      EXPECT_EQ(import.exit_code, 0) << import.err;
    }
    EXPECT_EQ(Napkin({"run"}, cli_db).exit_code, 0);
    return Napkin({"query", "hic", "--format", "json"}, cli_db).out;
  }

  TempDir dir_;
  fs::path db_ = dir_ / "lab.db";
  fs::path inbox_ = dir_ / "inbox";
};

TEST_F(ServeInbox, InotifyImportsAndProcessesWithTheCommandLinesNumbers) {
  const auto serve = Serve({"--settle", "1"});
  ASSERT_GT(serve->port(), 0) << serve->log();
  EXPECT_NE(serve->log().find("(inotify;"), std::string::npos) << serve->log();
  // A series without tests has no report, so no version to follow (as /report answers for it).
  EXPECT_EQ(serve->Client()->Get("/api/v1/report/version?series=sled")->status, 400);
  WriteTest(inbox_ / "sled" / "foam-a" / "t01.csv", 101);
  WriteTest(inbox_ / "sled" / "production" / "t02.csv", 102);
  const auto inbox_before = InboxContents();
  const auto start = std::chrono::steady_clock::now();
  WaitFor(*serve, "/api/v1/query/hic", Rows(2));
  // inotify wakes the watcher: well before its 30 s look-again interval.
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(20));
  const httplib::Result served = serve->Client()->Get("/api/v1/query/hic");
  EXPECT_EQ(served->body, CliQueryHic({{"foam-a", inbox_ / "sled" / "foam-a" / "t01.csv"},
                                       {"production", inbox_ / "sled" / "production" / "t02.csv"}}));
  const Json status = Json::parse(serve->Client()->Get("/api/v1/status")->body);
  EXPECT_EQ(status.at("inbox").at("watch"), "inotify");
  EXPECT_EQ(status.at("inbox").at("imported"), 2);
  EXPECT_EQ(status.at("inbox").at("processed"), 2);
  const std::string metrics = serve->Client()->Get("/metrics")->body;
  EXPECT_NE(metrics.find("napkin_inbox_imported_total 2\n"), std::string::npos) << metrics;
  EXPECT_NE(metrics.find("napkin_inbox_processed_total 2\n"), std::string::npos) << metrics;
  EXPECT_EQ(InboxContents(), inbox_before) << "the inbox was changed";
  // The live report has a version to follow now.
  const httplib::Result version = serve->Client()->Get("/api/v1/report/version?series=sled");
  ASSERT_TRUE(version);
  EXPECT_EQ(version->status, 200);
  EXPECT_TRUE(Json::parse(version->body).at("version").is_string());
  EXPECT_EQ(serve->Client()->Get("/report?series=sled")->status, 200);
  EXPECT_EQ(serve->Stop(), 0) << serve->log();
}

// A DTS SLICEWare CSV export dropped into the inbox with no sidecar naming its array (issue 46):
// its channel codes define it (6aw-cg), its Test ID names the test, and the numbers are those of
// `napkin import` and `napkin run` on the same file.
TEST_F(ServeInbox, DtsSliceExportIsImportedUnderItsTestIdWithTheArrayItsCodesDefine) {
  fs::remove(inbox_ / "napkin.json");
  synth::RandomMotionOptions motion;
  motion.seed = 4646;
  motion.duration_s = 0.03;
  motion.synth.rate_hz = 20000.0;
  const synth::SyntheticTest test = synth::SynthRandomMotion(formats::LoadArray("6aw-cg"), motion);
  const fs::path file = inbox_ / "drop" / "headform" / "fh1_UNFILTERED.csv";
  fs::create_directories(file.parent_path());
  WriteDtsExport(SixDxExport(test.signals, test.array), file);
  const auto serve = Serve({"--settle", "0.5"});
  ASSERT_GT(serve->port(), 0) << serve->log();
  const Json rows = WaitFor(*serve, "/api/v1/query/hic", Rows(1));
  ASSERT_EQ(rows.size(), 1u);
  EXPECT_EQ(rows[0].at("test_id"), "DTS-1");
  const fs::path cli_db = dir_ / "cli.db";
  ASSERT_EQ(Napkin({"init"}, cli_db).exit_code, 0);
  const CommandResult import =
      Napkin({"import", "--series", "drop", "--variant", "headform", file.string()}, cli_db);
  ASSERT_EQ(import.exit_code, 0) << import.err;
  ASSERT_EQ(Napkin({"run"}, cli_db).exit_code, 0);
  EXPECT_EQ(serve->Client()->Get("/api/v1/query/hic")->body,
            Napkin({"query", "hic", "--format", "json"}, cli_db).out);
  EXPECT_EQ(serve->Stop(), 0) << serve->log();
}

// The live report in headless Chromium: a test dropped into the inbox after the page was loaded
// appears on it without a reload: the page's script replaces its report in place when the series
// changes.
TEST_F(ServeInbox, LiveReportShowsANewTestWithoutAReload) {
  std::string chromium;
  for (const char* path : {"/usr/bin/chromium", "/usr/bin/chromium-headless-shell"})
    if (fs::exists(path)) chromium = path;
  if (chromium.empty()) GTEST_SKIP() << "headless Chromium (Debian: chromium) is not installed";
  const auto serve = Serve({"--settle", "3600"});  // only markers import: the test says when
  ASSERT_GT(serve->port(), 0) << serve->log();
  WriteTest(inbox_ / "sled" / "production" / "early-test.csv", 111);
  WriteText(inbox_ / "sled" / "production" / "early-test.ready", "");
  WaitFor(*serve, "/api/v1/query/hic", Rows(1));
  const auto requests = [&] {
    return Json::parse(serve->Client()->Get("/api/v1/status")->body).at("service").at("requests").get<int>();
  };
  int own = 0;  // this test's status requests since `before`
  const int before = requests();
  // Virtual time: the page's 3 s polls follow each other as fast as the service answers them;
  // 200 of them leave the inbox seconds to import and process the new test.
  const fs::path dom = dir_ / "dom.html";
  const pid_t browser =
      StartProgram("/usr/bin/timeout",
                   {"120", chromium, "--headless", "--no-sandbox", "--disable-gpu", "--no-first-run",
                    "--disable-extensions", "--user-data-dir=" + (dir_ / "profile").string(),
                    "--virtual-time-budget=600000", "--dump-dom",
                    "http://127.0.0.1:" + std::to_string(serve->port()) + "/report?series=sled"},
                   dom, dir_ / "chromium.err", dir_.path());
  // Once the page is loaded and polling (the page and two version requests), the second test arrives.
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (requests() - before - ++own < 3 && std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  ASSERT_LT(std::chrono::steady_clock::now(), deadline) << "the page never polled";
  WriteTest(inbox_ / "sled" / "foam-a" / "newcomer-test.csv", 112);
  WriteText(inbox_ / "sled" / "foam-a" / "newcomer-test.ready", "");
  EXPECT_EQ(WaitProgram(browser), 0) << ReadText(dir_ / "chromium.err");
  const std::string page = ReadText(dom);
  // The page was loaded (and polled twice) before newcomer-test existed.
  EXPECT_NE(page.find("early-test"), std::string::npos);
  EXPECT_NE(page.find("newcomer-test"), std::string::npos) << "the open page did not show the new test";
  // It was updated in place: a reload would have started the count again.
  EXPECT_NE(page.find("data-live-updates=\""), std::string::npos) << "the page was reloaded, not updated";
  EXPECT_NE(page.find(">live: updated at "), std::string::npos);  // the note in the corner
  EXPECT_EQ(page.find("class=\"napkin-script-error\""), std::string::npos) << page;
  EXPECT_EQ(serve->Stop(), 0);
}

TEST_F(ServeInbox, PollingFindsTestsAndAHalfWrittenFileWaitsUntilSettled) {
  const auto serve = Serve({"--settle", "3", "--poll", "0.5"});
  ASSERT_GT(serve->port(), 0) << serve->log();
  EXPECT_NE(serve->log().find("(poll, every"), std::string::npos) << serve->log();
  // The first half of the file, then (after less than --settle) the rest.
  const fs::path staged = dir_ / "whole.csv";
  formats::WriteSignalsCsv(SynthNapTest(103).signals, staged);
  const std::string whole = ReadText(staged);
  const fs::path target = inbox_ / "sled" / "foam-b" / "t03.csv";
  fs::create_directories(target.parent_path());
  WriteText(target, whole.substr(0, whole.size() / 2));
  WaitFor(*serve, "/api/v1/status",
          [](const Json& status) { return status.at("inbox").at("settling").size() == 1; });
  std::this_thread::sleep_for(std::chrono::milliseconds(1500));
  { std::ofstream(target, std::ios::binary | std::ios::app) << whole.substr(whole.size() / 2); }
  std::this_thread::sleep_for(std::chrono::milliseconds(1500));
  // 3 s after the first half was written, but 1.5 s after the rest: not yet imported.
  EXPECT_EQ(serve->Client()->Get("/api/v1/tests")->body, "[]\n");
  WaitFor(*serve, "/api/v1/query/hic", Rows(1));
  EXPECT_EQ(serve->Client()->Get("/api/v1/query/hic")->body, CliQueryHic({{"foam-b", target}}));
  const Json status = Json::parse(serve->Client()->Get("/api/v1/status")->body);
  EXPECT_EQ(status.at("inbox").at("watch"), "poll");
  EXPECT_EQ(status.at("inbox").at("imported"), 1);
  EXPECT_EQ(status.at("inbox").at("failed"), 0);
  EXPECT_EQ(serve->Stop(), 0);
}

TEST_F(ServeInbox, MarkerFileImportsAtOnce) {
  const auto serve = Serve({"--settle", "3600"});
  ASSERT_GT(serve->port(), 0) << serve->log();
  WriteTest(inbox_ / "sled" / "foam-a" / "t04.csv", 104);
  WriteText(inbox_ / "sled" / "foam-a" / "t04.ready", "");
  WaitFor(*serve, "/api/v1/query/hic", Rows(1), 30);
  EXPECT_EQ(serve->Stop(), 0);
}

TEST_F(ServeInbox, BadSidecarsAreOneSentenceInTheStatus) {
  fs::create_directories(inbox_ / "typo" / "a");
  WriteText(inbox_ / "typo" / "napkin.json", R"({"arry": "denton-3222"})");
  WriteTest(inbox_ / "typo" / "a" / "t05.csv", 105);
  fs::create_directories(inbox_ / "unknown" / "a");
  WriteText(inbox_ / "unknown" / "a" / "napkin.json", R"({"array": "no-such-array"})");
  WriteTest(inbox_ / "unknown" / "a" / "t06.csv", 106);
  const auto serve = Serve({"--settle", "0.5"});
  ASSERT_GT(serve->port(), 0) << serve->log();
  const Json status =
      WaitFor(*serve, "/api/v1/status", [](const Json& s) { return s.at("inbox").at("failed") == 2; });
  std::map<std::string, std::string> messages;  // source -> sentence
  for (const Json& event : status.at("inbox").at("events"))
    if (event.at("kind") == "sidecar") messages[event.at("source")] = event.at("message");
  ASSERT_EQ(messages.size(), 2u) << status.dump(2);
  EXPECT_EQ(messages[(inbox_ / "typo" / "a" / "t05.csv").string()],
            "sidecar '" + (inbox_ / "typo" / "napkin.json").string() +
                "' has the unknown key 'arry' (it may give array, config and channel_map).");
  const std::string& unknown = messages[(inbox_ / "unknown" / "a" / "t06.csv").string()];
  EXPECT_NE(unknown.find("no-such-array"), std::string::npos) << unknown;
  // Named by the sidecar file that gives the array.
  EXPECT_EQ(
      unknown.rfind("sidecar '" + (inbox_ / "unknown" / "a" / "napkin.json").string() + "' key 'array': ", 0),
      0u)
      << unknown;
  EXPECT_EQ(std::count(unknown.begin(), unknown.end(), '\n'), 0);
  // Not retried while the files stay as they are.
  std::this_thread::sleep_for(std::chrono::seconds(2));
  EXPECT_EQ(Json::parse(serve->Client()->Get("/api/v1/status")->body).at("inbox").at("failed"), 2);
  EXPECT_EQ(serve->Client()->Get("/api/v1/tests")->body, "[]\n");
  EXPECT_EQ(serve->Stop(), 0);
}

// A sidecar that names no config (misspelt, or a name of 300 bytes), holds a control character, is a
// FIFO or is too large fails exactly the tests below it, recorded in the catalogue and said once with
// a sentence naming the sidecar file and the test; the other folders go on, before and after a
// restart, and a restart says the failures again only as one line (issue 42, point 1: a misspelt
// config was imported, its run threw every second after a restart, and the good folder's test stayed
// `settling`; the catalogue held nothing of the failures).
TEST_F(ServeInbox, BadSidecarsFailOnlyTheirTestsOnceBeforeAndAfterARestart) {
  const fs::path typo = inbox_ / "s" / "typo" / "napkin.json";
  const fs::path control = inbox_ / "s" / "control" / "napkin.json";
  const fs::path fifo = inbox_ / "s" / "fifo" / "napkin.json";
  const fs::path padded = inbox_ / "s" / "padded" / "napkin.json";
  const fs::path zero = inbox_ / "s" / "zero" / "napkin.json";
  const fs::path long_name = inbox_ / "s" / "long" / "napkin.json";
  for (const fs::path& sidecar : {typo, control, fifo, padded, zero, long_name})
    fs::create_directories(sidecar.parent_path());
  fs::create_symlink("/dev/zero", zero);
  WriteText(typo, R"({"config": "defualt"})");
  WriteText(long_name, R"({"config": ")" + std::string(300, 'c') + R"("})");
  WriteText(control, "{\"config\": \"def\\u0001ault\"}");
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  WriteText(padded, R"({"array": "denton-3222")" + std::string(100 * 1024, ' ') + "}");
  WriteTest(inbox_ / "s" / "typo" / "t20.csv", 120);
  WriteTest(inbox_ / "s" / "control" / "t21.csv", 121);
  WriteTest(inbox_ / "s" / "fifo" / "t22.csv", 122);
  WriteTest(inbox_ / "s" / "padded" / "t23.csv", 123);
  WriteTest(inbox_ / "s" / "zero" / "t26.csv", 126);
  WriteTest(inbox_ / "s" / "long" / "t27.csv", 127);
  WriteTest(inbox_ / "s" / "good" / "t24.csv", 124);
  const std::map<std::string, std::pair<fs::path, std::string>> expected = {
      {"t20", {typo, "key 'config': \"defualt\" is neither a file nor a preset"}},
      {"t21", {control, "key 'config' holds a control character"}},
      {"t22", {fifo, "is a FIFO (named pipe), not a regular file"}},
      {"t23", {padded, "bytes, more than the 64 KiB a sidecar may have"}},
      {"t26", {zero, "is a character device, not a regular file"}},
      {"t27", {long_name, "key 'config': \"" + std::string(300, 'c') + "\" is neither a file nor a preset"}}};
  const int failing = static_cast<int>(expected.size());
  // The failures in the catalogue (status.catalogue.inbox_failures), each the sentence said.
  const auto check_recorded = [&](const Json& status, const std::map<std::string, std::string>& said) {
    const Json& recorded = status.at("catalogue").at("inbox_failures");
    ASSERT_EQ(recorded.size(), expected.size()) << status.dump(2);
    for (const Json& failure : recorded) {
      const fs::path source = failure.at("source").get<std::string>();
      const std::string id = source.stem().string();
      EXPECT_EQ(failure.at("kind"), "sidecar") << failure.dump();
      EXPECT_EQ(failure.at("series"), "s") << failure.dump();
      EXPECT_EQ(failure.at("variant"), source.parent_path().filename().string()) << failure.dump();
      EXPECT_EQ(failure.at("error"), said.at(id)) << failure.dump();
    }
  };
  std::map<std::string, std::string> said;  // test id -> sentence
  {
    const auto serve = Serve({"--settle", "0.5"});
    ASSERT_GT(serve->port(), 0) << serve->log();
    WaitFor(*serve, "/api/v1/query/hic", Rows(1));
    const Json status = WaitFor(*serve, "/api/v1/status",
                                [&](const Json& s) { return s.at("inbox").at("failed") == failing; });
    std::this_thread::sleep_for(std::chrono::seconds(2));  // looked at again: nothing said twice
    const Json later = Json::parse(serve->Client()->Get("/api/v1/status")->body);
    for (const Json& event : later.at("inbox").at("events"))
      if (event.at("kind") == "sidecar") said[event.at("test_id")] = event.at("message");
    ASSERT_EQ(said.size(), expected.size()) << later.dump(2);
    const std::string log = serve->log();
    for (const auto& [id, sidecar_and_words] : expected) {
      const std::string& sentence = said[id];
      EXPECT_EQ(sentence.rfind("sidecar '" + sidecar_and_words.first.string() + "' ", 0), 0u) << sentence;
      EXPECT_NE(sentence.find(sidecar_and_words.second), std::string::npos) << sentence;
      std::size_t times = 0;  // said once in the log
      for (std::size_t at = log.find(sentence); at != std::string::npos; at = log.find(sentence, at + 1))
        ++times;
      EXPECT_EQ(times, 1u) << sentence << "\n" << log;
    }
    check_recorded(later, said);
    // Nothing of the failed tests is in the catalogue, half-imported and waiting.
    const Json tests = Json::parse(serve->Client()->Get("/api/v1/tests")->body);
    ASSERT_EQ(tests.size(), 1u) << tests.dump(2);
    EXPECT_EQ(tests[0].at("test_id"), "t24");
    EXPECT_EQ(status.at("catalogue").at("pending"), 0);
    EXPECT_EQ(serve->Stop(), 0);
  }
  // `napkin status` shows them without the service.
  const CommandResult cli_status = Napkin({"status"});
  EXPECT_NE(cli_status.out.find("inbox tests that failed before their import: " + std::to_string(failing)),
            std::string::npos)
      << cli_status.out;
  EXPECT_NE(cli_status.out.find(said["t20"]), std::string::npos) << cli_status.out;

  const auto serve = Serve({"--settle", "0.5"});
  ASSERT_GT(serve->port(), 0) << serve->log();
  WriteTest(inbox_ / "s" / "good" / "t25.csv", 125);
  WaitFor(*serve, "/api/v1/query/hic", Rows(2), 30);
  const Json status = WaitFor(*serve, "/api/v1/status",
                              [&](const Json& s) { return s.at("inbox").at("failed_earlier") == failing; });
  EXPECT_TRUE(status.at("inbox").at("settling").empty()) << status.dump(2);
  std::this_thread::sleep_for(std::chrono::seconds(2));
  const Json later = Json::parse(serve->Client()->Get("/api/v1/status")->body);
  EXPECT_EQ(later.at("inbox").at("failed"), 0) << later.dump(2);
  EXPECT_EQ(later.at("inbox").at("failed_earlier"), failing) << later.dump(2);
  check_recorded(later, said);
  // Said once, before the restart: now one line for all of them.
  const std::string log = serve->log();
  for (const auto& [id, sentence] : said) EXPECT_EQ(log.find(sentence), std::string::npos) << log;
  EXPECT_NE(
      log.find(std::to_string(failing) + " inbox test(s) failed before with the same files and sidecars"),
      std::string::npos)
      << log;
  // The misspelt config corrected: its test is imported and its failure is no longer listed.
  WriteText(typo, R"({"config": "default"})");
  WaitFor(*serve, "/api/v1/query/hic", Rows(3), 30);
  const Json corrected = WaitFor(*serve, "/api/v1/status", [&](const Json& s) {
    return s.at("catalogue").at("inbox_failures").size() == expected.size() - 1;
  });
  for (const Json& failure : corrected.at("catalogue").at("inbox_failures"))
    EXPECT_NE(failure.at("source"), (inbox_ / "s" / "typo" / "t20.csv").string());
  EXPECT_EQ(serve->Stop(), 0);
}

// A recording that pauses longer than --settle is imported half-written; when it goes on, the
// complete file replaces it: results computed again, said in the log and the status (issue 42,
// point 4: the complete file was refused with advice, `--test-id`, that does not apply to an inbox).
TEST_F(ServeInbox, ARecordingThatPausedIsImportedAgainWhenItGoesOn) {
  const auto serve = Serve({"--settle", "1"});
  ASSERT_GT(serve->port(), 0) << serve->log();
  const fs::path staged = dir_ / "whole.csv";
  formats::WriteSignalsCsv(SynthNapTest(130).signals, staged);
  const std::string whole = ReadText(staged);
  const std::size_t cut = whole.find('\n', whole.size() / 2) + 1;  // whole rows only
  const fs::path target = inbox_ / "sled" / "a" / "t30.csv";
  fs::create_directories(target.parent_path());
  WriteText(target, whole.substr(0, cut));
  WaitFor(*serve, "/api/v1/status", [](const Json& s) {
    return s.at("inbox").at("imported") == 1 &&
           s.at("catalogue").at("done").get<int>() + s.at("catalogue").at("failed").get<int>() == 1;
  });
  const std::string partial_hic = serve->Client()->Get("/api/v1/query/hic")->body;
  { std::ofstream(target, std::ios::binary | std::ios::app) << whole.substr(cut); }
  const Json status = WaitFor(*serve, "/api/v1/status", [](const Json& s) {
    return s.at("inbox").at("superseded") == 1 && s.at("catalogue").at("done") == 1;
  });
  const std::string complete_hic = serve->Client()->Get("/api/v1/query/hic")->body;
  EXPECT_NE(complete_hic, partial_hic);
  EXPECT_EQ(complete_hic, CliQueryHic({{"a", target}}));
  EXPECT_EQ(Json::parse(serve->Client()->Get("/api/v1/tests")->body).size(), 1u);
  EXPECT_EQ(status.at("inbox").at("failed"), 0) << status.dump(2);
  EXPECT_EQ(status.at("catalogue").at("failed"), 0) << status.dump(2);
  const std::string sentence = "t30: imported again from " +
                               fs::absolute(target).lexically_normal().string() +
                               ", whose content changed; the new content replaces the old.";
  bool shown = false;
  for (const Json& event : status.at("inbox").at("events"))
    shown = shown || (event.at("kind") == "superseded" && event.at("message") == sentence);
  EXPECT_TRUE(shown) << status.dump(2);
  EXPECT_NE(serve->log().find(sentence), std::string::npos) << serve->log();
  EXPECT_EQ(serve->log().find("--test-id"), std::string::npos) << serve->log();
  EXPECT_EQ(serve->Stop(), 0);
}

// What the inbox does not import is said once, in the log and the status, and a link leading out of
// the inbox is refused, never followed; a folder name that cannot be a variant is said as a folder
// name (issue 42, point 12: none of these got a word, and the link out was imported).
TEST_F(ServeInbox, IgnoredEntriesAreSaidOnceAndLinksOutOfTheInboxAreRefused) {
  const fs::path variant = inbox_ / "sled" / "a";
  WriteTest(variant / "t40.csv", 140);
  WriteTest(inbox_ / "stray.csv", 141);
  WriteTest(inbox_ / "sled" / "loose.csv", 142);
  ASSERT_EQ(::mkfifo((variant / "pipe.csv").c_str(), 0600), 0);
  // A socket bound in the variant folder (a lab logger's), and a device node where this user may
  // make one (root: the CI machine).
  const int socket_fd = ::socket(AF_UNIX, SOCK_STREAM, 0);
  ASSERT_GE(socket_fd, 0);
  sockaddr_un socket_address{};
  socket_address.sun_family = AF_UNIX;
  const std::string socket_path = (variant / "logger.csv").string();
  ASSERT_LT(socket_path.size(), sizeof(socket_address.sun_path));
  std::copy(socket_path.begin(), socket_path.end(), socket_address.sun_path);
  ASSERT_EQ(::bind(socket_fd, reinterpret_cast<const sockaddr*>(&socket_address), sizeof(socket_address)), 0);
  const bool device_made = ::mknod((variant / "tty.csv").c_str(), S_IFCHR | 0600, makedev(1, 3)) == 0;
  fs::create_symlink(dir_ / "nowhere.csv", variant / "gone.csv");
  fs::create_symlink(variant / "loop.csv", variant / "loop.csv");
  WriteTest(dir_ / "outside" / "secret.csv", 143);
  fs::create_symlink(dir_ / "outside" / "secret.csv", variant / "secret.csv");
  WriteTest(inbox_ / "sled" / "(none)" / "t41.csv", 144);
  std::map<std::string, std::pair<std::string, std::string>> expected = {
      // path -> kind, words
      {socket_path, {"ignored", "is a socket, not a file or a folder"}},
      {(inbox_ / "stray.csv").string(), {"ignored", "is a file at the inbox root"}},
      {(inbox_ / "sled" / "loose.csv").string(), {"ignored", "is a file in series folder"}},
      {(variant / "pipe.csv").string(), {"ignored", "is a FIFO (named pipe), not a file or a folder"}},
      {(variant / "gone.csv").string(), {"ignored", "is a symbolic link to nothing"}},
      {(variant / "loop.csv").string(), {"ignored", "is a loop of symbolic links"}},
      {(variant / "secret.csv").string(), {"refused", "is a symbolic link out of the inbox"}},
      {(inbox_ / "sled" / "(none)" / "t41.csv").string(), {"folder", "variant folder name '(none)'"}}};
  if (device_made)
    expected[(variant / "tty.csv").string()] = {"ignored", "is a character device, not a file or a folder"};
  const auto serve = Serve({"--settle", "0.5"});
  ASSERT_GT(serve->port(), 0) << serve->log();
  WaitFor(*serve, "/api/v1/query/hic", Rows(1));
  WaitFor(*serve, "/api/v1/status", [](const Json& s) { return s.at("inbox").at("failed") == 1; });
  std::this_thread::sleep_for(std::chrono::seconds(2));  // looked at again: nothing said twice
  const Json status = Json::parse(serve->Client()->Get("/api/v1/status")->body);
  const std::string log = serve->log();
  for (const auto& [path, kind_and_words] : expected) {
    std::vector<std::string> said;
    for (const Json& event : status.at("inbox").at("events"))
      if (event.at("source") == path)
        said.push_back(event.at("kind").get<std::string>() + ": " + event.at("message").get<std::string>());
    ASSERT_EQ(said.size(), 1u) << path << "\n" << status.dump(2);
    EXPECT_EQ(said[0].rfind(kind_and_words.first + ": ", 0), 0u) << said[0];
    EXPECT_NE(said[0].find(kind_and_words.second), std::string::npos) << said[0];
    EXPECT_EQ(said[0].find("--variant"), std::string::npos) << said[0];
    const std::string sentence = said[0].substr(said[0].find(": ") + 2);
    std::size_t times = 0;
    for (std::size_t at = log.find(sentence); at != std::string::npos; at = log.find(sentence, at + 1))
      ++times;
    EXPECT_EQ(times, 1u) << sentence << "\n" << log;
  }
  const Json tests = Json::parse(serve->Client()->Get("/api/v1/tests")->body);
  ASSERT_EQ(tests.size(), 1u) << tests.dump(2);
  EXPECT_EQ(tests[0].at("test_id"), "t40");
  EXPECT_EQ(serve->Stop(), 0);
  ::close(socket_fd);
}

// A test that fails screening (a clipped channel): recorded as `napkin run` records it, shown in the
// status with its sentence at once, and not tried again.
TEST_F(ServeInbox, ScreeningFailureIsShownAndNotRetried) {
  const auto serve = Serve({"--settle", "0.5"});
  ASSERT_GT(serve->port(), 0) << serve->log();
  synth::SyntheticTest test = SynthNapTest(109);
  auto clipped = test.signals.samples.col(test.signals.FindSlot("cg_z"));
  const double clip = 0.5 * clipped.cwiseAbs().maxCoeff();
  clipped = clipped.cwiseMax(-clip).cwiseMin(clip);
  fs::create_directories(inbox_ / "sled" / "a");
  formats::WriteSignalsCsv(test.signals, inbox_ / "sled" / "a" / "clipped.csv");
  WriteTest(inbox_ / "sled" / "a" / "clean.csv", 110);
  const Json status = WaitFor(*serve, "/api/v1/status", [](const Json& s) {
    return s.at("inbox").at("failed") == 1 && s.at("inbox").at("processed") == 1;
  });
  const Json& failures = status.at("catalogue").at("failures");
  ASSERT_EQ(failures.size(), 1u) << status.dump(2);
  EXPECT_EQ(failures.at(0).at("test_id"), "clipped");
  const std::string sentence = failures.at(0).at("error");
  EXPECT_NE(sentence.find("cg_z"), std::string::npos) << sentence;
  bool shown = false;
  for (const Json& event : status.at("inbox").at("events"))
    shown = shown || (event.at("kind") == "failed" && event.value("test_id", "") == "clipped" &&
                      event.at("message") == sentence);
  EXPECT_TRUE(shown) << status.dump(2);
  // The same sentence `napkin status` gives; no second attempt.
  const Json cli = Json::parse(Napkin({"status", "--format", "json"}).out);
  EXPECT_EQ(cli.at("failures"), failures);
  std::this_thread::sleep_for(std::chrono::seconds(2));
  const Json later = Json::parse(serve->Client()->Get("/api/v1/status")->body);
  EXPECT_EQ(later.at("inbox").at("failed"), 1);
  EXPECT_EQ(later.at("inbox").at("imported"), 2);
  EXPECT_EQ(serve->Stop(), 0);
}

// The log line of a run counts every test it processed, a failed one too (issue 42, point 11: two
// tests, one failing screening, were "processed 1 tests").
TEST_F(ServeInbox, TheProcessedLineCountsFailedTestsToo) {
  // Only the markers import, and polling looks once a second, not at each file's inotify event: the
  // two markers, written microseconds apart, are found in one look.
  const auto serve = Serve({"--settle", "3600", "--poll", "1"});
  ASSERT_GT(serve->port(), 0) << serve->log();
  synth::SyntheticTest test = SynthNapTest(150);
  auto clipped = test.signals.samples.col(test.signals.FindSlot("cg_z"));
  const double clip = 0.5 * clipped.cwiseAbs().maxCoeff();
  clipped = clipped.cwiseMax(-clip).cwiseMin(clip);
  fs::create_directories(inbox_ / "sled" / "a");
  formats::WriteSignalsCsv(test.signals, inbox_ / "sled" / "a" / "clipped.csv");
  WriteTest(inbox_ / "sled" / "a" / "clean.csv", 151);
  WaitFor(*serve, "/api/v1/status", [](const Json& s) { return s.at("inbox").at("settling").size() == 2; });
  WriteText(inbox_ / "sled" / "a" / "clipped.ready", "");
  WriteText(inbox_ / "sled" / "a" / "clean.ready", "");
  WaitFor(*serve, "/api/v1/status", [](const Json& s) {
    return s.at("inbox").at("failed") == 1 && s.at("inbox").at("processed") == 1;
  });
  // The counts are in the status a moment before the line is in the log.
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  while (serve->log().find("test 'clipped' failed") == std::string::npos &&
         std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  const std::string log = serve->log();
  EXPECT_NE(log.find("processed 2 tests from the inbox in "), std::string::npos) << log;
  EXPECT_NE(log.find(" s: 1 with a result, 1 failed"), std::string::npos) << log;
  // Every line of the service's log carries its time, the error saying the test failed too (issue
  // 42, point 11: warnings and errors had none).
  const std::regex stamped(R"(^[0-9]{4}-[0-9]{2}-[0-9]{2}T[0-9]{2}:[0-9]{2}:[0-9]{2}\.[0-9]{3} .*)");
  std::istringstream lines(log);
  std::size_t errors = 0;
  for (std::string line; std::getline(lines, line);) {
    EXPECT_TRUE(std::regex_match(line, stamped)) << line;
    if (line.find(" napkin: test 'clipped' failed: ") != std::string::npos) ++errors;
  }
  EXPECT_EQ(errors, 1u) << log;
  EXPECT_EQ(serve->Stop(), 0);
}

TEST_F(ServeInbox, RemovedBeforeSettlingIsSaid) {
  const auto serve = Serve({"--settle", "3600", "--poll", "0.2"});
  ASSERT_GT(serve->port(), 0) << serve->log();
  WriteTest(inbox_ / "sled" / "a" / "t07.csv", 107);
  WaitFor(*serve, "/api/v1/status", [](const Json& s) { return s.at("inbox").at("settling").size() == 1; });
  fs::remove(inbox_ / "sled" / "a" / "t07.csv");
  const Json status =
      WaitFor(*serve, "/api/v1/status", [](const Json& s) { return s.at("inbox").at("settling").empty(); });
  bool said = false;
  for (const Json& event : status.at("inbox").at("events"))
    said = said || (event.at("kind") == "removed" &&
                    event.at("message") ==
                        "test '" + (inbox_ / "sled" / "a" / "t07.csv").string() +
                            "' was removed from the inbox before it settled; it was not imported.");
  EXPECT_TRUE(said) << status.dump(2);
  EXPECT_NE(serve->log().find("was removed from the inbox before it settled"), std::string::npos);
  EXPECT_EQ(serve->Stop(), 0);
}

// A test removed after it settled but before it was imported (the catalogue was locked meanwhile,
// as a CLI `run` committing holds it): a sentence in the log and the status, and the other test
// that settled with it is imported and processed.
TEST_F(ServeInbox, RemovedAfterSettlingBeforeImportIsSaidAndTheRestGoesOn) {
  const auto serve = Serve({"--settle", "3600", "--busy-timeout", "1"});
  ASSERT_GT(serve->port(), 0) << serve->log();
  sqlite3* holder = nullptr;
  ASSERT_EQ(sqlite3_open(db_.c_str(), &holder), SQLITE_OK);
  ASSERT_EQ(
      sqlite3_exec(holder, "PRAGMA locking_mode=EXCLUSIVE; BEGIN EXCLUSIVE; CREATE TABLE held_by_test(x);",
                   nullptr, nullptr, nullptr),
      SQLITE_OK)
      << sqlite3_errmsg(holder);
  const fs::path kept = inbox_ / "sled" / "a" / "t09.csv";
  const fs::path removed = inbox_ / "sled" / "a" / "t10.csv";
  WriteTest(kept, 109);
  WriteTest(removed, 110);
  WriteText(inbox_ / "sled" / "a" / "t09.ready", "");
  WriteText(inbox_ / "sled" / "a" / "t10.ready", "");
  // Both settled (their markers): the inbox waits for the catalogue to import them.
  WaitFor(*serve, "/api/v1/status",
          [](const Json& s) { return s.at("inbox").at("catalogue_waiting").is_string(); });
  fs::remove(removed);
  ASSERT_EQ(sqlite3_exec(holder, "ROLLBACK;", nullptr, nullptr, nullptr), SQLITE_OK);
  sqlite3_close(holder);
  WaitFor(*serve, "/api/v1/query/hic", Rows(1));
  // Which of two sentences depends on whether the inbox's next look began before the removal
  // (then it finds the file gone as it reads it) or after (then the test is simply gone).
  const std::string prefix = "test '" + removed.string() + "' was removed from the inbox ";
  const std::set<std::string> sentences = {
      prefix + "after it settled, before it could be imported; it was not imported.",
      prefix + "while it was being imported; it was not imported ('" + removed.string() +
          "' does not exist.)"};
  std::string said;
  const Json status = WaitFor(*serve, "/api/v1/status", [&](const Json& s) {
    for (const Json& event : s.at("inbox").at("events"))
      if (event.at("kind") == "removed" && sentences.count(event.at("message").get<std::string>()))
        said = event.at("message").get<std::string>();
    return !said.empty();
  });
  EXPECT_EQ(status.at("inbox").at("imported"), 1) << status.dump(2);
  EXPECT_NE(serve->log().find(said), std::string::npos) << serve->log();
  const Json tests = Json::parse(serve->Client()->Get("/api/v1/tests")->body);
  ASSERT_EQ(tests.size(), 1u);
  EXPECT_EQ(tests[0].at("test_id"), "t09");
  EXPECT_EQ(serve->Stop(), 0);
}

// A catalogue held locked by another process (as a CLI `run` committing holds it): the inbox waits,
// says so in the status, and imports once the lock is gone.
TEST_F(ServeInbox, LockedCatalogueWaitsAndSaysSo) {
  const auto serve = Serve({"--settle", "0"});
  ASSERT_GT(serve->port(), 0) << serve->log();
  sqlite3* holder = nullptr;
  ASSERT_EQ(sqlite3_open(db_.c_str(), &holder), SQLITE_OK);
  ASSERT_EQ(sqlite3_exec(holder,
                         "PRAGMA locking_mode=EXCLUSIVE; BEGIN EXCLUSIVE; CREATE TABLE held_by_test(x); "
                         "INSERT INTO held_by_test VALUES (1);",
                         nullptr, nullptr, nullptr),
            SQLITE_OK)
      << sqlite3_errmsg(holder);
  WriteTest(inbox_ / "sled" / "a" / "t08.csv", 108);
  const Json waiting = WaitFor(*serve, "/api/v1/status", [](const Json& s) {
    return s.value("catalogue", Json()).is_object() && s.at("inbox").at("catalogue_waiting").is_string();
  });
  EXPECT_NE(waiting.at("inbox")
                .at("catalogue_waiting")
                .get<std::string>()
                .find("waiting for catalogue '" + db_.string() + "', locked by another process"),
            std::string::npos);
  EXPECT_NE(serve->log().find("is busy"), std::string::npos) << serve->log();
  ASSERT_EQ(sqlite3_exec(holder, "ROLLBACK;", nullptr, nullptr, nullptr), SQLITE_OK);
  sqlite3_close(holder);
  WaitFor(*serve, "/api/v1/query/hic", Rows(1));
  WaitFor(*serve, "/api/v1/status",
          [](const Json& s) { return s.at("inbox").at("catalogue_waiting").is_null(); });
  EXPECT_EQ(serve->Stop(), 0);
}

// kill -9 while the inbox is being imported and processed, then a restart: every test exactly once.
TEST_F(ServeInbox, KillNineAndRestartLoseAndDuplicateNothing) {
  for (int i = 0; i < 12; ++i)
    WriteTest(inbox_ / "sled" / (i % 2 ? "a" : "b") / ("k" + std::to_string(i) + ".csv"), 200 + i);
  {
    const auto serve = Serve({"--settle", "0"});
    ASSERT_GT(serve->port(), 0) << serve->log();
    // Killed as soon as the first test is imported: the rest is mid-import or mid-processing.
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
    while (serve->log().find("imported from") == std::string::npos &&
           std::chrono::steady_clock::now() < deadline)
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    EXPECT_EQ(serve->Stop(SIGKILL), -1);
  }
  const auto serve = Serve({"--settle", "0"});
  ASSERT_GT(serve->port(), 0) << serve->log();
  WaitFor(
      *serve, "/api/v1/status", [](const Json& s) { return s.at("catalogue").at("done") == 12; }, 120);
  const Json tests = Json::parse(serve->Client()->Get("/api/v1/tests")->body);
  EXPECT_EQ(tests.size(), 12u);
  const Json status = Json::parse(serve->Client()->Get("/api/v1/status")->body);
  EXPECT_EQ(status.at("catalogue").at("failed"), 0);
  EXPECT_EQ(status.at("catalogue").at("pending"), 0);
  EXPECT_EQ(serve->Stop(), 0);
  // One result per test.
  db::Catalogue catalogue = OpenForReading(db_);
  EXPECT_EQ(catalogue.Query(db::QueryKind::kHic).rows.size(), 12u);
}

// kill -9 while the run scheduler holds leases (tests of 20,000 samples: processing takes a while
// under the sanitizers), then a restart: every test exactly once.
TEST_F(ServeInbox, KillNineDuringProcessingAndRestartLoseAndDuplicateNothing) {
  for (int i = 0; i < 8; ++i) {
    fs::create_directories(inbox_ / "sled" / "a");
    formats::WriteSignalsCsv(SynthNapTest(400 + i, 2.0).signals,
                             inbox_ / "sled" / "a" / ("p" + std::to_string(i) + ".csv"));
  }
  bool killed_while_running = false;
  {
    const auto serve = Serve({"--settle", "0"});
    ASSERT_GT(serve->port(), 0) << serve->log();
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(120);
    while (std::chrono::steady_clock::now() < deadline) {
      const httplib::Result status = serve->Client()->Get("/api/v1/status");
      if (status && status->status == 200) {
        const Json catalogue = Json::parse(status->body).at("catalogue");
        if (catalogue.contains("running") && catalogue.at("running").get<int>() > 0) {
          killed_while_running = true;
          break;
        }
        if (catalogue.contains("done") && catalogue.at("done").get<int>() == 8) break;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
    EXPECT_EQ(serve->Stop(SIGKILL), -1);
  }
  EXPECT_TRUE(killed_while_running) << "processing ended before a job was seen running";
  const auto serve = Serve({"--settle", "0"});
  ASSERT_GT(serve->port(), 0) << serve->log();
  WaitFor(
      *serve, "/api/v1/status", [](const Json& s) { return s.at("catalogue").value("done", 0) == 8; }, 240);
  const Json status = Json::parse(serve->Client()->Get("/api/v1/status")->body);
  EXPECT_EQ(status.at("catalogue").at("tests"), 8);
  EXPECT_EQ(status.at("catalogue").at("failed"), 0);
  EXPECT_EQ(status.at("catalogue").at("running"), 0);
  EXPECT_EQ(serve->Stop(), 0);
  db::Catalogue catalogue = OpenForReading(db_);
  EXPECT_EQ(catalogue.Query(db::QueryKind::kHic).rows.size(), 8u);
}

TEST_F(ServeInbox, SigtermWhileProcessingExitsZeroAndARestartFinishes) {
  for (int i = 0; i < 12; ++i) WriteTest(inbox_ / "sled" / "a" / ("s" + std::to_string(i) + ".csv"), 300 + i);
  {
    const auto serve = Serve({"--settle", "0"});
    ASSERT_GT(serve->port(), 0) << serve->log();
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
    while (serve->log().find("imported from") == std::string::npos &&
           std::chrono::steady_clock::now() < deadline)
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    EXPECT_EQ(serve->Stop(SIGTERM), 0) << serve->log();
  }
  const auto serve = Serve({"--settle", "0"});
  ASSERT_GT(serve->port(), 0) << serve->log();
  WaitFor(
      *serve, "/api/v1/status", [](const Json& s) { return s.at("catalogue").at("done") == 12; }, 120);
  EXPECT_EQ(Json::parse(serve->Client()->Get("/api/v1/tests")->body).size(), 12u);
  EXPECT_EQ(serve->Stop(), 0);
}

}  // namespace
}  // namespace napkin::test_support
