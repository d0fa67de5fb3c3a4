#include "records/array_record.h"

#include <nlohmann/json.hpp>

#include "common/error.h"
#include "formats/array_json.h"
#include "util/sha256.h"

namespace napkin::records {

db::ArrayRow MakeArrayRecord(const engine::ArrayGeometry& array) {
  db::ArrayRow record;
  record.name = array.name;
  record.definition_json = formats::ArrayToJson(array, "m").dump();
  record.definition_hash = util::Sha256Hex(record.definition_json);
  return record;
}

engine::ArrayGeometry DecodeArrayRecord(const db::ArrayRow& record) {
  const std::string source = "array '" + record.name + "' of the catalogue";
  nlohmann::json json;
  try {
    json = nlohmann::json::parse(record.definition_json);
  } catch (const nlohmann::json::parse_error&) {
    throw InputError(source + " is not valid JSON.");
  }
  return formats::ParseArrayJson(json, source);
}

}  // namespace napkin::records
