// Refused command lines (issue 19, point 17): every option error is one
// sentence "napkin: ..." with exit status 2 from the one diagnostics path
// (cli/diagnostics.cpp ReportOptionError, cli/option_checks.h), never
// CLI11's own text ("Value 0 not in range 0.000000 to 1797…", 309 digits,
// without the program's name); and --quiet leaves warnings and errors only.
#include <gtest/gtest.h>

#include "formats/csv.h"
#include "tests/cli/cli_test_util.h"
#include "tests/support/test_support.h"

namespace napkin::cli {

using namespace napkin::test_support;
namespace {

class CliOptionErrors : public ::testing::Test {
 protected:
  void SetUp() override { ASSERT_EQ(RunNapkin(dir_.path(), {"init"}).exit_code, 0); }

  // `args` is refused with exit 2 and exactly `sentence` on stderr.
  void ExpectRefused(const std::vector<std::string>& args, const std::string& sentence) {
    std::string shown;
    for (const std::string& arg : args) shown += " " + arg;
    SCOPED_TRACE("napkin" + shown);
    const RunResult run = RunNapkin(dir_.path(), args);
    EXPECT_EQ(run.exit_code, 2);
    EXPECT_EQ(run.out, "");
    EXPECT_EQ(run.err, "napkin: " + sentence + "\n");
  }

  napkin::test_support::TempDir dir_;
};

TEST_F(CliOptionErrors, BadValuesAreOneSentenceNamingTheOption) {
  ExpectRefused({"run", "--threads", "0"}, "--threads must be at least 1; it is 0.");
  ExpectRefused({"run", "--threads", "many"}, "--threads must be a whole number at least 1; it is 'many'.");
  ExpectRefused({"run", "--threads", "99999999999"},
                "--threads must be at most 2147483647; it is 99999999999.");
  ExpectRefused({"demo", "--threads", "-2"}, "--threads must be at least 1; it is -2.");
  ExpectRefused({"query", "hic", "--format", "xml"}, "--format must be table, csv or json; it is 'xml'.");
  ExpectRefused(
      {"query", "everything"},
      "the query kind must be tests, hic, rotation, criteria, risk, quality, conditioning, correlation or "
      "limits; it is 'everything'.");
  ExpectRefused({"run", "--shard", "5/3"}, "--shard takes I/N with 0 <= I < N, e.g. 0/3; it is '5/3'.");
  ExpectRefused({"compare", "--series", "s", "--by", "colour"},
                "--by must be variant or config; it is 'colour'.");
  ExpectRefused({"compare", "--series", "s", "--format", "xml"},
                "--format must be table, csv or json; it is 'xml'.");
  ExpectRefused({"status", "--format", "csv"}, "--format must be table or json; it is 'csv'.");
  ExpectRefused(
      {"export", "--test", "t", "--format", "xlsx", "--out", "x"},
      "--format must be csv, json, lsdyna, lcfile, isomme, uds, channels or recorded; it is 'xlsx'.");
  ExpectRefused({"export", "--test", "t", "--format", "uds", "--numform", "ibm", "--out", "x"},
                "--numform must be ieee, vax or sun; it is 'ibm'.");
  ExpectRefused({"export", "--test", "t", "--format", "lsdyna", "--units", "mm", "--out", "x"},
                "--units must be si or english; it is 'mm'.");
  ExpectRefused({"export", "--test", "t", "--format", "lsdyna", "--part", "0", "--out", "x"},
                "--part must be at least 1; it is 0.");
  ExpectRefused(
      {"synth", "--scenario", "crash"},
      "--scenario must be seed-fixed-axis, seed-sequential, random or padding-series; it is 'crash'.");
  ExpectRefused({"synth", "--scenario", "random", "--count", "0"}, "--count must be at least 1; it is 0.");
  ExpectRefused({"synth", "--scenario", "random", "--samples", "1"},
                "--samples must be from 2 to 100000000; it is 1.");
  ExpectRefused({"synth", "--scenario", "random", "--duration", "0"}, "--duration must be above 0; it is 0.");
  ExpectRefused({"synth", "--scenario", "random", "--rate", "fast"},
                "--rate must be a number above 0; it is 'fast'.");
  ExpectRefused({"transform", "--array", "a", "--solver", "magic", "in.csv", "--out", "o.csv"},
                "--solver must be exact or seed; it is 'magic'.");
  ExpectRefused(
      {"import", "--array", "a", "--orientation", "1,2", "x.csv"},
      "--orientation needs three comma-separated numbers, e.g. --orientation=0.1,0,-0.2; it is '1,2'.");
  // A long value is cut, as all quoted input.
  const RunResult long_value = RunNapkin(dir_.path(), {"query", "hic", "--format", std::string(5000, 'x')});
  EXPECT_EQ(long_value.exit_code, 2);
  ExpectOneSentenceError(long_value, {"--format must be table, csv or json; it is 'xxx", "more bytes)'"});
  EXPECT_LT(long_value.err.size(), 200u);
}

TEST_F(CliOptionErrors, StructuralErrorsAreOneSentenceToo) {
  for (const std::vector<std::string>& args : std::vector<std::vector<std::string>>{
           {},
           {"frobnicate"},
           {"query"},
           {"query", "hic", "--bogus"},
           {"run", "--threads"},
           {"export", "--test", "t"},
           {"synth", "--scenario", "random", "--samples", "5", "--duration", "1"}}) {
    std::string shown;
    for (const std::string& arg : args) shown += " " + arg;
    SCOPED_TRACE("napkin" + shown);
    const RunResult run = RunNapkin(dir_.path(), args);
    EXPECT_EQ(run.exit_code, 2);
    ExpectOneSentenceError(run, {"`napkin --help` lists the commands"});
    EXPECT_EQ(run.err.find("Run with --help"), std::string::npos) << run.err;
  }
  ExpectRefused(
      {"query"},
      "KIND is required; `napkin --help` lists the commands, `napkin COMMAND --help` their options.");
  ExpectRefused({"run", "--threads"},
                "--threads needs a value; `napkin --help` lists the commands, `napkin COMMAND --help` their "
                "options.");
  ExpectRefused({"synth", "--scenario", "random", "--samples", "5", "--duration", "1"},
                "--samples and --duration cannot be given together; `napkin --help` lists the commands, "
                "`napkin COMMAND --help` their options.");
  // --help and --version still print and succeed.
  EXPECT_EQ(RunNapkin(dir_.path(), {"--version"}).exit_code, 0);
  const RunResult help = RunNapkin(dir_.path(), {"run", "--help"});
  EXPECT_EQ(help.exit_code, 0);
  EXPECT_NE(help.out.find("--threads"), std::string::npos) << help.out;
}

TEST_F(CliOptionErrors, QuietLeavesWarningsAndErrorsOnly) {
  formats::WriteSignalsCsv(SynthNapTest(61).signals, dir_ / "q.csv");
  ASSERT_EQ(RunNapkin(dir_.path(), {"import", "--array", "denton-3222", "q.csv"}).exit_code, 0);
  // Without --quiet, run logs time-stamped information lines.
  const RunResult loud = RunNapkin(dir_.path(), {"run", "--config", "default"});
  EXPECT_EQ(loud.exit_code, 0) << loud.err;
  EXPECT_NE(loud.err.find(" info "), std::string::npos) << loud.err;

  for (const std::vector<std::string>& args :
       std::vector<std::vector<std::string>>{{"-q", "run", "--force"}, {"run", "--force", "--quiet"}}) {
    const RunResult quiet = RunNapkin(dir_.path(), args);
    EXPECT_EQ(quiet.exit_code, 0) << quiet.err;
    EXPECT_EQ(quiet.err, "");
  }
  // Errors still show.
  const RunResult error = RunNapkin(dir_.path(), {"-q", "run", "--config", "no-such-config"});
  EXPECT_NE(error.exit_code, 0);
  ExpectOneSentenceError(error, {"no-such-config"});
}

}  // namespace
}  // namespace napkin::cli
