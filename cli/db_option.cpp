#include "cli/db_option.h"

#include <algorithm>
#include <iterator>
#include <utility>

#include "common/error.h"
#include "common/joined.h"
#include "records/test_inputs.h"
#include "util/text.h"

namespace napkin::cli {
namespace {

// "name (hash 0123456789ab), ..." of `configs`.
std::string ConfigList(const std::vector<db::ConfigRow>& configs) {
  return Joined(configs, [](const db::ConfigRow& config) {
    return config.name + " (hash " + config.config_hash.substr(0, 12) + ")";
  });
}

}  // namespace

db::Catalogue OpenCatalogue(const GlobalOptions& global, bool read_only) {
  db::CatalogueOptions options;
  options.read_only = read_only;
  // Never write into a damaged catalogue (init, import, synth, run, merge).
  options.check_integrity = !read_only;
  return db::Catalogue::Open(global.db_path, options);
}

engine::Kinematics ReadResultKinematics(db::Catalogue& catalogue, db::TestId test, db::ConfigId config) {
  if (std::optional<engine::Kinematics> stored = catalogue.ReadKinematics(test, config))
    return std::move(*stored);
  // The inputs and the computation of `napkin run` (records/test_inputs.h);
  // a results file of `run --results` carries no raw channels
  // (docs/formats.md "Results files"): nothing to recompute from.
  return records::RecomputeResult(catalogue, test, config).kinematics;
}

db::ConfigRow ResolveConfigSelector(db::Catalogue& catalogue, const std::string& selector) {
  const std::vector<db::ConfigRow> configs = catalogue.ReadAllConfigs();
  if (configs.empty())
    throw UsageError("--config '" + selector +
                     "': the catalogue has no processing configs yet; run `napkin run` first.");
  std::vector<db::ConfigRow> named;
  std::copy_if(configs.begin(), configs.end(), std::back_inserter(named),
               [&](const db::ConfigRow& config) { return config.name == selector; });
  if (named.size() == 1) return named.front();
  if (named.size() > 1)
    throw UsageError("--config '" + selector + "' names " + std::to_string(named.size()) +
                     " configs: " + ConfigList(named) + "; give a hash prefix instead.");
  const std::string prefix = util::ToLower(selector);
  std::vector<db::ConfigRow> hashed;
  std::copy_if(configs.begin(), configs.end(), std::back_inserter(hashed), [&](const db::ConfigRow& config) {
    return util::ToLower(config.config_hash).rfind(prefix, 0) == 0;
  });
  if (hashed.size() == 1) return hashed.front();
  if (hashed.empty())
    throw UsageError("--config '" + selector +
                     "' is neither the name nor a hash prefix of a config; the configs are " +
                     ConfigList(configs) + ".");
  throw UsageError("--config '" + selector + "' starts the hashes of " + std::to_string(hashed.size()) +
                   " configs: " + ConfigList(hashed) + "; give more of the hash.");
}

}  // namespace napkin::cli
