#include "ingest/synthetic_import.h"

#include <nlohmann/json.hpp>
#include <utility>

#include "common/error.h"
#include "formats/array_json.h"
#include "ingest/content_hash.h"
#include "ingest/store.h"
#include "records/array_record.h"
#include "util/text.h"

namespace napkin::ingest {

SynthPlan PlanSynth(const SynthRequest& request) {
  // Names are UTF-8, printable and of sane length, as import's (util::CheckName).
  for (const auto& [option, value] : {std::pair<const char*, const std::string*>{"--series", &request.series},
                                      {"--test-id", &request.test_id}}) {
    if (value->empty()) continue;
    try {
      util::CheckName(option, *value);
    } catch (const InputError& error) {
      throw UsageError(error.what());
    }
  }
  SynthPlan plan;
  plan.array = formats::LoadArray(request.array);
  plan.array_record = records::MakeImportedArrayRecord(plan.array);
  const std::string name = synth::SynthScenarioName(request.scenario);
  plan.series = request.series.empty() ? name : request.series;
  synth::ScenarioOptions& scenario = plan.scenario;
  scenario.scenario = request.scenario;
  scenario.id_prefix = request.test_id.empty() ? name : request.test_id;
  scenario.count = request.count.value_or(synth::DefaultCount(request.scenario));
  scenario.seed = request.seed;
  scenario.synth.rate_hz = request.rate_hz;
  if (!synth::HasChosenDuration(request.scenario) && (request.samples || request.duration_s))
    throw InputError("--samples and --duration apply to the random scenario only; " + name +
                     " has the report's fixed duration.");
  scenario.duration_s =
      request.samples ? (*request.samples - 1) / request.rate_hz : request.duration_s.value_or(0.2);
  plan.tests = synth::ScenarioTests(scenario);
  return plan;
}

SynthCounts StoreSynthTests(db::Catalogue& catalogue, const SynthPlan& plan,
                            const std::function<void(std::size_t done, std::size_t total)>& progress) {
  const std::string name = synth::SynthScenarioName(plan.scenario.scenario);
  SynthCounts counts;
  for (const synth::ScenarioTest& scenario_test : plan.tests) {
    const synth::SyntheticTest test = synth::SynthScenarioTest(plan.array, plan.scenario, scenario_test);
    nlohmann::json synthetic = {{"scenario", name}, {"rate_hz", plan.scenario.synth.rate_hz}};
    if (scenario_test.seed) synthetic["seed"] = *scenario_test.seed;
    if (synth::HasChosenDuration(plan.scenario.scenario)) synthetic["duration_s"] = plan.scenario.duration_s;
    if (const std::optional<synth::HeadImpact>& impact = scenario_test.impact) {
      const Eigen::Vector3d& contact = impact->contact_point_body_m;
      synthetic["impact"] = {{"speed_mps", impact->speed_mps},
                             {"trajectory_deg", impact->trajectory_deg},
                             {"contact_point_body_m", {contact.x(), contact.y(), contact.z()}},
                             {"pulse_s", impact->pulse_s},
                             {"restitution", impact->restitution},
                             {"noise_g", impact->noise_g},
                             {"noise_radps", impact->noise_radps}};
    }

    db::TestRow record;
    record.external_id = scenario_test.external_id;
    record.series = plan.series;
    record.variant = scenario_test.variant;
    record.metadata_json = nlohmann::json{{"synthetic", synthetic}}.dump();
    record.initial_state = test.initial;
    record.source_path = "synth:" + name;
    record.content_hash = SyntheticContentHash(plan.array_record, test);
    if (StoreTest(catalogue, plan.array, plan.array_record, record, test.signals)) {
      ++counts.added;
    } else {
      ++counts.present;
    }
    if (progress) progress(static_cast<std::size_t>(counts.added + counts.present), plan.tests.size());
  }
  return counts;
}

}  // namespace napkin::ingest
