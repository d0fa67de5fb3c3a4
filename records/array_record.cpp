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

db::ArrayRow MakeImportedArrayRecord(const engine::ArrayGeometry& array,
                                     const std::filesystem::path& config_dir) {
  db::ArrayRow record = MakeArrayRecord(array);
  // A name that is no file name names no preset (import refuses it later).
  if (array.name.empty() || array.name.find('/') != std::string::npos || array.name.starts_with('.'))
    return record;
  const std::filesystem::path preset = config_dir / "arrays" / (array.name + ".json");
  std::error_code error;
  if (!std::filesystem::is_regular_file(preset, error)) return record;
  std::string preset_hash;
  try {
    preset_hash = MakeArrayRecord(formats::ReadArrayJson(preset)).definition_hash;
  } catch (const InputError&) {
    return record;  // a broken preset is refused where it is used, not here
  }
  if (preset_hash != record.definition_hash)
    record.name = db::HashQualifiedArrayName(record.name, record.definition_hash);
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
