// napkin_catalogue_io: the two measurements bench/run_throughput.sh needs
// besides `napkin run` itself.
//
//   napkin_catalogue_io io-baseline DB [--batch N] [--storage float64|float32|none]
//     Does everything `napkin run` does to the catalogue except computing:
//     enqueue, claim under a lease, read each test's record, array and raw
//     channels, write a result row with the findings and conditioning record
//     of a real result (the first test's, computed once before the clock
//     starts) and the 36 derived channels of the test's length encoded as
//     `storage` says (none: no derived channels; the values are the raw
//     samples repeated: SQLite does not care), complete the job, N tests per
//     transaction. Prints the wall time: what SQLite alone needs for the
//     run's inputs and outputs.
//
//   napkin_catalogue_io verify DB [--sample N] [--seed S] [--config NAME]
//     Recomputes N random tests (all with N = 0) with the transform core on
//     the stored inputs (records::RecomputeResult, the path of `napkin run`
//     and of `export` for storage none) and compares the stored summary (every field and
//     finding, engine/summary_fields.h) with it bit for bit, and the stored
//     kinematics as the config's storage.derived_channels says: bit for bit
//     (float64), each value the computed one rounded to float32 (float32), or
//     none stored (none), naming what differs. Exit 1 on any difference.
#include <fmt/core.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <chrono>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "common/error.h"
#include "db/catalogue.h"
#include "db/job_queue.h"
#include "engine/pipeline.h"
#include "engine/summary_fields.h"
#include "records/array_record.h"
#include "records/config_record.h"
#include "records/test_inputs.h"
#include "util/malloc_tuning.h"

namespace {

using namespace napkin;
using SteadyClock = std::chrono::steady_clock;

double Seconds(SteadyClock::time_point start) {
  return std::chrono::duration<double>(SteadyClock::now() - start).count();
}

int IoBaseline(const std::string& path, int batch, engine::DerivedStorage storage) {
  db::Catalogue catalogue = db::Catalogue::Open(path);
  // A config of its own, so the catalogue's real results are not touched.
  engine::ProcessingConfig config;
  config.filter.padding_s = 0.0123456;
  config.storage.derived_channels = storage;
  // A real summary (findings, conditioning record of every channel), so the
  // result rows are as large as the run's; computed once, outside the clock.
  engine::TestSummary real_summary;
  {
    const std::vector<db::TestRow> tests = catalogue.ReadAllTests();
    if (tests.empty()) throw InputError("catalogue '" + path + "' has no tests.");
    const engine::ArrayGeometry array = records::DecodeArrayRecord(catalogue.ReadArray(tests[0].array_id));
    real_summary = engine::ProcessTest(array, catalogue.ReadTestSignals(tests[0].id), tests[0].initial_state,
                                       engine::ProcessingConfig{})
                       .summary;
  }
  const auto start = SteadyClock::now();
  const db::ConfigId config_id = catalogue.WriteConfig(records::MakeConfigRecord(config, "io-baseline"));
  db::JobQueue queue(catalogue);
  queue.EnqueueMissing(config_id);
  const std::string owner = "io-baseline";
  std::int64_t tests = 0, samples = 0, bytes_written = 0;
  double read_s = 0, write_s = 0;
  for (;;) {
    const auto jobs = queue.ClaimJobs(config_id, owner, batch, 600.0);
    if (jobs.empty()) break;
    struct Output {
      db::Job job;
      engine::Kinematics kinematics;
    };
    std::vector<Output> outputs;
    const auto read_start = SteadyClock::now();
    for (const db::Job& job : jobs) {
      const db::TestRow test = catalogue.ReadTest(job.test_id);
      catalogue.ReadArray(test.array_id);
      const engine::TestSignals signals = catalogue.ReadTestSignals(job.test_id);
      samples += signals.samples.size();
      Output output{job, {}};
      const Eigen::Index n = signals.size();
      output.kinematics.Resize(n);
      output.kinematics.time_s = Eigen::VectorXd::LinSpaced(n, signals.t0_s, signals.TimeAt(n - 1));
      for (engine::Series3* series :
           {&output.kinematics.omega_body, &output.kinematics.alpha_body, &output.kinematics.omega_fixed,
            &output.kinematics.alpha_fixed, &output.kinematics.acc_body, &output.kinematics.acc_fixed,
            &output.kinematics.vel_fixed, &output.kinematics.pos_fixed, &output.kinematics.roll_pitch_yaw_rad,
            &output.kinematics.dcos_rad})
        *series = signals.samples.leftCols(3);
      output.kinematics.quat_fixed_from_body = signals.samples.leftCols(4);
      output.kinematics.residual = signals.samples.col(0);
      if (storage != engine::DerivedStorage::kNone)
        bytes_written +=
            (8 + 35 * (storage == engine::DerivedStorage::kFloat32 ? 4 : 8)) * n;  // time_s float64
      outputs.push_back(std::move(output));
    }
    read_s += Seconds(read_start);
    const auto write_start = SteadyClock::now();
    db::Transaction transaction = catalogue.BeginTransaction();
    for (const Output& output : outputs) {
      engine::TestSummary summary = real_summary;
      summary.hic15.value = static_cast<double>(output.job.test_id);
      catalogue.WriteResult(output.job.test_id, config_id, summary, engine::NameOf(config.solver),
                            &output.kinematics, storage);
      queue.CompleteJob(output.job.id, owner);
    }
    transaction.Commit();
    write_s += Seconds(write_start);
    tests += static_cast<std::int64_t>(jobs.size());
  }
  const double wall = Seconds(start);
  fmt::print("io-baseline: {} tests, {} input samples read, {:.0f} MB of derived channels written ({})\n",
             tests, samples, bytes_written / 1e6, engine::NameOf(storage));
  fmt::print("io-baseline: wall {:.2f} s (read {:.2f} s, write+commit {:.2f} s)\n", wall, read_s, write_s);
  fmt::print("io_baseline_wall_s={:.3f}\n", wall);
  return 0;
}

// The kinematics as float32 storage returns them: each value rounded to the
// nearest float and widened back (exactly), but the time base, which stays
// float64 (docs/formats.md "Derived-channel storage").
engine::Kinematics RoundedToFloat32(engine::Kinematics kinematics) {
  for (auto* matrix :
       {&kinematics.omega_body, &kinematics.alpha_body, &kinematics.omega_fixed, &kinematics.alpha_fixed,
        &kinematics.acc_body, &kinematics.acc_fixed, &kinematics.vel_fixed, &kinematics.pos_fixed,
        &kinematics.roll_pitch_yaw_rad, &kinematics.dcos_rad})
    *matrix = matrix->cast<float>().cast<double>();
  kinematics.quat_fixed_from_body = kinematics.quat_fixed_from_body.cast<float>().cast<double>();
  kinematics.residual = kinematics.residual.cast<float>().cast<double>();
  return kinematics;
}

bool Same(const engine::Kinematics& a, const engine::Kinematics& b) {
  return a.time_s == b.time_s && a.omega_body == b.omega_body && a.alpha_body == b.alpha_body &&
         a.omega_fixed == b.omega_fixed && a.alpha_fixed == b.alpha_fixed && a.acc_body == b.acc_body &&
         a.acc_fixed == b.acc_fixed && a.vel_fixed == b.vel_fixed && a.pos_fixed == b.pos_fixed &&
         a.quat_fixed_from_body == b.quat_fixed_from_body && a.roll_pitch_yaw_rad == b.roll_pitch_yaw_rad &&
         a.dcos_rad == b.dcos_rad && a.residual == b.residual;
}

int Verify(const std::string& path, std::size_t sample, std::uint64_t seed, const std::string& config_name) {
  db::CatalogueOptions options;
  options.read_only = true;
  db::Catalogue catalogue = db::Catalogue::Open(path, options);
  const records::ResolvedConfig resolved = records::ResolveConfig(config_name);
  const engine::ProcessingConfig& config = resolved.config;
  const auto config_id = catalogue.FindConfigByHash(resolved.record.config_hash);
  if (!config_id) throw InputError("config '" + config_name + "' has no results in '" + path + "'.");
  std::vector<db::TestRow> tests = catalogue.ReadAllTests();
  if (sample > 0 && sample < tests.size()) {
    std::mt19937_64 random(seed);
    std::shuffle(tests.begin(), tests.end(), random);
    tests.resize(sample);
  }
  int equal = 0, different = 0;
  for (const db::TestRow& test : tests) {
    const engine::ProcessedTest expected = records::RecomputeResult(catalogue, test.id, *config_id);
    const auto kinematics = catalogue.ReadKinematics(test.id, *config_id);
    const auto summary = catalogue.ReadSummary(test.id, *config_id);
    std::vector<std::string> differing;
    const engine::DerivedStorage storage = config.storage.derived_channels;
    if (!summary) {
      differing.emplace_back("no result");
    } else {
      differing = engine::DifferingSummaryFields(*summary, expected.summary);
      if (storage == engine::DerivedStorage::kNone) {
        if (kinematics) differing.emplace_back("kinematics stored although storage is none");
      } else if (!kinematics) {
        differing.emplace_back("no kinematics");
      } else if (!Same(*kinematics, storage == engine::DerivedStorage::kFloat32
                                        ? RoundedToFloat32(expected.kinematics)
                                        : expected.kinematics)) {
        differing.emplace_back("kinematics");
      }
    }
    if (differing.empty()) {
      ++equal;
    } else {
      ++different;
      fmt::print("verify: test '{}' differs from the transform core: {}\n", test.external_id,
                 fmt::join(differing, ", "));
    }
  }
  fmt::print("verify: {} of {} tests equal the transform core bit for bit\n", equal, equal + different);
  return different == 0 ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
  const std::vector<std::string> args(argv + 1, argv + argc);
  auto option = [&](const std::string& name, const std::string& fallback) {
    const auto found = std::find(args.begin(), args.end(), name);
    return found != args.end() && found + 1 != args.end() ? *(found + 1) : fallback;
  };
  try {
    if (args.size() >= 2 && args[0] == "io-baseline") {
      // The malloc of `napkin run` (jobs/scheduler.cpp, keep_freed_memory), so that run / floor
      // compares the work, not two memory policies.
      util::KeepFreedMemoryForReuse();
      const std::string storage_name = option("--storage", "float64");
      const auto storage = engine::ParseName<engine::DerivedStorage>(storage_name);
      if (!storage) throw InputError("--storage takes float64, float32 or none, not '" + storage_name + "'.");
      return IoBaseline(args[1], std::stoi(option("--batch", "16")), *storage);
    }
    if (args.size() >= 2 && args[0] == "verify")
      return Verify(args[1], std::stoul(option("--sample", "20")), std::stoull(option("--seed", "1")),
                    option("--config", "default"));
  } catch (const std::exception& error) {
    fmt::print(stderr, "napkin_catalogue_io: {}\n", error.what());
    return 1;
  }
  fmt::print(
      stderr,
      "usage: napkin_catalogue_io io-baseline DB [--batch N] [--storage float64|float32|none] | verify DB "
      "[--sample N] [--seed S] [--config NAME]\n");
  return 2;
}
