#pragma once
// The transform core: everything napkin does to one test, from raw signals
// to kinematics, criteria and screening findings, and whether it fails.
// `napkin transform` and the batch scheduler (jobs/) both call ProcessTest
// and FailingFinding, so a catalogue result (or failure) equals the
// single-test result (or error) for the same input and configuration.
#include <atomic>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "common/error.h"
#include "engine/array_geometry.h"
#include "engine/criteria.h"
#include "engine/kinematics.h"
#include "engine/processing.h"
#include "engine/signals.h"
#include "engine/summary.h"

namespace napkin::engine {

struct ProcessedTest {
  Kinematics kinematics;
  TestSummary summary;
};

// The memory ProcessTest works in, kept from one test to the next by its
// caller (one per thread: a workspace is used by one computation at a time).
// With it, and a ProcessedTest kept too, a loop over tests of one length
// allocates and frees no large block, so it maps no new page whatever
// glibc's malloc does with freed memory (docs/architecture.md "Memory"): a
// page fault costs about as much as the arithmetic on the page's samples.
// Holds no result: its contents between two calls mean nothing.
struct Workspace {
  TestSignals signals;          // the conditioned copy of the raw signals
  Eigen::VectorXd filter_work;  // the CFC filters' padded channels
  Kinematics exact;             // the exact solve that judges a seed solver's result
  CriteriaWork criteria;        // the resultant, HIC's integral and tree, a3ms, DAMAGE
  // The RMS rigid-body residual of the last exact solve (m/s^2; NaN before
  // one, +infinity when it diverged): the salvage record's before and after.
  double exact_rms_residual_mps2 = 0.0;
};

// Screening of the raw signals (engine/screening.h) -> conditioning (time
// shift, bias, CFC filters, crop) -> solver -> rigid-body screening ->
// summary -> injury criteria; summary.findings holds every finding. A
// faulty channel (engine/salvage.h) fails the test with its finding, whose
// sentence says what salvage would do, unless config.screening.salvage
// excludes or repairs it: the result is then that of the salvaged signals,
// summary.salvage its record (and `repaired` the repaired channels). Throws
// InputError naming the slot, sample or setting at fault: ScreeningFailure
// (with the findings) on a missing channel or a non-finite sample (the
// screening sentence), and when the solved kinematics diverge after an
// implausible sample (quoting the screening error that explains it).
// `cancel` (null: never) stops it: read between the stages and every
// kCancellationStride samples of the long loops (filters, solvers, HIC
// search), it makes ProcessTest throw Cancelled within milliseconds of being
// set (engine/cancellation.h).
ProcessedTest ProcessTest(const ArrayGeometry& array, const TestSignals& raw_signals,
                          const InitialState& initial, const ProcessingConfig& config,
                          const std::atomic<bool>* cancel = nullptr);

// The derived series a ProcessTest computes: all of them, or those the
// summary, the criteria and the screening read (SolveOptions::
// summary_series_only: omega_fixed, alpha_fixed, roll_pitch_yaw_rad and
// dcos_rad left empty), for a caller that keeps only the summary (a run
// that stores no derived channels, jobs/scheduler.cpp). The summary is the
// same, bit for bit.
enum class SeriesKept { kAll, kSummary };

// ProcessTest in the caller's memory: `workspace` for what it computes along
// the way, `out` for the result (its series overwritten in place, the
// summary replaced). The same result, bit for bit; on a throw `out` holds
// no result.
void ProcessTest(const ArrayGeometry& array, const TestSignals& raw_signals, const InitialState& initial,
                 const ProcessingConfig& config, Workspace& workspace, ProcessedTest& out,
                 const std::atomic<bool>* cancel = nullptr, SeriesKept series = SeriesKept::kAll);

// An upper estimate of the memory ProcessTest takes at its peak for `samples`
// samples (sampling interval dt_s) of `array` under `config`, besides its
// input: the conditioned copy of the signals, the filters' padded work
// columns, the solver's working series (the seed solver's and the exact
// solve that judges it), the kinematics it returns (36 series, 4 for an
// acceleration-only array) and the HIC search's integral and tree. A caller
// compares it (plus what it holds itself) with the memory available before
// starting work that cannot fit (python/ transform; util/available_memory.h).
std::uint64_t ProcessTestBytes(const ArrayGeometry& array, Eigen::Index samples, double dt_s,
                               const ProcessingConfig& config);

// Whether a processed test fails: it fails on its first error-severity
// finding (README "What it computes": data screening: a flipped or swapped
// channel, saturation), whose detail is the failure sentence; nullptr when
// it passes. `napkin run` records that sentence as the test's failure (with
// the findings), `napkin transform` exits 1 with it and writes nothing.
const Finding* FailingFinding(const ProcessedTest& processed);

// A test that fails screening: its what() is the failing finding's sentence
// (FailingFinding's detail, or the fatal or implausible finding ProcessTest
// stops on), findings() what screening found up to then, the failing finding
// among them, so that a front end can show them (napkin.ScreeningFailure's
// .findings) rather than the one sentence only.
class ScreeningFailure : public InputError {
 public:
  ScreeningFailure(const std::string& sentence, std::vector<Finding> findings)
      : InputError(sentence), findings_(std::move(findings)) {}
  const std::vector<Finding>& findings() const { return findings_; }

 private:
  std::vector<Finding> findings_;
};

}  // namespace napkin::engine
