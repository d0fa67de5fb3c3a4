#include "ingest/store.h"

#include <string>
#include <vector>

#include "records/test_record.h"

namespace napkin::ingest {

std::optional<db::TestId> StoreTest(db::Catalogue& catalogue, const engine::ArrayGeometry& array,
                                    const db::ArrayRow& array_record, db::TestRow record,
                                    const engine::TestSignals& signals, std::optional<db::TestId> replacing) {
  const std::vector<std::string> units = records::SlotUnits(array, signals.slots);
  db::Transaction transaction = catalogue.BeginTransaction();
  if (catalogue.ExistsTestByHash(record.content_hash)) return std::nullopt;
  if (replacing) catalogue.DeleteTest(*replacing);
  record.array_id = catalogue.WriteArray(array_record);
  const db::TestId test = catalogue.WriteTest(record);
  catalogue.WriteRawChannels(test, signals, units);
  transaction.Commit();
  return test;
}

}  // namespace napkin::ingest
