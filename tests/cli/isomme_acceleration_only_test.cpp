// `export --format isomme` of an acceleration-only test (array 3a-cg; docs/
// formats.md "ISO-MME export"): the channels such a test has — the CG
// acceleration along x, y, z and its resultant, with their ISO/TS 13499
// codes — written as stored, and re-imported (import -> run -> export ->
// import -> run) to the same acceleration and criteria.
#include <gtest/gtest.h>

#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "engine/units.h"
#include "formats/csv.h"
#include "formats/isomme.h"
#include "tests/cli/cli_test_util.h"
#include "tests/support/test_support.h"

namespace napkin::cli {
namespace {

using namespace napkin::test_support;

TEST(CliIsoMmeAccelerationOnly, ExportWritesTheCgAccelerationAndReimportsToTheSameChannels) {
  TempDir dir;
  ASSERT_EQ(RunNapkin(dir.path(), {"init"}).exit_code, 0);
  synth::RandomMotionOptions motion;
  motion.seed = 311;
  motion.duration_s = 0.05;
  formats::WriteSignalsCsv(synth::SynthRandomMotion(formats::LoadArray("3a-cg"), motion).signals,
                           dir / "a1.csv");
  ASSERT_EQ(RunNapkin(dir.path(), {"import", "--array", "3a-cg", "a1.csv"}).exit_code, 0);
  // Bit-exact derived channels (docs/formats.md "Derived-channel storage").
  WriteText(dir / "float64.json", R"({"name": "float64", "storage": {"derived_channels": "float64"}})");
  ASSERT_EQ(RunNapkin(dir.path(), {"run", "--config", "float64.json"}).exit_code, 0);

  const RunResult exported =
      RunNapkin(dir.path(), {"export", "--test", "a1", "--config", "float64.json", "--format", "isomme",
                             "--out", "iso", "--dummy-type", "H3"});
  ASSERT_EQ(exported.exit_code, 0) << exported.err;

  db::Catalogue catalogue = OpenForReading(dir / "napkin.db");
  const db::TestId test = *catalogue.FindTestByExternalId("a1");
  const std::optional<db::ConfigId> config = catalogue.ReadLatestResultConfig(test);
  ASSERT_TRUE(config.has_value());
  const engine::Kinematics stored = *catalogue.ReadKinematics(test, *config);
  const formats::IsoMmeTest back = formats::ReadIsoMme(dir / "iso");
  ASSERT_EQ(back.channels.size(), 4u);
  const char* codes[4] = {"11HEAD0000H3ACXA", "11HEAD0000H3ACYA", "11HEAD0000H3ACZA", "11HEAD0000H3ACRA"};
  const double g_per_si = 1.0 / engine::kStandardGravity;
  for (int c = 0; c < 4; ++c) {
    const formats::RawChannel& channel = back.channels[static_cast<std::size_t>(c)];
    EXPECT_EQ(channel.code, codes[c]);
    EXPECT_EQ(channel.unit, "g");
    EXPECT_EQ(channel.prefiltered_cfc, 1000.0);
    EXPECT_EQ(channel.dt_s, 1e-4);
    EXPECT_EQ(channel.t0_s, stored.time_s[0]);
    ASSERT_EQ(static_cast<Eigen::Index>(channel.values.size()), stored.size());
    for (Eigen::Index k = 0; k < stored.size(); ++k) {
      // The stored channel, in g, as written: the shortest exact decimal reads back the same double.
      const double expected =
          c < 3 ? stored.acc_body(k, c) * g_per_si : stored.acc_body.row(k).norm() * g_per_si;
      ASSERT_EQ(channel.values[static_cast<std::size_t>(k)], expected) << codes[c] << " sample " << k;
    }
  }

  // Re-imported (the default map takes the x, y, z channels) and run without conditioning: the
  // same acceleration and criteria.
  const RunResult import = RunNapkin(dir.path(), {"import", "--array", "3a-cg", "iso"});
  ASSERT_EQ(import.exit_code, 0) << import.err;
  WriteText(dir / "as-exported.json",
            R"({"name": "as-exported", "filter": {"linear_cfc": "none"}, "bias": {"mode": "none"},
                "storage": {"derived_channels": "float64"}})");
  ASSERT_EQ(RunNapkin(dir.path(), {"run", "--config", "as-exported.json"}).exit_code, 0);
  const db::TestId again = *catalogue.FindTestByExternalId("iso");
  const engine::Kinematics reread =
      *catalogue.ReadKinematics(again, *catalogue.ReadLatestResultConfig(again));
  ASSERT_EQ(reread.size(), stored.size());
  for (Eigen::Index k = 0; k < stored.size(); ++k)
    for (int a = 0; a < 3; ++a)
      ASSERT_NEAR(reread.acc_body(k, a), stored.acc_body(k, a),
                  1e-12 * std::max(1.0, std::abs(stored.acc_body(k, a))))
          << "sample " << k;
  auto hic15 = [&](const char* config, const char* id) {
    const RunResult hic = RunNapkin(dir.path(), {"query", "hic", "--config", config, "--format", "json"});
    EXPECT_EQ(hic.exit_code, 0) << hic.err;
    for (const nlohmann::json& row : nlohmann::json::parse(hic.out))
      if (row.at("test_id") == id) return row.at("hic15").get<double>();
    ADD_FAILURE() << "no hic15 of " << id << " under " << config;
    return 0.0;
  };
  const double original = hic15("float64", "a1");
  EXPECT_GT(original, 0.0);
  EXPECT_NEAR(hic15("as-exported", "iso"), original, 1e-9 * original);
}

}  // namespace
}  // namespace napkin::cli
