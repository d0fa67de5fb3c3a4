// Catalogue: opening, series, arrays, tests, raw channels, configs.
#include "db/catalogue.h"

#include <sqlite3.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <stdexcept>
#include <thread>

#include "common/error.h"
#include "common/version.h"
#include "db/catalogue_internal.h"
#include "db/float64_blob.h"
#include "db/migrate.h"

namespace napkin::db {

namespace internal {

bool PassesQuickCheck(Connection& connection, const std::string& schema) {
  const std::string qualified = "\"" + schema + "\".";
  const std::string pragma = "PRAGMA " + qualified;
  // quick_check reads every page of the file once. Memory-mapping the file for the
  // check replaces one pread() per page with page faults on a shared mapping: on a
  // 1.4 GB catalogue in the page cache the check takes well under half the time, most
  // of the saving system time (db/README.md "Integrity check" has the times). SQLite
  // maps only the file's current size and caps the request at its compile-time
  // maximum; damaged content is still a failed check. The mapping is dropped
  // afterwards, so the rest of the command keeps SQLite's read path; during the check
  // a disk read error becomes SIGBUS instead of SQLITE_IOERR (the process stops,
  // nothing has been written yet).
  const std::int64_t mmap_before = connection.PragmaInt(qualified + "mmap_size");
  struct RestoreMmap {
    Connection& connection;
    std::string pragma;
    std::int64_t bytes;
    ~RestoreMmap() {
      try {
        connection.Execute(pragma + "mmap_size = " + std::to_string(bytes));
      } catch (...) {
        // Restoring a performance setting cannot fail the check's caller.
      }
    }
  } restore{connection, pragma, mmap_before};
  connection.Execute(pragma + "mmap_size = 4294967296");
  try {
    // Its first line is "ok" or a problem.
    auto check = connection.Prepare(pragma + "quick_check(1)");
    return check->Step() && check->ColumnText(0) == "ok";
  } catch (const DatabaseError& error) {
    if (error.corrupt()) return false;
    throw;
  }
}

std::optional<std::string> JsonStringArray(const std::vector<std::string>& values) {
  if (values.empty()) return std::nullopt;
  std::string json = "[";
  for (const std::string& value : values) {
    if (json.size() > 1) json += ',';
    json += '"';
    for (const char c : value) {
      if (c == '"' || c == '\\') {
        json += '\\';
        json += c;
      } else if (static_cast<unsigned char>(c) < 0x20) {
        char escaped[8];
        std::snprintf(escaped, sizeof escaped, "\\u%04x",
                      static_cast<unsigned>(static_cast<unsigned char>(c)));
        json += escaped;
      } else {
        json += c;
      }
    }
    json += '"';
  }
  json += ']';
  return json;
}

namespace {

// `column` is one of `names`, bound to `parameter`: "= ?N" for one name (the
// index's equality seek), an IN over json_each for several.
std::string AnyOfTerm(const char* column, const std::vector<std::string>& names, const char* parameter) {
  if (names.empty()) return "";
  if (names.size() == 1) return std::string(" AND ") + column + " = " + parameter;
  return std::string(" AND ") + column + " IN (SELECT value FROM json_each(" + parameter + "))";
}

void BindAnyOf(Statement& statement, int parameter, const std::vector<std::string>& names) {
  if (names.size() == 1)
    statement.Bind(parameter, names.front());
  else if (names.size() > 1)
    statement.Bind(parameter, *JsonStringArray(names));
}

}  // namespace

std::string TestFilterTerms(const TestFilter& filter) {
  // The series as their keys, so that the planner seeks the tests of each through tests_by_series (a
  // name IN (...) on the joined series table walked every test).
  const std::string series = filter.series.empty()
                                 ? ""
                                 : " AND t.series_id IN (SELECT id FROM series AS named WHERE 1" +
                                       AnyOfTerm("named.name", filter.series, "?1") + ")";
  return "1" + series + AnyOfTerm("t.variant", filter.variants, "?2") +
         AnyOfTerm("t.external_id", filter.external_ids, "?3");
}

void BindTestFilter(Statement& statement, const TestFilter& filter) {
  BindAnyOf(statement, 1, filter.series);
  BindAnyOf(statement, 2, filter.variants);
  BindAnyOf(statement, 3, filter.external_ids);
}

}  // namespace internal

namespace {

using internal::IsoTimestampSql;

double SystemClockSeconds() {
  return std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
}

bool IsFinite(const Eigen::Vector3d& vector) { return vector.allFinite(); }

// Column list shared by ReadTest and ReadAllTests, read by ReadTestRow.
constexpr const char* kTestColumns =
    "t.id, t.external_id, s.name, t.variant, t.metadata_json, t.array_id, "
    "t.orientation_phi_rad, t.orientation_theta_rad, t.orientation_psi_rad, "
    "t.velocity_x_mps, t.velocity_y_mps, t.velocity_z_mps, "
    "t.omega_x_radps, t.omega_y_radps, t.omega_z_radps, "
    "t.source_path, t.content_hash, t.imported_at";

TestRow ReadTestRow(const Statement& row) {
  TestRow test;
  test.id = TestId{row.ColumnInt64(0)};
  test.external_id = row.ColumnText(1);
  test.series = row.ColumnOptionalText(2);
  test.variant = row.ColumnOptionalText(3);
  test.metadata_json = row.ColumnText(4);
  test.array_id = ArrayId{row.ColumnInt64(5)};
  for (int i = 0; i < 3; ++i) {
    test.initial_state.orientation_rad[i] = row.ColumnDouble(6 + i);
    test.initial_state.velocity_fixed_mps[i] = row.ColumnDouble(9 + i);
    test.initial_state.omega_body_radps[i] = row.ColumnDouble(12 + i);
  }
  test.source_path = row.ColumnText(15);
  test.content_hash = row.ColumnText(16);
  test.imported_at = row.ColumnText(17);
  return test;
}

// How WriteArray and WriteConfig store a JSON definition: once per content
// hash (schema/001_catalogue.sql: the hash columns are UNIQUE), in the
// columns <column>_json and <column>_hash of `table` beside its name.
struct HashKeyedTable {
  const char* table;            // "arrays"
  const char* column;           // "definition"
  const char* what;             // "array": messages name "array '<name>'"
  const char* definition_what;  // "definition of array": "... '<name>' is not valid JSON."
  const char* other_what;       // "array definition": "... the hash of a different array definition ..."
  bool created_at;              // the row records when it was written (configs)
  bool distinct_names;          // a new row's name taken by another row gets its hash (arrays)
};
constexpr HashKeyedTable kArrayTable{"arrays",           "definition", "array", "definition of array",
                                     "array definition", false,        true};
constexpr HashKeyedTable kConfigTable{"configs", "config", "processing config", "processing config", "config",
                                      true,      false};

// In one transaction: checks that `json` is valid JSON, inserts the row
// unless one with `hash` is there, and returns the id of the row holding
// `hash`: the new one, or the one already there when its JSON is the same.
std::int64_t InsertByHash(Connection& connection, const HashKeyedTable& table, const std::string& name,
                          const std::string& json, const std::string& hash,
                          const std::function<double()>& clock) {
  const std::string column = table.column;
  Transaction transaction(connection);
  {
    auto valid = connection.Prepare("SELECT json_valid(?1)");
    valid->Bind(1, json);
    valid->Step();
    if (valid->ColumnInt64(0) == 0)
      throw InputError(std::string(table.definition_what) + " '" + name + "' is not valid JSON.");
  }
  std::string stored_name = name;
  if (table.distinct_names) {
    // Issue 29 point 6: two geometries under one name were shown alike by
    // `query tests`. The first keeps the name; a later one (not yet stored
    // under its hash) takes the name qualified by its hash.
    auto taken = connection.Prepare(
        std::string("SELECT EXISTS (SELECT 1 FROM ") + table.table + " WHERE name = ?1 AND " + column +
        "_hash != ?2) AND NOT EXISTS (SELECT 1 FROM " + table.table + " WHERE " + column + "_hash = ?2)");
    taken->BindAll(name, hash);
    taken->Step();
    if (taken->ColumnInt64(0) != 0) stored_name = HashQualifiedArrayName(name, hash);
  }
  {
    auto insert =
        connection.Prepare(std::string("INSERT INTO ") + table.table + " (name, " + column + "_json, " +
                           column + "_hash" + (table.created_at ? ", created_at" : "") +
                           ") VALUES (?1, ?2, ?3" + (table.created_at ? ", " + IsoTimestampSql("?4") : "") +
                           ") ON CONFLICT (" + column + "_hash) DO NOTHING");
    insert->BindAll(stored_name, json, hash);
    if (table.created_at) insert->Bind(4, clock());
    insert->Execute();
  }
  auto select = connection.Prepare("SELECT id, " + column + "_json FROM " + table.table + " WHERE " + column +
                                   "_hash = ?1");
  select->Bind(1, hash);
  select->Step();
  if (select->ColumnText(1) != json)
    throw InputError(std::string(table.what) + " '" + name + "' has the hash " + hash + " of a different " +
                     table.other_what + " already in the catalogue.");
  const std::int64_t id = select->ColumnInt64(0);
  transaction.Commit();
  return id;
}

}  // namespace

// --------------------------------------------------------------------- open

namespace {

// Switching a file to WAL needs an exclusive lock, and SQLite answers
// SQLITE_BUSY at once, without calling the busy handler, while another
// process holds a lock on the file (two imports creating the same
// catalogue): retry until the busy timeout, as every other lock waits.
void SwitchToWal(Connection& connection, int busy_timeout_ms) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::milliseconds(busy_timeout_ms);
  for (;;) {
    try {
      connection.Execute("PRAGMA journal_mode = WAL");
      return;
    } catch (const DatabaseError& error) {
      if (!error.busy() || std::chrono::steady_clock::now() >= deadline) throw;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
}

}  // namespace

bool Catalogue::RestartWalIfLonger(std::int64_t max_log_bytes) {
  if (connection_.in_memory() || connection_.read_only() || connection_.InTransaction()) return false;
  int log_frames = 0, checkpointed_frames = 0;
  // PASSIVE: the automatic checkpoint's work, reporting the log's length.
  if (sqlite3_wal_checkpoint_v2(connection_.handle(), "main", SQLITE_CHECKPOINT_PASSIVE, &log_frames,
                                &checkpointed_frames) != SQLITE_OK ||
      log_frames <= 0)
    return false;
  if (static_cast<std::int64_t>(log_frames) * connection_.PragmaInt("page_size") <= max_log_bytes)
    return false;
  return sqlite3_wal_checkpoint_v2(connection_.handle(), "main", SQLITE_CHECKPOINT_RESTART, &log_frames,
                                   &checkpointed_frames) == SQLITE_OK;
}

Catalogue Catalogue::Open(const std::string& path, const CatalogueOptions& options) {
  const std::span<const schema::Migration> migrations =
      options.migrations.empty() ? schema::Migrations() : options.migrations;
  CheckMigrationList(migrations);
  const auto latest = static_cast<std::int64_t>(migrations.size());

  ConnectionOptions connection_options;
  connection_options.read_only = options.read_only;
  connection_options.immutable = options.immutable;
  connection_options.durable = options.durable;
  connection_options.busy_timeout_ms = options.busy_timeout_ms;
  connection_options.what = options.what;
  Connection connection = Connection::Open(path, connection_options);

  // Identify the file before changing anything in it.
  const std::int64_t version = connection.PragmaInt("user_version");
  if (version > 0 && connection.PragmaInt("application_id") != kCatalogueApplicationId)
    throw InputError("'" + path +
                     "' is not a napkin catalogue (it is another application's SQLite database).");
  if (version == 0) {
    auto tables = connection.Prepare("SELECT count(*) FROM sqlite_master");
    tables->Step();
    if (tables->ColumnInt64(0) > 0)
      throw InputError("'" + path + "' is not a napkin catalogue (it already holds other tables).");
  }
  if (version > latest)
    throw InputError("catalogue '" + path + "' has schema version " + std::to_string(version) +
                     ", newer than this napkin knows (" + std::to_string(latest) + ").");

  if (options.check_integrity &&
      !(options.integrity_checked_file && connection.FileIdentityOf() == options.integrity_checked_file)) {
    if (!internal::PassesQuickCheck(connection))
      throw InputError("catalogue '" + path +
                       "' is damaged (SQLite's integrity check fails) and was left as it was; restore it "
                       "from a backup, or save what is readable with `sqlite3 " +
                       path + " .recover | sqlite3 recovered.db`.");
  }
  if (options.read_only) {
    if (version < latest)
      throw InputError("catalogue '" + path + "' has schema version " + std::to_string(version) +
                       " and needs upgrading with 'napkin init'.");
  } else {
    // WAL: readers never block the writer (workers query while others write).
    if (!connection.in_memory()) {
      SwitchToWal(connection, options.busy_timeout_ms);
      // Truncate the WAL after checkpoints: derived channels make it grow large.
      connection.Execute("PRAGMA journal_size_limit = 67108864");
    }
    connection.Execute(options.durable ? "PRAGMA synchronous = FULL" : "PRAGMA synchronous = NORMAL");
  }

  Catalogue catalogue(std::move(connection), options.clock ? options.clock : SystemClockSeconds,
                      options.napkin_version.empty() ? napkin::Version() : options.napkin_version);
  catalogue.schema_version_ =
      options.read_only ? static_cast<int>(version) : ApplyMigrations(catalogue.connection_, migrations);
  return catalogue;
}

// ------------------------------------------------------------------- series

SeriesId Catalogue::WriteSeries(const std::string& name, const std::string& description) {
  Transaction transaction(connection_);
  {
    auto insert = connection_.Prepare(
        "INSERT INTO series (name, description) VALUES (?1, ?2) ON CONFLICT (name) DO NOTHING");
    insert->BindAll(name, description);
    insert->Execute();
  }
  auto select = connection_.Prepare("SELECT id FROM series WHERE name = ?1");
  select->Bind(1, name);
  select->Step();
  const SeriesId id{select->ColumnInt64(0)};
  transaction.Commit();
  return id;
}

std::optional<SeriesRow> Catalogue::ReadSeries(const std::string& name) {
  auto select = connection_.Prepare("SELECT id, name, description FROM series WHERE name = ?1");
  select->Bind(1, name);
  if (!select->Step()) return std::nullopt;
  return SeriesRow{SeriesId{select->ColumnInt64(0)}, select->ColumnText(1), select->ColumnText(2)};
}

std::vector<SeriesRow> Catalogue::ReadAllSeries() {
  auto select = connection_.Prepare("SELECT id, name, description FROM series ORDER BY name");
  std::vector<SeriesRow> series;
  while (select->Step())
    series.push_back({SeriesId{select->ColumnInt64(0)}, select->ColumnText(1), select->ColumnText(2)});
  return series;
}

// ------------------------------------------------------------------- arrays

std::string HashQualifiedArrayName(const std::string& name, const std::string& definition_hash) {
  return name + "@" + definition_hash.substr(0, 12);
}

ArrayId Catalogue::WriteArray(const ArrayRow& array) {
  return ArrayId{InsertByHash(connection_, kArrayTable, array.name, array.definition_json,
                              array.definition_hash, clock_)};
}

ArrayRow Catalogue::ReadArray(ArrayId id) {
  auto select =
      connection_.Prepare("SELECT name, definition_json, definition_hash FROM arrays WHERE id = ?1");
  select->Bind(1, id);
  if (!select->Step())
    throw InputError("array #" + std::to_string(static_cast<std::int64_t>(id)) + " is not in the catalogue.");
  return ArrayRow{id, select->ColumnText(0), select->ColumnText(1), select->ColumnText(2)};
}

// -------------------------------------------------------------------- tests

void Catalogue::DeleteTest(TestId id) {
  Transaction transaction(connection_);
  auto remove = connection_.Prepare("DELETE FROM tests WHERE id = ?1");
  remove->BindAll(id);
  remove->Execute();
  transaction.Commit();
}

TestId Catalogue::WriteTest(const TestRow& test) {
  Transaction transaction(connection_);
  {
    auto existing = connection_.Prepare("SELECT source_path FROM tests WHERE external_id = ?1");
    existing->Bind(1, test.external_id);
    if (existing->Step())
      throw InputError("test '" + test.external_id + "' is already in the catalogue (imported from '" +
                       existing->ColumnText(0) + "').");
  }
  {
    auto same_content = connection_.Prepare("SELECT external_id FROM tests WHERE content_hash = ?1");
    same_content->Bind(1, test.content_hash);
    if (same_content->Step())
      throw InputError("'" + test.source_path + "' has the same content as test '" +
                       same_content->ColumnText(0) + "', already in the catalogue.");
  }
  {
    auto object = connection_.Prepare("SELECT json_valid(?1) AND json_type(?1) = 'object'");
    object->Bind(1, test.metadata_json);
    object->Step();
    if (object->ColumnInt64(0) == 0)
      throw InputError("metadata of test '" + test.external_id + "' is not a JSON object.");
  }
  const engine::InitialState& initial = test.initial_state;
  if (!IsFinite(initial.orientation_rad) || !IsFinite(initial.velocity_fixed_mps) ||
      !IsFinite(initial.omega_body_radps))
    throw InputError("initial state of test '" + test.external_id + "' has a non-finite value.");

  std::optional<SeriesId> series;
  if (test.series) series = WriteSeries(*test.series);

  auto insert = connection_.Prepare(
      "INSERT INTO tests (external_id, series_id, variant, metadata_json, array_id, "
      "orientation_phi_rad, orientation_theta_rad, orientation_psi_rad, "
      "velocity_x_mps, velocity_y_mps, velocity_z_mps, omega_x_radps, omega_y_radps, omega_z_radps, "
      "source_path, content_hash, imported_at) "
      "VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8, ?9, ?10, ?11, ?12, ?13, ?14, ?15, ?16, " +
      IsoTimestampSql("?17") + ")");
  insert->BindAll(test.external_id, series, test.variant, test.metadata_json, test.array_id,
                  initial.orientation_rad.x(), initial.orientation_rad.y(), initial.orientation_rad.z(),
                  initial.velocity_fixed_mps.x(), initial.velocity_fixed_mps.y(),
                  initial.velocity_fixed_mps.z(), initial.omega_body_radps.x(), initial.omega_body_radps.y(),
                  initial.omega_body_radps.z(), test.source_path, test.content_hash, clock_());
  insert->Execute();
  const TestId id{connection_.LastInsertRowId()};
  transaction.Commit();
  return id;
}

bool Catalogue::ExistsTestByHash(const std::string& content_hash) {
  auto select = connection_.Prepare("SELECT 1 FROM tests WHERE content_hash = ?1");
  select->Bind(1, content_hash);
  return select->Step();
}

bool Catalogue::ExistsTestByExternalId(const std::string& external_id) {
  return FindTestByExternalId(external_id).has_value();
}

std::optional<TestId> Catalogue::FindTestByExternalId(const std::string& external_id) {
  auto select = connection_.Prepare("SELECT id FROM tests WHERE external_id = ?1");
  select->Bind(1, external_id);
  if (!select->Step()) return std::nullopt;
  return TestId{select->ColumnInt64(0)};
}

// How messages name a test: its id as the user gave it, never the internal
// row number (README "Errors"), or a sentence saying the row is gone.
std::string NameOfTest(Connection& connection, TestId id) {
  auto select = connection.Prepare("SELECT external_id FROM tests WHERE id = ?1");
  select->Bind(1, id);
  if (select->Step()) return "test '" + select->ColumnText(0) + "'";
  return "a test removed from the catalogue meanwhile";
}

TestRow Catalogue::ReadTest(TestId id) {
  auto select =
      connection_.Prepare(std::string("SELECT ") + kTestColumns +
                          " FROM tests AS t LEFT JOIN series AS s ON s.id = t.series_id WHERE t.id = ?1");
  select->Bind(1, id);
  if (!select->Step())
    throw InputError(
        "a test was removed from the catalogue while napkin was using it; run the command again.");
  return ReadTestRow(*select);
}

std::vector<TestRow> Catalogue::ReadAllTests(const TestFilter& filter) {
  auto select = connection_.Prepare(std::string("SELECT ") + kTestColumns +
                                    " FROM tests AS t LEFT JOIN series AS s ON s.id = t.series_id WHERE " +
                                    internal::TestFilterTerms(filter) + " ORDER BY t.external_id");
  internal::BindTestFilter(*select, filter);
  std::vector<TestRow> tests;
  while (select->Step()) tests.push_back(ReadTestRow(*select));
  return tests;
}

// ------------------------------------------------------------- raw channels

void Catalogue::WriteRawChannels(TestId test, const engine::TestSignals& signals,
                                 std::span<const std::string> units) {
  const auto channels = static_cast<std::size_t>(signals.samples.cols());
  if (signals.slots.size() != channels || units.size() != channels)
    throw std::invalid_argument("WriteRawChannels: " + std::to_string(channels) + " signal columns, " +
                                std::to_string(signals.slots.size()) + " slots and " +
                                std::to_string(units.size()) + " units");
  if (!(signals.dt_s > 0.0) || !std::isfinite(signals.dt_s) || !std::isfinite(signals.t0_s))
    throw InputError("the signals of " + NameOfTest(connection_, test) +
                     " have an invalid sampling interval or start time.");

  Transaction transaction(connection_);
  {
    auto remove = connection_.Prepare("DELETE FROM raw_channels WHERE test_id = ?1");
    remove->Bind(1, test);
    remove->Execute();
  }
  // prefiltered_cfc (schema version 5) only for signals that carry it: a
  // plain test's statement is the same as before that version.
  const bool prefiltered = !signals.prefiltered_cfc.empty();
  auto insert = connection_.Prepare(
      prefiltered
          ? "INSERT INTO raw_channels (test_id, position, slot, unit, dt_s, t0_s, sample_count, samples, "
            "prefiltered_cfc) VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8, ?9)"
          : "INSERT INTO raw_channels (test_id, position, slot, unit, dt_s, t0_s, sample_count, samples) "
            "VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8)");
  std::vector<std::byte> scratch;
  for (std::size_t c = 0; c < channels; ++c) {
    const auto column = std::span<const double>(signals.samples.col(static_cast<Eigen::Index>(c)).data(),
                                                static_cast<std::size_t>(signals.samples.rows()));
    insert->BindAll(test, c, signals.slots[c], units[c], signals.dt_s, signals.t0_s, signals.samples.rows(),
                    Float64LittleEndianBytes(column, scratch));
    if (prefiltered) insert->Bind(9, signals.PrefilteredCfc(static_cast<Eigen::Index>(c)));
    insert->Execute();
    insert->Reset();
  }
  transaction.Commit();
}

std::vector<RawChannelInfo> Catalogue::ReadRawChannelInfo(TestId test) {
  auto select = connection_.Prepare(
      "SELECT slot, unit, dt_s, t0_s, sample_count FROM raw_channels WHERE test_id = ?1 ORDER BY position");
  select->Bind(1, test);
  std::vector<RawChannelInfo> channels;
  while (select->Step())
    channels.push_back({select->ColumnText(0), select->ColumnText(1), select->ColumnDouble(2),
                        select->ColumnDouble(3), select->ColumnInt64(4)});
  return channels;
}

engine::TestSignals Catalogue::ReadTestSignals(TestId test) {
  const std::vector<RawChannelInfo> channels = ReadRawChannelInfo(test);
  engine::TestSignals signals;
  if (channels.empty()) {
    signals.samples.resize(0, 0);
    return signals;
  }
  const RawChannelInfo& first = channels.front();
  for (const RawChannelInfo& channel : channels)
    if (channel.dt_s != first.dt_s || channel.t0_s != first.t0_s ||
        channel.sample_count != first.sample_count)
      throw InputError("channel '" + channel.slot + "' of test '" + ReadTest(test).external_id +
                       "' is sampled differently from channel '" + first.slot + "' in the catalogue.");
  signals.dt_s = first.dt_s;
  signals.t0_s = first.t0_s;
  signals.samples.resize(static_cast<Eigen::Index>(first.sample_count),
                         static_cast<Eigen::Index>(channels.size()));

  auto select = connection_.Prepare(
      "SELECT slot, samples, prefiltered_cfc FROM raw_channels WHERE test_id = ?1 ORDER BY position");
  select->Bind(1, test);
  for (Eigen::Index c = 0; select->Step(); ++c) {
    signals.slots.push_back(select->ColumnText(0));
    if (!select->ColumnIsNull(2)) {  // only tests with a recorded prefilter carry the vector
      signals.prefiltered_cfc.resize(channels.size());
      signals.prefiltered_cfc[static_cast<std::size_t>(c)] = select->ColumnDouble(2);
    }
    DecodeFloat64LittleEndian(
        select->ColumnBlob(1),
        std::span<double>(signals.samples.col(c).data(), static_cast<std::size_t>(signals.samples.rows())));
  }
  return signals;
}

// ------------------------------------------------------------------ configs

ConfigId Catalogue::WriteConfig(const ConfigRow& config) {
  return ConfigId{
      InsertByHash(connection_, kConfigTable, config.name, config.config_json, config.config_hash, clock_)};
}

ConfigRow Catalogue::ReadConfig(ConfigId id) {
  auto select =
      connection_.Prepare("SELECT name, config_json, config_hash, created_at FROM configs WHERE id = ?1");
  select->Bind(1, id);
  if (!select->Step())
    throw InputError("processing config #" + std::to_string(static_cast<std::int64_t>(id)) +
                     " is not in the catalogue.");
  return ConfigRow{id, select->ColumnText(0), select->ColumnText(1), select->ColumnText(2),
                   select->ColumnText(3)};
}

std::optional<ConfigId> Catalogue::FindConfigByHash(const std::string& config_hash) {
  auto select = connection_.Prepare("SELECT id FROM configs WHERE config_hash = ?1");
  select->Bind(1, config_hash);
  if (!select->Step()) return std::nullopt;
  return ConfigId{select->ColumnInt64(0)};
}

std::vector<ConfigRow> Catalogue::ReadAllConfigs() {
  auto select =
      connection_.Prepare("SELECT id, name, config_json, config_hash, created_at FROM configs ORDER BY id");
  std::vector<ConfigRow> configs;
  while (select->Step())
    configs.push_back({ConfigId{select->ColumnInt64(0)}, select->ColumnText(1), select->ColumnText(2),
                       select->ColumnText(3), select->ColumnText(4)});
  return configs;
}

}  // namespace napkin::db
