// `napkin init`: create a catalogue, or migrate an existing one in place to
// this build's schema (Catalogue::Open applies the missing migrations, one
// transaction each, keeping every row). Says which it did.
#include <fmt/core.h>

#include <filesystem>
#include <optional>

#include "cli/catalogue_option.h"
#include "cli/command.h"
#include "db/sqlite.h"

namespace napkin::cli {
namespace {

// The schema version of an existing catalogue file before init touches it;
// nullopt when the file cannot be read as SQLite (Catalogue::Open then
// explains why) or is empty.
std::optional<std::int64_t> ExistingSchemaVersion(const std::string& path) {
  std::error_code error;
  if (!std::filesystem::exists(path, error) || std::filesystem::file_size(path, error) == 0)
    return std::nullopt;
  try {
    db::Connection connection = db::Connection::Open(path, db::ConnectionOptions{.read_only = true});
    return connection.PragmaInt("user_version");
  } catch (const std::exception&) {
    return std::nullopt;
  }
}

class InitCommand : public Command {
 public:
  CLI::App* Setup(CLI::App& app, const GlobalOptions& global) override {
    global_ = &global;
    return app.add_subcommand("init", "create a catalogue, or migrate an existing one to this version");
  }

  int Run() override {
    const std::string& path = global_->db_path;
    const std::optional<std::int64_t> before = ExistingSchemaVersion(path);
    db::Catalogue catalogue = OpenCatalogue(*global_);
    const int now = catalogue.schema_version();
    if (!before || *before == 0) {
      fmt::print("created catalogue '{}' (schema version {}).\n", path, now);
    } else if (*before < now) {
      fmt::print("migrated catalogue '{}' from schema version {} to {}.\n", path, *before, now);
    } else {
      fmt::print("catalogue '{}' is up to date (schema version {}).\n", path, now);
    }
    return kExitOk;
  }

 private:
  const GlobalOptions* global_ = nullptr;
};

}  // namespace

std::unique_ptr<Command> MakeInitCommand() { return std::make_unique<InitCommand>(); }

}  // namespace napkin::cli
