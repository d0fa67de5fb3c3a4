#include "jobs/result_writer.h"

#include <spdlog/spdlog.h>

#include <algorithm>

namespace napkin::jobs {
namespace {

// The write-ahead log is restarted once longer than this (64 MiB, SQLite's
// journal_size_limit of the catalogue: the file is cut back to it).
constexpr std::int64_t kMaxWalBytes = 64 << 20;

}  // namespace

ResultWriter::ResultWriter(RunContext& context, db::Catalogue& results)
    : context_(context),
      catalogue_(results),
      queue_(results),
      // Commit once the queue holds this many tests: waiting for more would
      // leave fewer than two tokens per thread for reading and computing.
      commit_target_(
          static_cast<std::size_t>(std::clamp(context.report.max_tests_in_flight - 2 * context.report.threads,
                                              1, std::max(1, context.options.commit_batch)))),
      thread_([this] { Loop(); }) {}

void ResultWriter::Push(ItemPtr item) {
  {
    std::lock_guard lock(mutex_);
    queue_items_.push_back(Queued{std::move(item), SteadyClock::now()});
  }
  changed_.notify_one();
}

void ResultWriter::RequestFlush() {
  {
    std::lock_guard lock(mutex_);
    flush_requested_ = true;
  }
  changed_.notify_one();
}

std::exception_ptr ResultWriter::Join() {
  {
    std::lock_guard lock(mutex_);
    closed_ = true;
  }
  changed_.notify_one();
  if (thread_.joinable()) thread_.join();
  return error_;
}

void ResultWriter::Loop() {
  const RunOptions& options = context_.options;
  for (;;) {
    std::vector<ItemPtr> batch;
    {
      std::unique_lock lock(mutex_);
      for (;;) {
        if (queue_items_.empty()) {
          if (closed_) return;
          flush_requested_ = false;
          changed_.wait(lock);
          continue;
        }
        if (closed_ || flush_requested_ || queue_items_.size() >= commit_target_) break;
        const auto due =
            queue_items_.front().arrived + std::chrono::duration_cast<SteadyClock::duration>(
                                               std::chrono::duration<double>(options.commit_interval_s));
        if (SteadyClock::now() >= due) break;
        changed_.wait_until(lock, due);
      }
      flush_requested_ = false;
      const std::size_t count = std::min(queue_items_.size(), static_cast<std::size_t>(options.commit_batch));
      for (std::size_t i = 0; i < count; ++i) {
        batch.push_back(std::move(queue_items_.front().item));
        queue_items_.pop_front();
      }
    }
    // The batch leaves the tokens' count: the reader may read the next tests.
    context_.state.ReleaseTokens(static_cast<int>(batch.size()));
    if (!error_) {
      try {
        Commit(batch);
      } catch (...) {
        // The run ends; the tests that reach the queue from now on are dropped.
        error_ = std::current_exception();
        context_.state.Abort();
      }
    }
    if (error_) context_.state.Committed(static_cast<int>(batch.size()));
  }
}

void ResultWriter::Commit(const std::vector<ItemPtr>& batch) {
  const auto write_start = SteadyClock::now();
  RunReport& report = context_.report;
  const engine::ProcessingConfig& config = context_.processing.config;
  std::vector<Outcome> outcomes;
  outcomes.reserve(batch.size());
  {
    db::Transaction transaction = catalogue_.BeginTransaction();
    for (const ItemPtr& item : batch) {
      db::Transaction test = catalogue_.BeginTransaction();  // a savepoint: this test's rows or none
      bool held = false;
      if (item->error) {
        if (!item->processed.summary.findings.empty())
          catalogue_.WriteFindings(item->job.test_id, report.config, item->processed.summary.findings);
        held = queue_.FailJob(item->job.id, report.owner, *item->error);
      } else {
        catalogue_.WriteResult(item->job.test_id, report.config, item->processed.summary,
                               engine::NameOf(config.solver), &item->processed.kinematics,
                               config.storage.derived_channels);
        held = queue_.CompleteJob(item->job.id, report.owner);
      }
      // Without the lease another worker owns the job now: drop our rows.
      if (held) test.Commit();
      outcomes.push_back(!held ? Outcome::kLost : item->error ? Outcome::kFailed : Outcome::kDone);
    }
    transaction.Commit();
  }
  // The reader never pauses, so the log would otherwise grow by every
  // byte written (db::Catalogue::RestartWalIfLonger).
  catalogue_.RestartWalIfLonger(kMaxWalBytes);
  // Counted only once durable.
  for (std::size_t i = 0; i < batch.size(); ++i) {
    const WorkItem& item = *batch[i];
    context_.leases.Remove(item.job.id);
    switch (outcomes[i]) {
      case Outcome::kDone:
        ++report.done;
        report.samples += item.samples;
        break;
      case Outcome::kFailed:
        ++report.failed;
        report.samples += item.samples;
        spdlog::warn("test '{}' failed: {}", item.inputs.external_id, *item.error);
        break;
      case Outcome::kLost:
        ++report.lost;
        spdlog::warn("test '{}': the job's lease passed to another worker; its result was not stored",
                     item.inputs.external_id);
        break;
    }
  }
  context_.state.Committed(static_cast<int>(batch.size()));
  report.write_s += SecondsSince(write_start);
  if (context_.progress)
    context_.progress(RunProgress{report.total, report.done, report.failed, SecondsSince(context_.start)});
}

}  // namespace napkin::jobs
