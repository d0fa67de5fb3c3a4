#include "cli/catalogue_protection.h"

#include <filesystem>
#include <system_error>
#include <vector>

#include "formats/output_destination.h"

namespace napkin::cli {

void ProtectCatalogueFromOutput(const std::string& db_path) {
  const std::string catalogue = "the catalogue '" + db_path + "'";
  std::vector<std::string> names = {db_path};
  std::error_code error;
  const std::filesystem::path resolved = std::filesystem::canonical(db_path, error);
  if (!error && resolved != std::filesystem::absolute(db_path)) names.push_back(resolved.string());
  for (const std::string& name : names) {
    formats::ProtectFromOutput(name, catalogue + " itself");
    formats::ProtectFromOutput(name + "-wal", "the write-ahead log of " + catalogue);
    formats::ProtectFromOutput(name + "-shm", "the shared-memory index of " + catalogue);
    formats::ProtectFromOutput(name + "-journal", "the rollback journal of " + catalogue);
  }
}

}  // namespace napkin::cli
