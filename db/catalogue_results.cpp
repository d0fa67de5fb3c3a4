// Catalogue: results, findings and derived channels (kinematics); queries are
// in catalogue_query.cpp.
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <set>
#include <stdexcept>
#include <unordered_map>

#include "common/error.h"
#include "common/joined.h"
#include "db/catalogue.h"
#include "db/catalogue_internal.h"
#include "db/float64_blob.h"
#include "engine/summary_fields.h"
#include "engine/units.h"

namespace napkin::db {

namespace {

using engine::TestSummary;
using internal::IsoTimestampSql;
using internal::SummaryColumnList;

// Reads the summary fields from columns first, first+1, ... of `row`.
void ReadSummaryFields(const Statement& row, int first, TestSummary& summary) {
  int column = first;
  for (const engine::SummaryField& field : engine::SummaryFields())
    field.Set(summary, row.ColumnDouble(column++));
}

// The column as engine::SeverityName wrote it.
engine::Severity ParseSeverity(const std::string& text) {
  if (const std::optional<engine::Severity> severity = engine::ParseName<engine::Severity>(text))
    return *severity;
  throw InputError("finding severity '" + text + "' in the catalogue is not info, warning or error.");
}

// A name of vocabulary E as the catalogue stores it; an unknown one is a
// catalogue this napkin did not write.
template <typename E>
E ParseStored(const std::string& text, const char* what) {
  if (const std::optional<E> value = engine::ParseName<E>(text)) return *value;
  throw InputError(std::string(what) + " '" + text + "' in the catalogue is not one napkin knows.");
}

// One derived channel of a Kinematics: its stable name (SI unit in the
// name), the contiguous column it is stored from / read into, and whether it
// needs the rotation (absent from acceleration-only kinematics).
struct KinematicsChannel {
  std::string name;
  double* column;
  bool needs_rotation;
};

// The derived channels of `kinematics`, in storage order. Acceleration-only
// kinematics (engine::Kinematics::ResizeWithoutRotation) have data in the
// channels that need no rotation (time_s, acc_body_*) only.
std::vector<KinematicsChannel> KinematicsChannels(engine::Kinematics& kinematics) {
  std::vector<KinematicsChannel> channels;
  channels.push_back({"time_s", kinematics.time_s.data(), false});
  const auto add3 = [&channels](const std::string& prefix, engine::Series3& series, const std::string& unit,
                                const std::array<const char*, 3>& components, bool needs_rotation = true) {
    for (int c = 0; c < 3; ++c)
      channels.push_back(
          {std::string(prefix).append(components[c]).append(unit), series.col(c).data(), needs_rotation});
  };
  constexpr std::array<const char*, 3> kXyz = {"x", "y", "z"};
  add3("omega_body_", kinematics.omega_body, "_radps", kXyz);
  add3("alpha_body_", kinematics.alpha_body, "_radps2", kXyz);
  add3("omega_fixed_", kinematics.omega_fixed, "_radps", kXyz);
  add3("alpha_fixed_", kinematics.alpha_fixed, "_radps2", kXyz);
  add3("acc_body_", kinematics.acc_body, "_mps2", kXyz, /*needs_rotation=*/false);
  add3("acc_fixed_", kinematics.acc_fixed, "_mps2", kXyz);
  add3("vel_fixed_", kinematics.vel_fixed, "_mps", kXyz);
  add3("pos_fixed_", kinematics.pos_fixed, "_m", kXyz);
  constexpr std::array<const char*, 4> kWxyz = {"w", "x", "y", "z"};
  for (int c = 0; c < 4; ++c)
    channels.push_back(
        {std::string("quat_") + kWxyz[c], kinematics.quat_fixed_from_body.col(c).data(), true});
  add3("", kinematics.roll_pitch_yaw_rad, "_rad", {"roll", "pitch", "yaw"});
  add3("dcos_", kinematics.dcos_rad, "_rad", {"xx", "yy", "zz"});
  // The rigid-body residual cannot be judged without the rotation either.
  channels.push_back({"residual_mps2", kinematics.residual.data(), true});
  return channels;
}

// Whether `kinematics` has the rotation-dependent series: true when every
// series has time_s's rows, false for the shape of
// engine::Kinematics::ResizeWithoutRotation (time_s and acc_body only).
// Throws std::invalid_argument for any other shape.
bool CheckKinematicsShape(const engine::Kinematics& kinematics) {
  const Eigen::Index n = kinematics.size();
  const bool rotation = kinematics.quat_fixed_from_body.rows() != 0 || n == 0;
  const auto check = [n, rotation](Eigen::Index rows, const char* member, bool needs_rotation = true) {
    const Eigen::Index expected = rotation || !needs_rotation ? n : 0;
    if (rows != expected)
      throw std::invalid_argument(std::string("Kinematics::") + member + " has " + std::to_string(rows) +
                                  " rows, time_s has " + std::to_string(n) +
                                  (rotation ? "" : " and the quaternion none"));
  };
  check(kinematics.omega_body.rows(), "omega_body");
  check(kinematics.alpha_body.rows(), "alpha_body");
  check(kinematics.omega_fixed.rows(), "omega_fixed");
  check(kinematics.alpha_fixed.rows(), "alpha_fixed");
  check(kinematics.acc_body.rows(), "acc_body", /*needs_rotation=*/false);
  check(kinematics.acc_fixed.rows(), "acc_fixed");
  check(kinematics.vel_fixed.rows(), "vel_fixed");
  check(kinematics.pos_fixed.rows(), "pos_fixed");
  check(kinematics.quat_fixed_from_body.rows(), "quat_fixed_from_body");
  check(kinematics.roll_pitch_yaw_rad.rows(), "roll_pitch_yaw_rad");
  check(kinematics.dcos_rad.rows(), "dcos_rad");
  check(kinematics.residual.rows(), "residual");
  return rotation;
}

}  // namespace

std::string internal::SummaryColumnList(const std::string& prefix) {
  return Joined(engine::SummaryFields(),
                [&prefix](const engine::SummaryField& field) { return prefix + field.name; });
}

// ------------------------------------------------------------------ results

void Catalogue::WriteResult(TestId test, ConfigId config, const engine::TestSummary& summary,
                            const std::string& solver, const engine::Kinematics* kinematics,
                            engine::DerivedStorage storage) {
  Transaction transaction(connection_);
  {
    // Delete + insert (not upsert): the new row gets the largest id, which is
    // how the views find a test's most recent result.
    auto remove = connection_.Prepare("DELETE FROM results WHERE test_id = ?1 AND config_id = ?2");
    remove->BindAll(test, config);
    remove->Execute();
  }
  {
    // The napkin version that computed it (schema/007_provenance.sql) is the last parameter.
    static const std::string kInsert = [] {
      std::string sql = "INSERT INTO results (test_id, config_id, solver, computed_at, " +
                        SummaryColumnList() + ", napkin_version) VALUES (?1, ?2, ?3, " +
                        IsoTimestampSql("?4");
      const std::size_t fields = engine::SummaryFields().size();
      for (std::size_t i = 0; i <= fields; ++i) sql += ", ?" + std::to_string(5 + i);
      return sql + ")";
    }();
    auto insert = connection_.Prepare(kInsert);
    insert->BindAll(test, config, solver, clock_());
    int parameter = 5;
    for (const engine::SummaryField& field : engine::SummaryFields())
      insert->Bind(parameter++, field.Get(summary));
    insert->Bind(parameter, napkin_version_);
    insert->Execute();
  }
  WriteFindings(test, config, summary.findings);
  WriteConditioning(test, config, summary.conditioning);
  WriteSalvage(test, config, summary.salvage);
  if (kinematics != nullptr && storage != engine::DerivedStorage::kNone)
    WriteKinematics(test, config, *kinematics, storage);
  else
    DeleteDerivedChannels(test, config);
  transaction.Commit();
}

void Catalogue::WriteFindings(TestId test, ConfigId config, std::span<const engine::Finding> findings) {
  Transaction transaction(connection_);
  {
    auto remove = connection_.Prepare("DELETE FROM findings WHERE test_id = ?1 AND config_id = ?2");
    remove->BindAll(test, config);
    remove->Execute();
  }
  auto insert = connection_.Prepare(
      "INSERT INTO findings (test_id, config_id, position, check_name, channel, severity, detail) "
      "VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7)");
  for (std::size_t i = 0; i < findings.size(); ++i) {
    const engine::Finding& finding = findings[i];
    insert->BindAll(test, config, i, finding.check, finding.channel, engine::NameOf(finding.severity),
                    finding.detail);
    insert->Execute();
    insert->Reset();
  }
  transaction.Commit();
}

void Catalogue::WriteConditioning(TestId test, ConfigId config,
                                  std::span<const engine::ChannelConditioning> conditioning) {
  Transaction transaction(connection_);
  {
    auto remove =
        connection_.Prepare("DELETE FROM result_conditioning WHERE test_id = ?1 AND config_id = ?2");
    remove->BindAll(test, config);
    remove->Execute();
  }
  auto insert = connection_.Prepare(
      "INSERT INTO result_conditioning (test_id, config_id, position, channel, filter, filter_cfc, "
      "prefiltered_cfc, bias_removed, bias_t1_s, bias_t2_s, time_shift_s) "
      "VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8, ?9, ?10, ?11)");
  for (std::size_t i = 0; i < conditioning.size(); ++i) {
    const engine::ChannelConditioning& record = conditioning[i];
    insert->BindAll(test, config, i, record.channel, engine::FilterDescription(record), record.filter_cfc,
                    record.prefiltered_cfc, record.bias_removed, record.bias_window_start_s,
                    record.bias_window_end_s, record.time_shift_s);
    insert->Execute();
    insert->Reset();
  }
  transaction.Commit();
}

void Catalogue::WriteSalvage(TestId test, ConfigId config,
                             const std::optional<engine::SalvageAudit>& salvage) {
  Transaction transaction(connection_);
  {
    auto remove = connection_.Prepare("DELETE FROM result_salvage WHERE test_id = ?1 AND config_id = ?2");
    remove->BindAll(test, config);
    remove->Execute();
  }
  if (salvage) {
    auto insert = connection_.Prepare(
        "INSERT INTO result_salvage (test_id, config_id, position, mode, channel, fault, action, partner, "
        "t1_s, "
        "t2_s, samples_replaced, rms_residual_before_g, rms_residual_after_g, channels_used, channels_total, "
        "repaired_samples) VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8, ?9, ?10, ?11, ?12, ?13, ?14, ?15, ?16)");
    // NULL for a residual that could not be computed (NaN, or +inf: diverged).
    const auto in_g = [](double mps2) {
      return std::isfinite(mps2) ? std::optional<double>(mps2 / engine::kStandardGravity) : std::nullopt;
    };
    for (std::size_t i = 0; i < salvage->channels.size(); ++i) {
      const engine::SalvagedChannel& channel = salvage->channels[i];
      insert->BindAll(test, config, i, salvage->mode, channel.channel, engine::NameOf(channel.fault),
                      engine::NameOf(channel.action), channel.partner, channel.t1_s, channel.t2_s,
                      channel.samples_replaced, in_g(salvage->rms_residual_before_mps2),
                      in_g(salvage->rms_residual_after_mps2), salvage->channels_used,
                      salvage->channels_total);
      // An excluded channel has no repaired samples: NULL.
      std::vector<std::byte> scratch;
      if (channel.repaired_samples.empty())
        insert->Bind(16, std::nullopt);
      else
        insert->Bind(16, Float64LittleEndianBytes(channel.repaired_samples, scratch));
      insert->Execute();
      insert->Reset();
    }
  }
  transaction.Commit();
}

void Catalogue::DeleteDerivedChannels(TestId test, ConfigId config) {
  auto remove = connection_.Prepare("DELETE FROM derived_channels WHERE test_id = ?1 AND config_id = ?2");
  remove->BindAll(test, config);
  remove->Execute();
}

void Catalogue::WriteKinematics(TestId test, ConfigId config, const engine::Kinematics& kinematics,
                                engine::DerivedStorage storage) {
  const bool rotation = CheckKinematicsShape(kinematics);
  if (storage == engine::DerivedStorage::kNone) {
    DeleteDerivedChannels(test, config);
    return;
  }
  // time_s, the time base, stays float64 whatever the storage: exports' sampling
  // interval and first-sample time stay exact (docs/formats.md "Derived-channel storage").
  const std::string time_channel = "time_s";
  const Eigen::Index n = kinematics.size();
  // Informative only (readers of plain sqlite3); time_s itself is stored
  // bit-exact. NaN binds as NULL: no t0 without samples, no dt below two.
  constexpr double kNone = std::numeric_limits<double>::quiet_NaN();
  const double t0_s = n > 0 ? kinematics.time_s[0] : kNone;
  const double dt_s =
      n > 1 ? (kinematics.time_s[n - 1] - kinematics.time_s[0]) / static_cast<double>(n - 1) : kNone;

  Transaction transaction(connection_);
  DeleteDerivedChannels(test, config);
  auto insert = connection_.Prepare(
      "INSERT INTO derived_channels (test_id, config_id, name, dt_s, t0_s, sample_count, encoding, samples) "
      "VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8)");
  std::vector<std::byte> scratch;
  // The accessors only read the columns here. Only the channels with data
  // are stored: acceleration-only kinematics have 4 (docs/formats.md
  // "Derived-channel storage").
  for (const auto& [name, column, needs_rotation] :
       KinematicsChannels(const_cast<engine::Kinematics&>(kinematics))) {
    if (needs_rotation && !rotation) continue;
    const std::span<const double> values(column, static_cast<std::size_t>(n));
    const bool float32 = storage == engine::DerivedStorage::kFloat32 && name != time_channel;
    const char* encoding = engine::NameOf(float32 ? storage : engine::DerivedStorage::kFloat64);
    insert->BindAll(
        test, config, name, dt_s, t0_s, n, encoding,
        float32 ? Float32LittleEndianBytes(values, scratch) : Float64LittleEndianBytes(values, scratch));
    insert->Execute();
    insert->Reset();
  }
  transaction.Commit();
}

std::optional<engine::TestSummary> Catalogue::ReadSummary(TestId test, ConfigId config) {
  engine::TestSummary summary;
  {
    static const std::string kSelect =
        "SELECT " + SummaryColumnList() + " FROM results WHERE test_id = ?1 AND config_id = ?2";
    auto select = connection_.Prepare(kSelect);
    select->BindAll(test, config);
    if (!select->Step()) return std::nullopt;
    ReadSummaryFields(*select, 0, summary);
  }
  auto findings = connection_.Prepare(
      "SELECT check_name, channel, severity, detail FROM findings "
      "WHERE test_id = ?1 AND config_id = ?2 ORDER BY position");
  findings->BindAll(test, config);
  while (findings->Step())
    summary.findings.push_back({findings->ColumnText(0), findings->ColumnOptionalText(1),
                                ParseSeverity(findings->ColumnText(2)), findings->ColumnText(3)});
  auto conditioning = connection_.Prepare(
      "SELECT channel, filter, filter_cfc, prefiltered_cfc, bias_removed, bias_t1_s, bias_t2_s, time_shift_s "
      "FROM result_conditioning WHERE test_id = ?1 AND config_id = ?2 ORDER BY position");
  conditioning->BindAll(test, config);
  const auto optional = [&conditioning](int column) {
    return conditioning->ColumnIsNull(column) ? std::nullopt
                                              : std::optional<double>(conditioning->ColumnDouble(column));
  };
  while (conditioning->Step()) {
    engine::ChannelConditioning& record = summary.conditioning.emplace_back();
    record.channel = conditioning->ColumnText(0);
    record.filter_cfc = optional(2);
    record.prefiltered_cfc = optional(3);
    // FilterDescription's words for a filter left out because of the prefilter.
    record.filter_skipped_prefiltered = conditioning->ColumnText(1).rfind("none, prefiltered", 0) == 0;
    record.bias_removed = conditioning->ColumnDouble(4);
    record.bias_window_start_s = optional(5);
    record.bias_window_end_s = optional(6);
    record.time_shift_s = conditioning->ColumnDouble(7);
  }
  auto salvage = connection_.Prepare(
      "SELECT mode, channel, fault, action, partner, t1_s, t2_s, samples_replaced, rms_residual_before_g, "
      "rms_residual_after_g, channels_used, channels_total, repaired_samples FROM result_salvage "
      "WHERE test_id = ?1 AND config_id = ?2 ORDER BY position");
  salvage->BindAll(test, config);
  while (salvage->Step()) {
    if (!summary.salvage) {
      engine::SalvageAudit& record = summary.salvage.emplace();
      record.mode = salvage->ColumnText(0);
      const auto in_mps2 = [&salvage](int column) {
        return salvage->ColumnIsNull(column) ? std::numeric_limits<double>::quiet_NaN()
                                             : salvage->ColumnDouble(column) * engine::kStandardGravity;
      };
      record.rms_residual_before_mps2 = in_mps2(8);
      record.rms_residual_after_mps2 = in_mps2(9);
      record.channels_used = static_cast<int>(salvage->ColumnInt64(10));
      record.channels_total = static_cast<int>(salvage->ColumnInt64(11));
    }
    engine::SalvagedChannel& channel = summary.salvage->channels.emplace_back();
    channel.channel = salvage->ColumnText(1);
    channel.fault = ParseStored<engine::FaultKind>(salvage->ColumnText(2), "salvage fault");
    channel.action = ParseStored<engine::SalvageAction>(salvage->ColumnText(3), "salvage action");
    channel.partner = salvage->ColumnOptionalText(4);
    channel.t1_s = salvage->ColumnDouble(5);
    channel.t2_s = salvage->ColumnDouble(6);
    channel.samples_replaced = salvage->ColumnInt64(7);
    if (!salvage->ColumnIsNull(12)) {
      const std::span<const std::byte> bytes = salvage->ColumnBlob(12);
      channel.repaired_samples.resize(bytes.size() / sizeof(double));
      DecodeFloat64LittleEndian(bytes, channel.repaired_samples);
    }
  }
  return summary;
}

std::optional<engine::Kinematics> Catalogue::ReadKinematics(TestId test, ConfigId config) {
  std::int64_t n = -1;
  {
    auto count = connection_.Prepare(
        "SELECT sample_count FROM derived_channels WHERE test_id = ?1 AND config_id = ?2 AND name = "
        "'time_s'");
    count->BindAll(test, config);
    if (!count->Step()) return std::nullopt;
    n = count->ColumnInt64(0);
  }
  // A result without any channel that needs the rotation is an
  // acceleration-only one, stored without them (docs/formats.md
  // "Derived-channel storage"): they stay absent (empty), not NaN-filled.
  // Results stored before that hold them as NaN, and read back as stored.
  bool rotation = false;
  {
    std::set<std::string> rotation_channels;
    engine::Kinematics shapeless;
    for (const KinematicsChannel& channel : KinematicsChannels(shapeless))
      if (channel.needs_rotation) rotation_channels.insert(channel.name);
    auto names =
        connection_.Prepare("SELECT name FROM derived_channels WHERE test_id = ?1 AND config_id = ?2");
    names->BindAll(test, config);
    while (!rotation && names->Step()) rotation = rotation_channels.count(names->ColumnText(0)) > 0;
  }
  engine::Kinematics kinematics;
  if (rotation)
    kinematics.Resize(static_cast<Eigen::Index>(n));
  else
    kinematics.ResizeWithoutRotation(static_cast<Eigen::Index>(n));
  std::unordered_map<std::string, double*> destinations;
  for (const auto& [name, column, needs_rotation] : KinematicsChannels(kinematics))
    if (rotation || !needs_rotation) destinations.emplace(name, column);

  auto select = connection_.Prepare(
      "SELECT name, sample_count, samples, encoding FROM derived_channels WHERE test_id = ?1 AND "
      "config_id = ?2");
  select->BindAll(test, config);
  std::size_t found = 0;
  while (select->Step()) {
    const auto destination = destinations.find(select->ColumnText(0));
    if (destination == destinations.end()) continue;  // a channel this build does not know
    if (select->ColumnInt64(1) != n)
      throw InputError("derived channel '" + destination->first + "' of test '" + ReadTest(test).external_id +
                       "' has " + std::to_string(select->ColumnInt64(1)) + " samples, time_s has " +
                       std::to_string(n) + ".");
    const std::span<double> values(destination->second, static_cast<std::size_t>(n));
    const std::string encoding = select->ColumnText(3);
    if (encoding == engine::NameOf(engine::DerivedStorage::kFloat32))
      DecodeFloat32LittleEndian(select->ColumnBlob(2), values);
    else if (encoding == engine::NameOf(engine::DerivedStorage::kFloat64))
      DecodeFloat64LittleEndian(select->ColumnBlob(2), values);
    else  // the schema's CHECK allows no other
      throw InputError("derived channel '" + destination->first + "' of test '" + ReadTest(test).external_id +
                       "' has encoding '" + encoding + "', neither float64 nor float32.");
    destination->second = nullptr;  // mark as read
    ++found;
  }
  if (found != destinations.size()) {
    for (const auto& [name, column] : destinations)
      if (column != nullptr)
        throw InputError("derived channels of test '" + ReadTest(test).external_id + "' lack '" + name +
                         "'.");
  }
  return kinematics;
}

std::optional<ConfigId> Catalogue::ReadLatestResultConfig(TestId test) {
  auto select =
      connection_.Prepare("SELECT config_id FROM results WHERE test_id = ?1 ORDER BY id DESC LIMIT 1");
  select->Bind(1, test);
  if (!select->Step()) return std::nullopt;
  return ConfigId{select->ColumnInt64(0)};
}

// ------------------------------------------------------------------ results with labels

std::vector<LabelledResult> Catalogue::ReadResults(const TestFilter& filter, ResultSelection selection) {
  const std::string source = selection == ResultSelection::kLatest ? "v_latest_results" : "results";
  auto select = connection_.Prepare(
      "SELECT t.external_id, t.variant, c.id, c.name, c.config_hash, " + SummaryColumnList("r.") +
      ", EXISTS (SELECT 1 FROM result_salvage AS rs WHERE rs.test_id = r.test_id AND "
      "rs.config_id = r.config_id) FROM " +
      source +
      " AS r JOIN tests AS t ON t.id = r.test_id JOIN configs AS c ON c.id = r.config_id "
      "LEFT JOIN series AS s ON s.id = t.series_id WHERE " +
      internal::TestFilterTerms(filter) + " ORDER BY t.external_id, c.id");
  internal::BindTestFilter(*select, filter);
  std::vector<LabelledResult> results;
  while (select->Step()) {
    LabelledResult& result = results.emplace_back();
    result.test_id = select->ColumnText(0);
    result.variant = select->ColumnOptionalText(1);
    result.config_id = ConfigId{select->ColumnInt64(2)};
    result.config_name = select->ColumnText(3);
    result.config_hash = select->ColumnText(4);
    ReadSummaryFields(*select, 5, result.summary);
    result.salvaged = select->ColumnInt64(5 + static_cast<int>(engine::SummaryFields().size())) != 0;
  }
  return results;
}

}  // namespace napkin::db
