#include "jobs/job_reader.h"

#include <spdlog/spdlog.h>

namespace napkin::jobs {

JobReader::JobReader(RunContext& context, db::Catalogue& inputs, db::Catalogue& jobs, ReadyQueue& ready,
                     ResultWriter& writer)
    : context_(context), inputs_(inputs), queue_(jobs), ready_(ready), writer_(writer), thread_([this] {
        Loop();
      }) {}

std::exception_ptr JobReader::Join() {
  if (thread_.joinable()) thread_.join();
  return error_;
}

void JobReader::Loop() {
  try {
    while (!Stopping()) {
      if (!context_.state.AcquireToken(std::chrono::milliseconds(50))) continue;
      if (claimed_.empty() && !Claim()) {
        context_.state.ReleaseTokens(1);
        break;
      }
      ready_.Push(ReadNext());
    }
  } catch (...) {
    error_ = std::current_exception();
    context_.state.Abort();
  }
  ready_.Close();
}

ItemPtr JobReader::ReadNext() {
  const auto read_start = SteadyClock::now();
  auto item = std::make_unique<WorkItem>();
  item->job = claimed_.front();
  claimed_.pop_front();
  // An array that cannot be decoded fails the test when it is computed.
  item->inputs = inputs_.Read(item->job.test_id);
  item->samples = static_cast<std::int64_t>(item->inputs.signals.samples.size());
  context_.state.Read();
  context_.report.read_s += SecondsSince(read_start);
  return item;
}

// True once a stop is requested (or a stage failed): no more claims.
bool JobReader::Stopping() {
  if (context_.stop != nullptr && context_.stop->load()) stopped_ = true;
  return stopped_ || context_.state.aborted();
}

// Claims the next jobs; while none is claimable but other workers still
// hold jobs in scope, waits for them (their jobs come back if they die).
// False when nothing is left (or a stop was requested).
bool JobReader::Claim() {
  const RunOptions& options = context_.options;
  RunReport& report = context_.report;
  while (!Stopping()) {
    const auto jobs =
        queue_.ClaimJobs(report.config, report.owner, options.claim_batch, options.lease_s, options.scope);
    if (!jobs.empty()) {
      for (const db::Job& job : jobs) {
        context_.leases.Add(job.id);
        claimed_.push_back(job);
      }
      return true;
    }
    bool others_working = false;
    bool released = false;
    for (const std::string& owner : queue_.ReadLeaseOwners(report.config, options.scope)) {
      if (owner == report.owner) continue;  // our own tests in flight
      if (IsDeadLocalOwner(owner)) {
        const std::int64_t count = queue_.ReleaseLeases(report.config, owner);
        spdlog::warn("worker {} is gone: {} of its jobs go back to the queue", owner, count);
        report.reclaimed += count;
        released = released || count > 0;
      } else {
        others_working = true;
      }
    }
    if (released) continue;
    if (!others_working) return false;
    // Nothing to compute here for a while: make our finished results
    // durable rather than keep them waiting for the next batch.
    writer_.RequestFlush();
    const auto wait_start = SteadyClock::now();
    while (!Stopping() && SecondsSince(wait_start) < options.poll_interval_s)
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return false;
}

}  // namespace napkin::jobs
