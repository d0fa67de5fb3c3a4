#include "app/result_selection.h"

#include <utility>

#include "common/error.h"
#include "common/joined.h"
#include "records/test_inputs.h"
#include "util/text.h"

namespace napkin::app {
namespace {

// "name (hash 0123456789ab), ..." of `configs`.
std::string ConfigList(const std::vector<db::ConfigRow>& configs) {
  return Joined(configs, [](const db::ConfigRow& config) {
    return config.name + " (hash " + config.config_hash.substr(0, 12) + ")";
  });
}

}  // namespace

std::optional<db::ConfigId> FindResult(db::Catalogue& catalogue, db::TestId test,
                                       const ResultChoice& choice) {
  if (std::holds_alternative<Latest>(choice)) return catalogue.ReadLatestResultConfig(test);
  std::optional<db::ConfigId> config;
  if (const auto* stored = std::get_if<Stored>(&choice))
    config = ResolveConfigSelector(catalogue, stored->selector, stored->option).id;
  else
    config =
        catalogue.FindConfigByHash(ResolveConfig(std::get<Preset>(choice).name_or_path).record.config_hash);
  if (!config || !catalogue.ReadSummary(test, *config)) return std::nullopt;
  return config;
}

TestResult ResultOf(db::Catalogue& catalogue, const std::string& test_id, const ResultChoice& choice) {
  const std::optional<db::TestId> test = catalogue.FindTestByExternalId(test_id);
  if (!test) throw NotFoundError("test '" + test_id + "' is not in catalogue '" + catalogue.path() + "'.");
  const std::optional<db::ConfigId> config = FindResult(catalogue, *test, choice);
  if (config) return {*test, *config};
  if (std::holds_alternative<Latest>(choice))
    throw InputError("test '" + test_id + "' has no results yet; run `napkin run` first.");
  const std::string& named = std::holds_alternative<Stored>(choice) ? std::get<Stored>(choice).selector
                                                                    : std::get<Preset>(choice).name_or_path;
  throw InputError("test '" + test_id + "' has no results for config '" + named +
                   "' yet; run `napkin run --config " + named + "` first.");
}

engine::Kinematics ReadResultKinematics(db::Catalogue& catalogue, db::TestId test, db::ConfigId config) {
  if (std::optional<engine::Kinematics> stored = catalogue.ReadKinematics(test, config))
    return std::move(*stored);
  // The inputs and the computation of `napkin run` (records/test_inputs.h);
  // a results file of `run --results` carries no raw channels
  // (docs/formats.md "Results files"): nothing to recompute from.
  return records::RecomputeResult(catalogue, test, config).kinematics;
}

ResultChannels ReadResultChannels(db::Catalogue& catalogue, db::TestId test,
                                  std::optional<db::ConfigId> config, bool recorded) {
  ResultChannels channels{catalogue.ReadTestSignals(test), {}, {}};
  engine::TestSignals& signals = channels.signals;
  for (Eigen::Index column = 0; column < signals.samples.cols(); ++column)
    if (const std::optional<double> cfc = signals.PrefilteredCfc(column))
      channels.notes.push_back(signals.slots[static_cast<std::size_t>(column)] +
                               ": recorded as already filtered" +
                               (*cfc > 0 ? " at CFC " + util::FormatNumber(*cfc) : std::string()) +
                               ", which this file cannot say.");
  if (!config) return channels;
  const std::optional<engine::TestSummary> summary = catalogue.ReadSummary(test, *config);
  if (!summary || !summary->salvage) return channels;
  const std::string test_id = catalogue.ReadTest(test).external_id;
  for (const engine::SalvagedChannel& channel : summary->salvage->channels) {
    const std::string interval =
        util::FormatNumber(channel.t1_s, 6) + " to " + util::FormatNumber(channel.t2_s, 6) + " s";
    if (channel.action == engine::SalvageAction::kExcluded || recorded) {
      channels.notes.push_back(channel.channel + ": as recorded; salvage (" + summary->salvage->mode + ") " +
                               engine::NameOf(channel.action) + " it (" + engine::NameOf(channel.fault) +
                               ", " + interval + ").");
      continue;
    }
    const int column = signals.FindSlot(channel.channel);
    if (column < 0)
      throw InputError("test '" + test_id + "': its salvage record repairs channel '" + channel.channel +
                       "', which the test does not have.");
    if (channel.repaired_samples.empty())
      throw InputError("test '" + test_id + "': the repaired channel '" + channel.channel +
                       "' of its result was not kept (computed before schema version 13); `napkin run "
                       "--force` computes it again.");
    if (static_cast<Eigen::Index>(channel.repaired_samples.size()) != signals.size())
      throw InputError("test '" + test_id + "': the repaired channel '" + channel.channel + "' has " +
                       std::to_string(channel.repaired_samples.size()) + " samples, the recorded one " +
                       std::to_string(signals.size()) + ".");
    signals.samples.col(column) =
        Eigen::Map<const Eigen::VectorXd>(channel.repaired_samples.data(), signals.size());
    channels.repaired.push_back(channel.channel);
    std::string what = engine::NameOf(channel.action);
    if (channel.partner) what += " with " + *channel.partner;
    if (channel.samples_replaced > 0)
      what += ", " + std::to_string(channel.samples_replaced) + " samples by the rigid-body prediction";
    channels.notes.push_back(channel.channel + ": repaired by salvage (" + engine::NameOf(channel.fault) +
                             ", " + interval + "; " + what + ").");
  }
  return channels;
}

db::ConfigRow ResolveConfigSelector(db::Catalogue& catalogue, const std::string& selector,
                                    const std::string& option) {
  const std::vector<db::ConfigRow> configs = catalogue.ReadAllConfigs();
  if (configs.empty())
    throw UsageError(option + " '" + selector +
                     "': the catalogue has no processing configs yet; run `napkin run` first.");
  return configs[MatchConfigSelector(configs, option, selector)];
}

std::size_t MatchConfigSelector(const std::vector<db::ConfigRow>& configs, const std::string& option,
                                const std::string& selector, const std::string& listed) {
  if (selector.empty()) throw UsageError(option + " must not be empty; give a config's name or hash prefix.");
  // The indexes of the configs `matches` accepts.
  const auto matching = [&](const auto& matches) {
    std::vector<std::size_t> found;
    for (std::size_t i = 0; i < configs.size(); ++i)
      if (matches(configs[i])) found.push_back(i);
    return found;
  };
  const auto listing = [&](const std::vector<std::size_t>& indexes) {
    std::vector<db::ConfigRow> rows;
    rows.reserve(indexes.size());
    for (const std::size_t i : indexes) rows.push_back(configs[i]);
    return ConfigList(rows);
  };
  const std::vector<std::size_t> named =
      matching([&](const db::ConfigRow& config) { return config.name == selector; });
  if (named.size() == 1) return named.front();
  if (named.size() > 1)
    throw UsageError(option + " '" + selector + "' names " + std::to_string(named.size()) +
                     " configs: " + listing(named) + "; give a hash prefix instead.");
  const std::string prefix = util::ToLower(selector);
  const std::vector<std::size_t> hashed = matching(
      [&](const db::ConfigRow& config) { return util::ToLower(config.config_hash).rfind(prefix, 0) == 0; });
  if (hashed.size() == 1) return hashed.front();
  if (hashed.empty())
    throw UsageError(option + " '" + selector + "' is neither the name nor a hash prefix of a config; " +
                     listed + " " + ConfigList(configs) + ".");
  throw UsageError(option + " '" + selector + "' starts the hashes of " + std::to_string(hashed.size()) +
                   " configs: " + listing(hashed) + "; give more of the hash.");
}

}  // namespace napkin::app
