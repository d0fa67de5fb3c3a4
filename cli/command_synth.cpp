// `napkin synth`: add synthetic tests with exact known answers to the
// catalogue (report scenarios 4.4 and 4.5, random motions, a padding series of
// oblique head impacts), one transaction per test, idempotent by content hash.
#include <fmt/core.h>

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "cli/catalogue_option.h"
#include "cli/command.h"
#include "cli/option_checks.h"
#include "cli/progress.h"
#include "ingest/synthetic_import.h"
#include "synth/synthetic_tests.h"

namespace napkin::cli {
namespace {

class SynthCommand : public Command {
 public:
  CLI::App* Setup(CLI::App& app, const GlobalOptions& global) override {
    global_ = &global;
    CLI::App* sub =
        app.add_subcommand("synth", "add synthetic tests with exact known answers to the catalogue");
    std::vector<std::string> scenarios;
    for (const synth::SynthScenario scenario : synth::kSynthScenarios)
      scenarios.push_back(synth::SynthScenarioName(scenario));
    sub->add_option("--scenario", scenario_,
                    "seed-fixed-axis (report 4.5), seed-sequential (report 4.4), random, padding-series")
        ->required()
        ->check(OneOfCheck("--scenario", scenarios));
    sub->add_option("--count", request_.count,
                    "random: number of tests (default 1); padding-series: repeats per variant (default 5)")
        ->check(WholeNumberCheck("--count", 1));
    sub->add_option("--seed", request_.seed, "generator seed of the first test")->capture_default_str();
    sub->add_option("--array", request_.array, "array preset name or array JSON file")
        ->capture_default_str()
        ->check(PathCheck("--array"));
    sub->add_option("--series", request_.series, "series label (default: the scenario name)");
    sub->add_option("--test-id", request_.test_id,
                    "test id, or prefix of numbered ids (default: the scenario name)");
    auto* samples = sub->add_option("--samples", request_.samples, "random: samples per channel")
                        ->check(WholeNumberCheck("--samples", 2, 100000000));
    sub->add_option("--duration", request_.duration_s, "random: duration in s (default 0.2)")
        ->check(PositiveNumberCheck("--duration"))
        ->excludes(samples);
    sub->add_option("--rate", request_.rate_hz, "sampling rate in Hz")
        ->check(PositiveNumberCheck("--rate"))
        ->capture_default_str();
    return sub;
  }

  int Run() override {
    request_.scenario = *synth::ParseSynthScenario(scenario_);  // checked by OneOfCheck
    const ingest::SynthPlan plan = ingest::PlanSynth(request_);
    db::Catalogue catalogue = OpenCatalogue(*global_);
    // Tests done, rate and time left: a bar on a terminal, a log line every 10 s otherwise.
    std::optional<ProgressBar> progress_bar;
    ProgressLog progress_log("synth", !global_->quiet && !StderrIsTerminal(), /*final_always=*/false);
    const auto start = std::chrono::steady_clock::now();
    const ingest::SynthCounts counts =
        ingest::StoreSynthTests(catalogue, plan, [&](std::size_t done, std::size_t total) {
          if (!progress_bar) progress_bar.emplace(total, ProgressBar::WantedOnStderr(global_->quiet));
          progress_bar->Update(done, "");
          progress_log.Update(
              static_cast<std::int64_t>(done), 0, static_cast<std::int64_t>(total),
              std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
        });
    progress_bar.reset();
    fmt::print("{}: {} synthetic test{} added, {} already present (scenario {}, series '{}').\n",
               global_->db_path, counts.added, counts.added == 1 ? "" : "s", counts.present, scenario_,
               plan.series);
    return kExitOk;
  }

 private:
  const GlobalOptions* global_ = nullptr;
  std::string scenario_;  // seed-fixed-axis, seed-sequential, random, padding-series
  ingest::SynthRequest request_;
};

}  // namespace

std::unique_ptr<Command> MakeSynthCommand() { return std::make_unique<SynthCommand>(); }

}  // namespace napkin::cli
