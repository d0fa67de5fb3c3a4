#include "jobs/scheduler.h"

#include <oneapi/tbb/global_control.h>
#include <oneapi/tbb/info.h>
#include <oneapi/tbb/parallel_pipeline.h>
#include <oneapi/tbb/task_arena.h>
#include <spdlog/spdlog.h>

#include <exception>
#include <optional>
#include <stdexcept>

#include "db/results_file.h"
#include "jobs/job_reader.h"
#include "jobs/lease_keeper.h"
#include "jobs/result_writer.h"
#include "jobs/run_context.h"
#include "jobs/test_computation.h"
#include "util/malloc_tuning.h"

namespace napkin::jobs {

engine::ProcessedTest ComputeInThreadWorkspace(const records::TestInputs& inputs,
                                               const engine::ProcessingConfig& config) {
  thread_local engine::Workspace workspace;
  engine::ProcessedTest processed;
  // Without derived channels to store, the writer keeps only the summary
  // (jobs/test_computation.cpp): the series nobody reads are not computed.
  const engine::SeriesKept series = config.storage.derived_channels == engine::DerivedStorage::kNone
                                        ? engine::SeriesKept::kSummary
                                        : engine::SeriesKept::kAll;
  records::ComputeResult(inputs, config, workspace, processed, series);
  return processed;
}

void RunOptions::Check() const {
  auto require = [](bool ok, const char* what) {
    if (!ok) throw std::invalid_argument(std::string("RunOptions: ") + what);
  };
  require(threads >= 0, "threads must be >= 0 (0 = all cores)");
  require(tests_in_flight_per_thread >= 1, "tests_in_flight_per_thread must be >= 1");
  require(claim_batch >= 1, "claim_batch must be >= 1");
  require(commit_batch >= 1, "commit_batch must be >= 1");
  require(commit_interval_s > 0.0, "commit_interval_s must be positive");
  require(lease_s > 0.0, "lease_s must be positive");
  require(poll_interval_s > 0.0, "poll_interval_s must be positive");
  require(static_cast<bool>(compute), "compute must be set");
}

RunReport RunScheduler(const std::string& db_path, const records::ResolvedConfig& processing,
                       const RunOptions& options, const ProgressCallback& progress,
                       const std::atomic<bool>* stop) {
  options.Check();
  processing.config.Check();
  RunContext context(processing, options,
                     options.threads > 0 ? options.threads : tbb::info::default_concurrency(), progress,
                     stop);
  // Freed results are reused by the next test (util/malloc_tuning.h; RunOptions::keep_freed_memory).
  if (options.keep_freed_memory && !util::KeepFreedMemoryForReuse())
    spdlog::debug("run: malloc tuning (mallopt) not applied");

  RunReport& report = context.report;
  report.owner = MakeOwnerId();
  const LiveOwnerScope live_owner(report.owner);

  // Jobs and results live in the work catalogue: the catalogue, or a results
  // file beside the shared read-only catalogue (`inputs`).
  const bool results_file = !options.results_path.empty();
  context.work_path = results_file ? options.results_path : db_path;
  std::optional<db::Catalogue> inputs;
  if (results_file) inputs.emplace(db::ResultsFile::OpenSharedCatalogue(db_path));
  db::Catalogue reader_catalogue =
      results_file ? db::ResultsFile::Open(context.work_path, *inputs) : db::Catalogue::Open(db_path);
  if (results_file) db::ResultsFile::CopyTests(*inputs, reader_catalogue, options.scope);
  db::JobQueue reader_queue(reader_catalogue);
  report.config = reader_catalogue.WriteConfig(processing.record);
  reader_queue.EnqueueMissing(report.config, options.scope, options.force, options.outdated);
  {
    const db::StatusCounts counts = reader_queue.ReadStatusCounts(report.config, options.scope);
    report.total = counts.pending + counts.running;
    report.skipped = counts.done;
  }
  spdlog::info("run {}: config '{}' ({}), {} tests to process, {} up to date, {} threads", report.owner,
               processing.record.name, processing.record.config_hash.substr(0, 12), report.total,
               report.skipped, report.threads);

  db::Catalogue writer_catalogue = db::Catalogue::Open(context.work_path);
  ReadyQueue ready;
  std::exception_ptr error;
  {
    // Declared first, so it renews the leases until the writer has committed the last batch.
    LeaseKeeper lease_keeper(context);
    ResultWriter writer(context, writer_catalogue);
    JobReader reader(context, inputs ? *inputs : reader_catalogue, reader_catalogue, ready, writer);
    try {
      // The compute threads: an arena of exactly `threads`; reading and
      // writing happen on the two threads above, never on these.
      tbb::global_control parallelism(tbb::global_control::max_allowed_parallelism,
                                      static_cast<std::size_t>(report.threads));
      tbb::task_arena arena(report.threads);
      arena.execute([&] {
        tbb::parallel_pipeline(
            static_cast<std::size_t>(report.max_tests_in_flight),
            tbb::make_filter<void, ItemPtr>(tbb::filter_mode::serial_in_order,
                                            [&](tbb::flow_control& control) {
                                              ItemPtr item = ready.Pop();
                                              if (!item) control.stop();
                                              return item;
                                            }) &
                tbb::make_filter<ItemPtr, ItemPtr>(tbb::filter_mode::parallel,
                                                   [&](ItemPtr item) {
                                                     ComputeTest(*item, context);
                                                     return item;
                                                   }) &
                tbb::make_filter<ItemPtr, void>(tbb::filter_mode::serial_out_of_order,
                                                [&](ItemPtr item) { writer.Push(std::move(item)); }));
      });
    } catch (...) {
      error = std::current_exception();
      context.state.Abort();
    }
    // The reader ends once the pipeline has (or on the abort); then the
    // writer commits what the pipeline handed it.
    const std::exception_ptr read_error = reader.Join();
    const std::exception_ptr write_error = writer.Join();
    if (!error) error = read_error ? read_error : write_error;
    report.stopped = reader.stopped();
  }
  if (error) {
    // Give our jobs back so another run need not wait for the leases.
    try {
      reader_queue.ReleaseLeases(report.config, report.owner);
    } catch (const std::exception& release_error) {
      // Not a second error line: the error rethrown below is what the user
      // acts on (a full disk fails this write too), and the leases expire
      // after lease_s anyway (or at once for the next run on this host).
      spdlog::debug("could not release the leases of {}: {}", report.owner, release_error.what());
    }
    std::rethrow_exception(error);
  }
  // Jobs claimed but never started (a stop) go back to the queue.
  report.released = reader_queue.ReleaseLeases(report.config, report.owner);
  report.peak_tests_in_memory = context.state.peak_in_memory();
  report.compute_s = context.compute_s.load();
  report.wall_s = SecondsSince(context.start);
  spdlog::info("run {}: {} done, {} failed, {} lost, {} released in {:.1f} s", report.owner, report.done,
               report.failed, report.lost, report.released, report.wall_s);
  return report;
}

}  // namespace napkin::jobs
