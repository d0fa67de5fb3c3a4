#include "cli/catalogue_access.h"

#include <filesystem>

#include "formats/array_json.h"
#include "formats/content_hash.h"
#include "formats/processing_config_json.h"

namespace napkin::cli {

db::Catalogue OpenCatalogue(const GlobalOptions& global, bool read_only) {
  db::CatalogueOptions options;
  options.read_only = read_only;
  return db::Catalogue::Open(global.db_path, options);
}

ResolvedConfig ResolveConfig(const std::string& name_or_path) {
  const std::string name = name_or_path.empty() ? "default" : name_or_path;
  const std::filesystem::path path = formats::ResolvePreset(name, "processing");
  ResolvedConfig resolved;
  resolved.config = formats::ReadProcessingConfig(path);
  resolved.record.name = path.stem().string();
  resolved.record.config_json = formats::CanonicalProcessingConfig(resolved.config);
  resolved.record.config_hash = formats::Sha256Hex(resolved.record.config_json);
  return resolved;
}

}  // namespace napkin::cli
