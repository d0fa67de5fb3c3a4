#pragma once
// Results files (README "Batch runs", docs/formats.md "Results files"):
// `napkin run --shard I/N --results FILE.db` reads a catalogue that many
// processes share read-only (on a cluster's shared file system) and writes
// the shard's results into FILE.db, a small catalogue of the same schema
// holding, for the tests of the shard, their rows (keys as in the catalogue,
// content hash included), series and arrays, but no raw channels; and the
// config, jobs, results, findings, conditioning records and derived
// channels the run computed. `napkin merge FILE.db...` takes them back into
// the catalogue (Catalogue::MergeShard), matching tests by content hash.
#include <cstdint>
#include <string>

#include "db/catalogue.h"
#include "db/job_queue.h"

namespace napkin::db {

class ResultsFile {
 public:
  // Opens the catalogue at `path` for reading only, immutable: no lock is
  // taken and no file is ever created beside it, so it works in a read-only
  // directory and on a shared file system read by many nodes at once. Throws
  // InputError (one sentence) when it does not exist, is not a napkin
  // catalogue of this schema version, or has changes still in its -wal file
  // (an immutable reader would not see them; the sentence says how to fold
  // them in). Nothing may write the catalogue while it is open this way.
  static Catalogue OpenSharedCatalogue(const std::string& path);

  // Opens the results file at `results_path`, creating and migrating it when
  // missing, for a run reading `catalogue`. Throws InputError (one sentence)
  // when the path is a directory, its directory does not exist or may not be
  // written, or it is `catalogue`'s own file under any name (device and inode
  // compared, as MergeShard does).
  static Catalogue Open(const std::string& results_path, const Catalogue& catalogue,
                        const CatalogueOptions& options = {});

  // Copies the rows of the tests of `scope` in `catalogue` into `results`
  // with their keys (so the shard rule, key % N, selects the same tests in
  // both), and the series and arrays they name, in one transaction; raw
  // channels stay in the catalogue. Rows already there are kept. Returns
  // the number of tests copied. Throws InputError naming both files when
  // `results` holds a test, series or array of the same key with other
  // content, or the same content under another key (a results file written
  // for another catalogue).
  static std::int64_t CopyTests(Catalogue& catalogue, Catalogue& results, const JobScope& scope);
};

}  // namespace napkin::db
