// `napkin synth`: add synthetic tests with exact known answers to the
// catalogue (report scenarios 4.4 and 4.5, random motions, a padding-variant
// series), one transaction per test, idempotent by content hash.
#include <fmt/core.h>

#include <cstring>
#include <nlohmann/json.hpp>
#include <optional>
#include <span>
#include <vector>

#include "cli/array_record.h"
#include "cli/catalogue_access.h"
#include "cli/command.h"
#include "engine/error.h"
#include "engine/synth.h"
#include "formats/array_json.h"
#include "formats/content_hash.h"

namespace napkin::cli {
namespace {

struct SynthOptions {
  std::string scenario;           // seed-fixed-axis, seed-sequential, random, padding-variants
  int count = 1;                  // random: tests; padding-variants: repeats per variant
  std::uint64_t seed = 1;         // random generator seed of the first test
  std::string array = "ideal-3222";  // array preset or JSON file the signals are generated for
  std::string series;             // series label (default: the scenario name)
  std::string test_id;            // test id, or the prefix of numbered ids (default: the scenario name)
  std::optional<int> samples;     // random, padding-variants: samples per channel
  std::optional<double> duration_s;  // ... or duration (default 0.2 s)
  double rate_hz = 10000.0;       // sampling rate
};

// Identity of a synthetic test's content: array, initial state, time base,
// slot names and the samples' bytes.
std::string ContentHash(const db::ArrayRecord& array, const engine::SyntheticTest& test) {
  formats::Sha256 hash;
  hash.Update("napkin synthetic test\n");
  hash.Update(array.definition_hash);
  for (const std::string& slot : test.signals.slots) {
    hash.Update("\n");
    hash.Update(slot);
  }
  auto update = [&](const double* values, std::size_t count) {
    hash.Update(std::span<const std::uint8_t>(reinterpret_cast<const std::uint8_t*>(values), count * sizeof(double)));
  };
  const engine::InitialState& initial = test.initial;
  const double header[11] = {test.signals.dt_s,           test.signals.t0_s,           initial.orientation_rad[0],
                             initial.orientation_rad[1],  initial.orientation_rad[2],  initial.velocity_fixed_mps[0],
                             initial.velocity_fixed_mps[1], initial.velocity_fixed_mps[2], initial.omega_body_radps[0],
                             initial.omega_body_radps[1], initial.omega_body_radps[2]};
  update(header, 11);
  update(test.signals.samples.data(), static_cast<std::size_t>(test.signals.samples.size()));
  return hash.HexDigest();
}

struct Labels {
  std::string external_id;
  std::string series;
  std::optional<std::string> variant;
  nlohmann::json metadata;
};

class SynthCommand : public Command {
 public:
  CLI::App* Setup(CLI::App& app, const GlobalOptions& global) override {
    global_ = &global;
    CLI::App* sub = app.add_subcommand("synth", "add synthetic tests with exact known answers to the catalogue");
    sub->add_option("--scenario", options_.scenario,
                    "seed-fixed-axis (report 4.5), seed-sequential (report 4.4), random, padding-variants")
        ->required()
        ->check(CLI::IsMember({"seed-fixed-axis", "seed-sequential", "random", "padding-variants"}));
    sub->add_option("--count", options_.count, "random: number of tests; padding-variants: repeats per variant")
        ->check(CLI::PositiveNumber)
        ->capture_default_str();
    sub->add_option("--seed", options_.seed, "seed of the first random motion")->capture_default_str();
    sub->add_option("--array", options_.array, "array preset name or array JSON file")->capture_default_str();
    sub->add_option("--series", options_.series, "series label (default: the scenario name)");
    sub->add_option("--test-id", options_.test_id, "test id, or prefix of numbered ids (default: the scenario name)");
    auto* samples = sub->add_option("--samples", options_.samples, "random, padding-variants: samples per channel")
                        ->check(CLI::Range(2, 100000000));
    sub->add_option("--duration", options_.duration_s, "random, padding-variants: duration in s (default 0.2)")
        ->check(CLI::PositiveNumber)
        ->excludes(samples);
    sub->add_option("--rate", options_.rate_hz, "sampling rate in Hz")->check(CLI::PositiveNumber)->capture_default_str();
    return sub;
  }

  int Run() override {
    const engine::ArrayGeometry array = formats::LoadArray(options_.array);
    const db::ArrayRecord array_record = MakeArrayRecord(array);
    const std::string series = options_.series.empty() ? options_.scenario : options_.series;
    const std::string prefix = options_.test_id.empty() ? options_.scenario : options_.test_id;
    engine::SynthOptions synth;
    synth.rate_hz = options_.rate_hz;
    const bool timed = options_.scenario == "random" || options_.scenario == "padding-variants";
    if (!timed && (options_.samples || options_.duration_s))
      throw InputError("--samples and --duration apply to the random and padding-variants scenarios only; " +
                       options_.scenario + " has the report's fixed duration.");
    const double duration_s = options_.samples ? (*options_.samples - 1) / options_.rate_hz
                                               : options_.duration_s.value_or(0.2);

    db::Catalogue catalogue = OpenCatalogue(*global_);
    int added = 0, present = 0;
    auto store = [&](const engine::SyntheticTest& test, const Labels& labels) {
      const std::string content_hash = ContentHash(array_record, test);
      db::Transaction transaction = catalogue.BeginTransaction();
      if (catalogue.ExistsTestByHash(content_hash)) {
        ++present;
        return;
      }
      db::TestRecord record;
      record.external_id = labels.external_id;
      record.series = labels.series;
      record.variant = labels.variant;
      record.metadata_json = labels.metadata.dump();
      record.array_id = catalogue.WriteArray(array_record);
      record.initial_state = test.initial;
      record.source_path = "synth:" + options_.scenario;
      record.content_hash = content_hash;
      const db::TestId id = catalogue.WriteTest(record);
      std::vector<std::string> units;
      for (const std::string& slot : test.signals.slots) units.push_back(array.sensors[*array.FindSlot(slot)].unit);
      catalogue.WriteRawChannels(id, test.signals, units);
      transaction.Commit();
      ++added;
    };
    auto metadata = [&](std::optional<std::uint64_t> seed) {
      nlohmann::json synthetic = {{"scenario", options_.scenario}, {"rate_hz", options_.rate_hz}};
      if (seed) synthetic["seed"] = *seed;
      if (timed) synthetic["duration_s"] = duration_s;
      return nlohmann::json{{"synthetic", synthetic}};
    };
    auto numbered = [&](const std::string& stem, int number, int width) {
      return fmt::format("{}-{:0{}d}", stem, number, width);
    };

    if (options_.scenario == "seed-fixed-axis") {
      // Report 4.5: head initially at phi = theta = psi = 0.5 rad.
      store(engine::SynthSeedFixedAxis(array, Eigen::Vector3d(0.5, 0.5, 0.5), synth),
            {prefix, series, std::nullopt, metadata(std::nullopt)});
    } else if (options_.scenario == "seed-sequential") {
      store(engine::SynthSequential(array, synth), {prefix, series, std::nullopt, metadata(std::nullopt)});
    } else if (options_.scenario == "random") {
      const int width = std::max(4, static_cast<int>(std::to_string(options_.count).size()));
      for (int i = 0; i < options_.count; ++i) {
        engine::RandomMotionOptions motion;
        motion.seed = options_.seed + static_cast<std::uint64_t>(i);
        motion.duration_s = duration_s;
        motion.synth = synth;
        store(engine::SynthRandomMotion(array, motion),
              {numbered(prefix, i + 1, width), series, std::nullopt, metadata(motion.seed)});
      }
    } else {
      // The same impacts (one seed per repeat) with three paddings that
      // scale the head's load: production trim, then foams A and B.
      struct Variant {
        const char* name;
        double load_factor;
      };
      constexpr Variant kVariants[] = {{"production", 1.0}, {"foam-a", 0.8}, {"foam-b", 0.65}};
      for (const Variant& variant : kVariants)
        for (int r = 0; r < options_.count; ++r) {
          engine::RandomMotionOptions motion;
          motion.seed = options_.seed + static_cast<std::uint64_t>(r);
          motion.duration_s = duration_s;
          motion.peak_acc_g *= variant.load_factor;
          motion.peak_omega_radps *= variant.load_factor;
          motion.synth = synth;
          nlohmann::json meta = metadata(motion.seed);
          meta["synthetic"]["load_factor"] = variant.load_factor;
          store(engine::SynthRandomMotion(array, motion),
                {numbered(prefix + "-" + variant.name, r + 1, 2), series, std::string(variant.name), meta});
        }
    }
    fmt::print("{}: {} synthetic test{} added, {} already present (scenario {}, series '{}').\n", global_->db_path,
               added, added == 1 ? "" : "s", present, options_.scenario, series);
    return kExitOk;
  }

 private:
  const GlobalOptions* global_ = nullptr;
  SynthOptions options_;
};

}  // namespace

std::unique_ptr<Command> MakeSynthCommand() { return std::make_unique<SynthCommand>(); }

}  // namespace napkin::cli
