// RunScheduler with RunOptions::results_path (`run --results`): the inputs
// come from the catalogue, which is left byte for byte as it was; the
// results file, merged back, equals the same run made in the catalogue.
#include <gtest/gtest.h>

#include <filesystem>

#include "db/job_queue.h"
#include "tests/jobs/jobs_test_helpers.h"
#include "tests/support/db/catalogue_inspector.h"
#include "tests/support/db/results_dump.h"
#include "tests/support/run_command.h"
#include "tests/support/test_support.h"

namespace napkin::jobs {
namespace {

namespace fs = std::filesystem;

TEST(ResultsFileRun, TheCatalogueIsOnlyReadAndTheMergedResultsEqualAnInPlaceRun) {
  napkin::test_support::TempDir dir;
  const std::string catalogue = dir / "catalogue.db";
  test_support::AddRandomTests(catalogue, 8, 800);
  const std::string in_place = dir / "in-place.db";
  fs::copy_file(catalogue, in_place);
  const std::string catalogue_bytes = test_support::ReadText(catalogue);

  RunOptions options;
  options.threads = 2;
  options.poll_interval_s = 0.05;
  options.scope.shard = db::Shard{1, 2};
  const RunReport in_place_report = RunScheduler(in_place, test_support::Processing(), options);
  EXPECT_EQ(in_place_report.done, 4);

  options.results_path = dir / "results.db";
  const RunReport report = RunScheduler(catalogue, test_support::Processing(), options);
  EXPECT_EQ(report.done, 4);
  EXPECT_EQ(test_support::ReadText(catalogue), catalogue_bytes);
  EXPECT_FALSE(fs::exists(catalogue + "-wal"));
  EXPECT_FALSE(fs::exists(catalogue + "-shm"));
  const RunReport again = RunScheduler(catalogue, test_support::Processing(), options);
  EXPECT_EQ(again.done, 0);
  EXPECT_EQ(again.skipped, 4);

  const std::string merged = dir / "merged.db";
  fs::copy_file(catalogue, merged);
  {
    db::Catalogue target = db::Catalogue::Open(merged);
    const db::MergeReport merge = target.MergeShard(options.results_path);
    EXPECT_EQ(merge.tests_added, 0);
    EXPECT_EQ(merge.results_merged, 4);
  }
  EXPECT_EQ(db::CanonicalResultsDump(merged), db::CanonicalResultsDump(in_place));
}

}  // namespace
}  // namespace napkin::jobs
