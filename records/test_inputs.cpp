#include "records/test_inputs.h"

#include "common/error.h"
#include "records/array_record.h"
#include "records/config_record.h"

namespace napkin::records {

TestInputs TestInputReader::Read(db::TestId test) {
  const db::TestRow record = catalogue_.ReadTest(test);
  TestInputs inputs;
  inputs.external_id = record.external_id;
  inputs.initial = record.initial_state;
  inputs.signals = catalogue_.ReadTestSignals(test);
  auto found = arrays_.find(record.array_id);
  if (found == arrays_.end()) {
    DecodedArray decoded;
    decoded.record = std::make_shared<const db::ArrayRow>(catalogue_.ReadArray(record.array_id));
    try {
      decoded.geometry = std::make_shared<const engine::ArrayGeometry>(DecodeArrayRecord(*decoded.record));
    } catch (const InputError& error) {
      decoded.error = error.what();
    }
    found = arrays_.emplace(record.array_id, std::move(decoded)).first;
  }
  inputs.array = found->second.geometry;
  inputs.array_error = found->second.error;
  inputs.array_record = found->second.record;
  return inputs;
}

engine::ProcessedTest ComputeResult(const TestInputs& inputs, const engine::ProcessingConfig& config) {
  if (!inputs.array) throw InputError(inputs.array_error);
  return engine::ProcessTest(*inputs.array, inputs.signals, inputs.initial, config);
}

void ComputeResult(const TestInputs& inputs, const engine::ProcessingConfig& config,
                   engine::Workspace& workspace, engine::ProcessedTest& out, engine::SeriesKept series) {
  if (!inputs.array) throw InputError(inputs.array_error);
  engine::ProcessTest(*inputs.array, inputs.signals, inputs.initial, config, workspace, out, nullptr, series);
}

engine::ProcessedTest RecomputeResult(db::Catalogue& catalogue, db::TestId test, db::ConfigId config) {
  const TestInputs inputs = TestInputReader(catalogue).Read(test);
  if (!inputs.array) throw InputError(inputs.array_error);
  const engine::ProcessingConfig processing = DecodeConfigRecord(catalogue.ReadConfig(config));
  if (inputs.signals.samples.cols() == 0)
    throw InputError("test '" + inputs.external_id +
                     "' has no stored derived channels (its config stores none) and no raw channels to "
                     "recompute them from (a results file of `run --results` holds none); export it from the "
                     "catalogue the results were merged into.");
  return ComputeResult(inputs, processing);
}

}  // namespace napkin::records
