#pragma once
// The napkin catalogue: typed repositories over one SQLite file (schema/).
// Verb+entity methods as in COLMAP's Database (Write/Read/ReadAll/Exists...).
// Every write runs in a transaction that rolls back on an exception; several
// writes can be made atomic together with BeginTransaction() (they nest as
// savepoints). All values are bound as SQL parameters.
//
// A Catalogue is not thread-safe: give each thread (or process) its own; they
// may share one file (WAL, busy timeout, atomic job claims).
#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <variant>
#include <vector>

#include "db/query_kinds.h"
#include "db/sqlite.h"
#include "db/where_expression.h"
#include "engine/kinematics.h"
#include "engine/processing.h"
#include "engine/signals.h"
#include "engine/summary.h"
#include "engine/vocabulary.h"
#include "schema/migrations.h"

namespace napkin::db {

// Catalogue keys (SQLite rowids), typed so a test key cannot be passed where
// a config key is expected.
enum class SeriesId : std::int64_t {};
enum class ArrayId : std::int64_t {};
enum class TestId : std::int64_t {};
enum class ConfigId : std::int64_t {};

struct SeriesRow {
  SeriesId id{};
  std::string name;
  std::string description;
};

// An accelerometer array definition (docs/formats.md), deduplicated by hash.
// Its name tells one geometry: a second definition under a name already
// taken is stored as HashQualifiedArrayName (WriteArray).
struct ArrayRow {
  ArrayId id{};                 // set by WriteArray / ReadArray
  std::string name;             // e.g. "denton-3222"
  std::string definition_json;  // canonical JSON
  std::string definition_hash;  // hash of definition_json (computed by the caller)
};

// "NAME@HASH12": an array's name followed by the first 12 hex digits of its
// definition hash, the name of a geometry whose plain name is another's.
std::string HashQualifiedArrayName(const std::string& name, const std::string& definition_hash);

// A processing configuration, deduplicated by hash.
struct ConfigRow {
  ConfigId id{};            // set by WriteConfig / ReadConfig
  std::string name;         // e.g. "default"
  std::string config_json;  // canonical JSON
  std::string config_hash;  // hash of config_json (computed by the caller)
  std::string created_at;   // ISO-8601 UTC, set by WriteConfig
};

struct TestRow {
  TestId id{};                        // set by WriteTest / ReadTest
  std::string external_id;            // the user's test id ("v0001"); unique
  std::optional<std::string> series;  // series name; created on write if new
  std::optional<std::string> variant;
  std::string metadata_json = "{}";  // free JSON object
  ArrayId array_id{};
  engine::InitialState initial_state;
  std::string source_path;   // file or folder the test was imported from
  std::string content_hash;  // hash of the imported content; unique
  std::string imported_at;   // ISO-8601 UTC, set by WriteTest
};

// Which tests an operation covers: the one selection of tests of every
// command and front end (run, query, report, compare, correlate, status; the
// service's and Python's parameters of the same names). A test is selected
// when its series is one of `series`, its variant one of `variants` and its id
// one of `external_ids`; an empty member does not filter.
struct TestFilter {
  std::vector<std::string> series;
  std::vector<std::string> variants;
  std::vector<std::string> external_ids;
  bool empty() const { return series.empty() && variants.empty() && external_ids.empty(); }
};

struct RawChannelInfo {
  std::string slot;
  std::string unit;
  double dt_s = 0.0;
  double t0_s = 0.0;
  std::int64_t sample_count = 0;
};

// `napkin query` tables: the kinds, their columns and what their rows are read
// from are the table of db/query_kinds.h; column names are the query contract.
using Cell = std::variant<std::monostate, std::int64_t, double, std::string>;  // monostate: NULL
struct Table {
  std::vector<std::string> columns;
  std::vector<std::vector<Cell>> rows;
};

// One stored result with its test's labels and its config (`napkin compare`).
struct LabelledResult {
  std::string test_id;  // the test's external id
  std::optional<std::string> variant;
  ConfigId config_id{};
  std::string config_name;
  std::string config_hash;
  engine::TestSummary summary;  // the summary fields; findings are not read
  bool salvaged = false;        // the result comes from salvaged channels (result_salvage)
};

// Which results ReadResults returns: each test's most recently written one
// (what the query views show), or one per config the test has results for.
enum class ResultSelection { kLatest, kEveryConfig };

// The columns of `napkin query <kind>`, in order (docs/formats.md "Query
// filters"): test_id, series, variant, then those its row of QueryKinds()
// gives (for `limits`, those of `criteria`, whose rows it checks).
std::vector<QueryField> QueryFields(QueryKind kind);

// "test_id, series, ...": the names of `fields`, for messages that list them.
std::string FieldNames(const std::vector<QueryField>& fields);

// One --sort key.
struct SortKey {
  std::string field;  // one of QueryFields(kind)
  bool descending = false;
};

// Which rows `napkin query` shows and in what order; empty members do not
// filter. Rows match every member (and within series, variants or test ids
// any one of the names).
struct QueryRequest {
  TestFilter tests;                    // the tests whose rows are shown
  std::vector<WhereExpression> where;  // all must hold; fields from QueryFields(kind)
  // Sort keys in order (rows with NULL in a key come last in either
  // direction), then test_id (and for quality check, channel, detail).
  std::vector<SortKey> sort;
  std::optional<std::int64_t> limit;  // at most this many rows (>= 0)
  // The results (and findings) of this config; empty: each test's most
  // recently written result. Query kind `tests` then lists the tests with a result of it.
  std::optional<ConfigId> config;
};

// One ISO/TS 18571 rating of a channel of a test's result against a
// reference curve (table correlations, schema/009_correlation.sql;
// docs/formats.md "Correlation ratings").
struct CorrelationRow {
  TestId test{};
  ConfigId config{};  // the rated result is the test's under this config
  std::string channel;
  std::string reference_kind;  // "model", "test" or "variant-mean"
  std::string reference;       // as shown
  std::string reference_key;   // identity of the reference (one row per key and parameters)
  std::optional<std::string> model_file, model_sha256, model_column;
  // The --model-units a model without units of its own was rated under (schema/010); part of
  // reference_key, so other units are another rating.
  std::optional<std::string> model_units;
  std::optional<TestId> reference_test;
  std::optional<std::string> reference_series, reference_variant;
  std::string edition;  // "2014" or "2024"
  double start_s = 0.0, end_s = 0.0;
  double corridor = 0.0, phase = 0.0, magnitude = 0.0, slope = 0.0, overall = 0.0;
  std::string grade;
  double shift_s = 0.0;
};

// A test under `napkin serve --inbox` that failed before it was imported
// (table inbox_failures, schema/016_inbox_failures.sql; docs/serve.md
// "Inbox"): a bad sidecar above it, a folder name that cannot be a series or
// variant, a file the importer could not read.
struct InboxFailure {
  std::string source;           // the test's file or folder in the inbox
  std::string test_name;        // its name in the inbox (the file's stem, the folder's name)
  std::string series, variant;  // the names of the folders it stands in
  std::string kind;             // "sidecar", "folder" or "import failed"
  std::string error;            // the sentence said in the log and the status
  std::string signature;        // its files' and sidecars' sizes and times when it failed
  std::string failed_at;        // ISO-8601 UTC, set by WriteInboxFailure
};

// What MergeShard took from a shard catalogue.
struct MergeReport {
  std::int64_t tests_added = 0;      // tests (with raw channels) the catalogue did not have
  std::int64_t results_merged = 0;   // results new to the catalogue or newer than its own
  std::int64_t failures_merged = 0;  // failed jobs of tests without a result here
  std::int64_t ratings_merged = 0;   // ISO/TS 18571 ratings new to the catalogue or newer than its own
  // Inbox failures (InboxFailure) of tests the catalogue lacks, new or newer than its own.
  std::int64_t inbox_failures_merged = 0;
};

struct CatalogueOptions {
  bool read_only = false;  // queries only: never migrates, never writes
  // With read_only: open the file immutable (ConnectionOptions::immutable):
  // no lock taken, no file created beside it; refused while a non-empty -wal
  // is beside it. For a catalogue shared by many readers (`run --results`).
  bool immutable = false;
  // Run SQLite's quick_check before anything is written (init, import and
  // the other writing commands): a damaged file is refused with an
  // InputError naming it, instead of being written into.
  bool check_integrity = false;
  // With check_integrity: a file this process has checked already. The check
  // is left out when the file opened is that one (its device and inode), for
  // a service that opens the catalogue again for each batch of its inbox
  // (docs/serve.md "Inbox"): quick_check reads the whole file (seconds a
  // gigabyte), and once a batch it made each test's cost grow with the catalogue.
  std::optional<FileIdentity> integrity_checked_file;
  bool durable = true;          // synchronous=FULL (else NORMAL: may lose the last commits on power loss)
  int busy_timeout_ms = 30000;  // wait for another writer this long before failing
  // Migrations to apply; empty = the embedded schema/ migrations. Tests pass
  // their own list to exercise upgrades.
  std::span<const schema::Migration> migrations;
  // Seconds since the Unix epoch, for job leases and timestamps; empty = system clock.
  std::function<double()> clock;
  // The napkin version recorded with every result and finished job written through this
  // catalogue, and the one `run --outdated` compares with (docs/formats.md "Version
  // string"); empty = this build's, napkin::Version(). Tests set another to stand for an
  // older napkin.
  std::string napkin_version;
  // What the file is to the user, in the messages of opening it ("results file", "shard").
  std::string what = "catalogue";
};

class Catalogue {
 public:
  // Opens (creating if needed) and migrates the catalogue at `path`
  // (":memory:" for a private in-memory one). Throws InputError, one sentence
  // naming the file, when it is not an SQLite database, not a napkin
  // catalogue, read-only (the file, or for writing its directory), newer
  // than this build, or (with check_integrity) damaged.
  static Catalogue Open(const std::string& path, const CatalogueOptions& options = {});

  int schema_version() const { return schema_version_; }
  // The file's name as given to Open (":memory:" in memory), for messages.
  const std::string& path() const { return connection_.path(); }
  // The device and inode of the file opened; nullopt in memory.
  std::optional<FileIdentity> file_identity() const { return connection_.FileIdentityOf(); }
  // The napkin version this catalogue records with what it writes (CatalogueOptions).
  const std::string& napkin_version() const { return napkin_version_; }
  // A write transaction over several calls; rolls back unless committed.
  Transaction BeginTransaction() { return Transaction(connection_); }

  // Keeps the write-ahead log short while other connections read without
  // pause (napkin run's reader). SQLite's automatic checkpoint copies the
  // log into the file but can start the log again from its beginning only
  // when no reader is using it; with reads always in progress the log grows
  // by everything written (gigabytes of derived channels) and is copied at
  // the end. Once the log holds more than `max_log_bytes`, this checkpoints
  // with SQLITE_CHECKPOINT_RESTART, which waits (busy timeout) until the
  // readers have moved to the file and then restarts the log. Call outside
  // a transaction, after a commit. Returns whether the log was restarted
  // (false: short enough, not WAL, or readers kept it busy).
  bool RestartWalIfLonger(std::int64_t max_log_bytes);

  // ---- series
  // Returns the series' key, creating it if new (an existing description is kept).
  SeriesId WriteSeries(const std::string& name, const std::string& description = "");
  std::optional<SeriesRow> ReadSeries(const std::string& name);
  // Every series, in name order.
  std::vector<SeriesRow> ReadAllSeries();

  // ---- arrays
  // Returns the key of the array with this hash, inserting it if new. A new
  // array whose name another definition of the catalogue already has is
  // stored as HashQualifiedArrayName(name, hash), so that `query tests`
  // tells the two apart (docs/formats.md "Array names in the catalogue").
  ArrayId WriteArray(const ArrayRow& array);
  ArrayRow ReadArray(ArrayId id);

  // ---- tests
  // Inserts a test (creating its series if new). Throws InputError when its
  // external id or content hash is already in the catalogue, or its metadata
  // is not a JSON object.
  TestId WriteTest(const TestRow& test);
  bool ExistsTestByHash(const std::string& content_hash);
  bool ExistsTestByExternalId(const std::string& external_id);
  std::optional<TestId> FindTestByExternalId(const std::string& external_id);
  TestRow ReadTest(TestId id);
  // Removes a test with everything that refers to it (raw channels, jobs,
  // results, findings, derived channels, ratings of it and against it: ON
  // DELETE CASCADE), in one transaction. A test whose source changed is
  // replaced this way (ingest::ImportOptions::supersede_changed_source).
  void DeleteTest(TestId id);
  std::vector<TestRow> ReadAllTests(const TestFilter& filter = {});

  // ---- raw channels
  // Stores (replacing) the test's channels: one row per slot, samples as
  // little-endian float64 BLOBs, with signals.prefiltered_cfc. `units[i]` is
  // the unit of column i.
  void WriteRawChannels(TestId test, const engine::TestSignals& signals, std::span<const std::string> units);
  // The test's channels in their original column order, bit-exact, with their
  // prefiltered_cfc (empty when no channel has one).
  engine::TestSignals ReadTestSignals(TestId test);
  std::vector<RawChannelInfo> ReadRawChannelInfo(TestId test);

  // ---- configs
  // Returns the key of the config with this hash, inserting it if new.
  ConfigId WriteConfig(const ConfigRow& config);
  ConfigRow ReadConfig(ConfigId id);
  std::optional<ConfigId> FindConfigByHash(const std::string& config_hash);
  // Every config, in key (creation) order.
  std::vector<ConfigRow> ReadAllConfigs();

  // ---- results
  // Stores (replacing) the test's summary, findings and conditioning record
  // (table result_conditioning) for `config`, and its
  // kinematics as derived channels encoded as `storage` says when given and
  // storage is not kNone (otherwise earlier derived channels of this test and
  // config are removed: they belong to an older computation). One transaction.
  void WriteResult(TestId test, ConfigId config, const engine::TestSummary& summary,
                   const std::string& solver, const engine::Kinematics* kinematics = nullptr,
                   engine::DerivedStorage storage = engine::DerivedStorage::kFloat64);
  // Stores (replacing) findings alone, e.g. for a test that failed.
  void WriteFindings(TestId test, ConfigId config, std::span<const engine::Finding> findings);
  // Stores (replacing) the conditioning record of the test under `config`
  // (one row per channel, docs/formats.md "Conditioning record").
  void WriteConditioning(TestId test, ConfigId config,
                         std::span<const engine::ChannelConditioning> conditioning);
  // Stores (replacing) the salvage record of the test under `config` (table
  // result_salvage, one row per salvaged channel; none removes it;
  // docs/formats.md "Salvage record").
  void WriteSalvage(TestId test, ConfigId config, const std::optional<engine::SalvageAudit>& salvage);
  // Stores (replacing) the kinematics as named derived channels, encoded as
  // `storage` says (docs/formats.md "Derived-channel storage"; time_s is
  // always float64); kNone only removes the earlier ones.
  void WriteKinematics(TestId test, ConfigId config, const engine::Kinematics& kinematics,
                       engine::DerivedStorage storage = engine::DerivedStorage::kFloat64);
  // The summary (with findings and conditioning record) of the test under `config`, if computed.
  std::optional<engine::TestSummary> ReadSummary(TestId test, ConfigId config);
  // The kinematics written by WriteKinematics, if any: bit-exact when stored
  // as float64, each float32 value widened to double exactly otherwise.
  std::optional<engine::Kinematics> ReadKinematics(TestId test, ConfigId config);
  // The config of the test's most recently written result, if any.
  std::optional<ConfigId> ReadLatestResultConfig(TestId test);
  // `napkin query <kind>` rows from the views, ordered by test id.
  Table Query(QueryKind kind, const TestFilter& filter = {});
  // The results of the tests of `filter` (see ResultSelection), ordered by
  // test id, then config key.
  std::vector<LabelledResult> ReadResults(const TestFilter& filter, ResultSelection selection);
  // The same table, filtered, sorted, limited and of the chosen result set
  // as `request` says; every value is bound as an SQL parameter. Throws
  // UsageError when a field of `request` is not in QueryFields(kind) or a
  // text value is compared with a numeric field.
  Table Query(QueryKind kind, const QueryRequest& request);

  // ---- ISO/TS 18571 ratings (db/catalogue_correlation.cpp)
  // Stores a rating of the test's result under record.config, replacing one
  // of the same result, channel, reference key, edition and interval.
  // Throws InputError when the test has no result under that config.
  void WriteCorrelation(const CorrelationRow& record);
  // The ratings of the test's result under `config`, by channel, reference
  // and edition.
  std::vector<CorrelationRow> ReadCorrelations(TestId test, ConfigId config);

  // ---- the inbox's failures (db/catalogue_inbox.cpp)
  // Stores (replacing the test's earlier one) a failure of an inbox test before its import.
  void WriteInboxFailure(const InboxFailure& failure);
  // Removes the failure of the test at `source`, if any: it was imported, or was in the
  // catalogue already.
  void DeleteInboxFailure(const std::string& source);
  // The failure recorded for the test at `source`, if any.
  std::optional<InboxFailure> ReadInboxFailure(const std::string& source);
  // Every recorded inbox failure, by source.
  std::vector<InboxFailure> ReadInboxFailures();

  // ---- jobs: db::JobQueue (db/job_queue.h) works on this connection.

  // ---- shards (run --shard I/N on several machines, then merge)
  // Merges the shard catalogue at `shard_path` (a copy of this catalogue
  // processed elsewhere) in one transaction. Entities are matched by content,
  // not by key: tests by content hash, arrays and configs by hash, series by
  // name. A shard result replaces this catalogue's result for the same test
  // and config only when it was computed later; its findings, derived
  // channels and job state come with it (and a failed job's findings, for a
  // test without a result here). A results file of `run --results`
  // (db/results_file.h) merges the same way. Merging the same shard twice
  // changes nothing. Throws InputError naming the shard when it is not a
  // napkin catalogue of this schema version, holds a test id whose content
  // differs from this catalogue's test of that id, or a test this catalogue
  // lacks without its raw channels (a results file cannot add tests), or a
  // result whose values (summary fields or solver) differ from this
  // catalogue's result for the same test and config (a conflict: the same
  // input and config must give the same answer, so one of the two was
  // computed differently), and at
  // once when the shard is this catalogue's own file under any name (path,
  // symbolic or hard link, "file:" URI: the device and inode are compared).
  MergeReport MergeShard(const std::string& shard_path);

 private:
  friend class JobQueue;            // the job queue shares the connection and clock
  friend class ResultsFile;         // copies test rows between catalogues (db/results_file.h)
  friend class CatalogueInspector;  // test-only access (tests/support/db/catalogue_inspector.h)

  Catalogue(Connection connection, std::function<double()> clock, std::string napkin_version)
      : connection_(std::move(connection)),
        clock_(std::move(clock)),
        napkin_version_(std::move(napkin_version)) {}

  void DeleteDerivedChannels(TestId test, ConfigId config);

  Connection connection_;
  std::function<double()> clock_;
  std::string napkin_version_;
  int schema_version_ = 0;
};

}  // namespace napkin::db
