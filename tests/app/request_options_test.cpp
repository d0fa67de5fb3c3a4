// app/request_options.h and the parsers over it (ParseCompareRequest,
// ParseExportRequest), without a front end: the same options and defaults
// whichever front end gives them, and each refusal one sentence naming the
// option as that front end spells it (issue 43 points 5, 7 and 8).
#include "app/request_options.h"

#include <gtest/gtest.h>

#include <set>
#include <string>
#include <variant>

#include "app/comparison.h"
#include "app/export.h"
#include "common/error.h"

namespace napkin::app {
namespace {

constexpr FrontEnd kFrontEnds[] = {FrontEnd::kCommandLine, FrontEnd::kService, FrontEnd::kPython};

// The UsageError `parse` throws ("" for none).
template <typename Parse>
std::string Refusal(Parse parse) {
  try {
    parse();
  } catch (const UsageError& error) {
    return error.what();
  }
  return "";
}

TEST(RequestOptions, EachFrontEndSpellsAnOptionItsWay) {
  EXPECT_EQ(OptionName(FrontEnd::kCommandLine, "dummy-type"), "--dummy-type");
  EXPECT_EQ(OptionName(FrontEnd::kService, "dummy-type"), "parameter 'dummy_type'");
  EXPECT_EQ(OptionName(FrontEnd::kPython, "dummy-type"), "argument 'dummy_type'");
  EXPECT_EQ(OptionSetting(FrontEnd::kCommandLine, "by", "config"), "--by config");
  EXPECT_EQ(OptionSetting(FrontEnd::kService, "by", "config"), "by=config");
  EXPECT_EQ(OptionSetting(FrontEnd::kPython, "by", "config"), "by='config'");
  // Given as the front end spells it, asked for by the command line's name.
  RequestOptions service(FrontEnd::kService);
  service.Add("dummy_type", "H3").Add("metrics", "hic15,,bric").Add("metrics", "a3ms_g");
  EXPECT_EQ(service.One("dummy-type"), "H3");
  EXPECT_EQ(service.CommaList("metrics"), (std::vector<std::string>{"hic15", "bric", "a3ms_g"}));
  EXPECT_EQ(Refusal([&] { (void)service.One("metrics"); }), "parameter 'metrics' is given more than once.");
  EXPECT_EQ(Refusal([&] { service.CheckKnown({"dummy-type"}); }),
            "unknown parameter 'metrics' (this route takes dummy_type).");
  RequestOptions python(FrontEnd::kPython);
  python.Add("part", "x");
  EXPECT_EQ(Refusal([&] { (void)python.WholeNumber("part", 1, 1); }),
            "argument 'part' must be a whole number at least 1; it is 'x'.");
  EXPECT_EQ(Refusal([&] { (void)python.Required("series", "the series"); }),
            "argument 'series' is required (the series).");
}

TEST(ParseCompareRequest, TheDefaultsAndTheOptionsAreTheSameInEveryFrontEnd) {
  for (const FrontEnd front_end : kFrontEnds) {
    RequestOptions defaults(front_end);
    defaults.Add("series", "s");
    const CompareRequest plain = ParseCompareRequest(defaults);
    EXPECT_EQ(plain.series, "s");
    EXPECT_EQ(plain.by, CompareBy::kVariant);
    EXPECT_EQ(plain.scale, CompareScale::kLog);
    EXPECT_EQ(plain.equivalence_pct, kDefaultEquivalencePct);
    EXPECT_FALSE(plain.baseline);
    EXPECT_TRUE(plain.metrics.empty() && plain.configs.empty() && plain.limits.empty());
    EXPECT_EQ(plain.front_end, front_end);

    RequestOptions given(front_end);
    given.Add("series", "s")
        .Add("by", "config")
        .Add("baseline", "default")
        .Add("metrics", "hic15,bric")
        .Add("config", "a")
        .Add("config", "b")
        .Add("scale", "linear")
        .Add("equivalence", "2.5")
        .Add("limits", "fmvss208");
    const CompareRequest request = ParseCompareRequest(given);
    EXPECT_EQ(request.by, CompareBy::kConfig);
    EXPECT_EQ(request.baseline, "default");
    EXPECT_EQ(request.metrics, (std::vector<std::string>{"hic15", "bric"}));
    EXPECT_EQ(request.configs, (std::vector<std::string>{"a", "b"}));
    EXPECT_EQ(request.scale, CompareScale::kLinear);
    EXPECT_EQ(request.equivalence_pct, 2.5);
    EXPECT_EQ(request.limits, (std::vector<std::string>{"fmvss208"}));
  }
}

TEST(ParseCompareRequest, ARefusalIsOneSentenceSpelledByTheFrontEnd) {
  const auto refusal = [](FrontEnd front_end, const std::string& option, const std::string& value) {
    RequestOptions options(front_end);
    options.Add("series", "s").Add(option, value);
    return Refusal([&] { (void)ParseCompareRequest(options); });
  };
  EXPECT_EQ(refusal(FrontEnd::kCommandLine, "by", "colour"),
            "--by must be variant or config; it is 'colour'.");
  EXPECT_EQ(refusal(FrontEnd::kService, "by", "colour"),
            "parameter 'by' must be variant or config; it is 'colour'.");
  EXPECT_EQ(refusal(FrontEnd::kPython, "scale", "cubic"),
            "argument 'scale' must be log or linear; it is 'cubic'.");
  for (const std::string bad : {"0", "100", "-5", "ten", "nan", "inf"})
    EXPECT_EQ(
        refusal(FrontEnd::kService, "equivalence", bad),
        "parameter 'equivalence' must be a margin in percent between 0 and 100 (exclusive), e.g. 10 for "
        "±10 %; it is '" +
            bad + "'.")
        << bad;
  EXPECT_EQ(refusal(FrontEnd::kService, "colour", "red"),
            "unknown parameter 'colour' (this route takes series, by, baseline, metrics, config, scale, "
            "equivalence, limits).");
  RequestOptions two_configs(FrontEnd::kPython);
  two_configs.Add("series", "s").Add("config", "a").Add("config", "b");
  EXPECT_EQ(Refusal([&] { (void)ParseCompareRequest(two_configs); }),
            "by='variant' compares the results of one config; give argument 'config' once (or use "
            "by='config').");
  RequestOptions two_limits(FrontEnd::kCommandLine);
  two_limits.Add("series", "s")
      .Add("limits", "fmvss208")
      .Add("limits", "euro-ncap-aop-v9.3-frontal-head-hiii50m");
  EXPECT_EQ(
      Refusal([&] { (void)ParseCompareRequest(two_limits); }).rfind("--limits: FMVSS 208 and Euro NCAP", 0),
      0u);
  RequestOptions no_series(FrontEnd::kService);
  EXPECT_EQ(Refusal([&] { (void)ParseCompareRequest(no_series); }),
            "parameter 'series' is required (the series whose tests are compared).");
}

TEST(ExportFormats, OneRowPerFormatEachWithAWriter) {
  std::set<std::string_view> names;
  for (const ExportFormat& format : ExportFormats()) {
    EXPECT_TRUE(names.insert(format.name).second) << format.name;
    EXPECT_NE(format.write, nullptr) << format.name;
    EXPECT_FALSE(format.description.empty()) << format.name;
    // A folder has no extension of its own and goes out as a zip archive.
    EXPECT_EQ(format.folder, format.extension.empty()) << format.name;
    EXPECT_EQ(format.folder, format.content_type == "application/zip") << format.name;
    EXPECT_TRUE(format.input == ExportInput::kDerived || !format.needs_rotation) << format.name;
    EXPECT_EQ(FindExportFormat(format.name), &format);
  }
  EXPECT_EQ(ExportFormatNames(), (std::vector<std::string>{"csv", "json", "lsdyna", "lcfile", "isomme", "uds",
                                                           "channels", "recorded"}));
  EXPECT_EQ(FindExportFormat("xlsx"), nullptr);
}

TEST(ParseExportRequest, TheConfigIsAPresetOnTheCommandLineAndAStoredConfigElsewhere) {
  for (const FrontEnd front_end : kFrontEnds) {
    RequestOptions options(front_end);
    options.Add("format", "lsdyna").Add("config", "default");
    const ExportRequest request = ParseExportRequest("T1", options);
    EXPECT_EQ(request.test_id, "T1");
    EXPECT_EQ(request.format, FindExportFormat("lsdyna"));
    EXPECT_EQ(request.lsdyna.units, formats::LsDynaUnits::kSi);
    EXPECT_EQ(request.lsdyna.part_id, 1);
    EXPECT_EQ(request.number_form, formats::UdsNumberForm::kIeee);
    if (front_end == FrontEnd::kCommandLine) {
      ASSERT_TRUE(std::holds_alternative<Preset>(request.result));
      EXPECT_EQ(std::get<Preset>(request.result).name_or_path, "default");
    } else {
      ASSERT_TRUE(std::holds_alternative<Stored>(request.result));
      EXPECT_EQ(std::get<Stored>(request.result).selector, "default");
      EXPECT_EQ(std::get<Stored>(request.result).option, OptionName(front_end, "config"));
    }
  }
  RequestOptions given(FrontEnd::kService);
  given.Add("format", "uds")
      .Add("units", "english")
      .Add("part", "7")
      .Add("numform", "vax")
      .Add("dummy_type", "H3");
  const ExportRequest request = ParseExportRequest("T1", given);
  EXPECT_TRUE(std::holds_alternative<Latest>(request.result));
  EXPECT_EQ(request.lsdyna.units, formats::LsDynaUnits::kEnglish);
  EXPECT_EQ(request.lsdyna.part_id, 7);
  EXPECT_EQ(request.number_form, formats::UdsNumberForm::kVax);
  EXPECT_EQ(request.dummy_type, "H3");
  EXPECT_FALSE(request.position);

  RequestOptions unknown(FrontEnd::kCommandLine);
  unknown.Add("format", "xlsx");
  EXPECT_EQ(Refusal([&] { (void)ParseExportRequest("T1", unknown); }),
            "--format must be csv, json, lsdyna, lcfile, isomme, uds, channels or recorded; it is 'xlsx'.");
  RequestOptions part(FrontEnd::kService);
  part.Add("format", "lsdyna").Add("part", "0");
  EXPECT_EQ(Refusal([&] { (void)ParseExportRequest("T1", part); }),
            "parameter 'part' must be at least 1; it is 0.");
  RequestOptions test(FrontEnd::kService);
  test.Add("format", "csv").Add("test", "T2");
  EXPECT_EQ(Refusal([&] { (void)ParseExportRequest("T1", test); }),
            "unknown parameter 'test' (this route takes format, config, units, part, numform, position, "
            "dummy_type).");
}

}  // namespace
}  // namespace napkin::app
