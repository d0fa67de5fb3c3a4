#include "app/db_protection.h"

#include <filesystem>
#include <system_error>
#include <vector>

#include "util/output_destination.h"

namespace napkin::app {

void ProtectCatalogueFromOutput(const std::string& db_path) {
  const std::string catalogue = "the catalogue '" + db_path + "'";
  std::vector<std::string> names = {db_path};
  std::error_code error;
  const std::filesystem::path resolved = std::filesystem::canonical(db_path, error);
  if (!error && resolved != std::filesystem::absolute(db_path)) names.push_back(resolved.string());
  for (const std::string& name : names) {
    util::ProtectFromOutput(name, catalogue + " itself");
    util::ProtectFromOutput(name + "-wal", "the write-ahead log of " + catalogue);
    util::ProtectFromOutput(name + "-shm", "the shared-memory index of " + catalogue);
    util::ProtectFromOutput(name + "-journal", "the rollback journal of " + catalogue);
  }
}

void ProtectInputFromOutput(const std::filesystem::path& input, const std::string& what) {
  if (input.empty()) return;
  util::ProtectFromOutput(input, what + " '" + input.string() + "' that this command reads",
                          util::Refusal::kUsage);
}

}  // namespace napkin::app
