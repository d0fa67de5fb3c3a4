#include "db/migrate.h"

#include <stdexcept>
#include <string>

namespace napkin::db {

void CheckMigrationList(std::span<const schema::Migration> migrations) {
  for (std::size_t i = 0; i < migrations.size(); ++i)
    if (migrations[i].version != static_cast<int>(i) + 1)
      throw std::invalid_argument("migration '" + std::string(migrations[i].name) + "' has version " +
                                  std::to_string(migrations[i].version) + ", expected " +
                                  std::to_string(i + 1));
}

int ApplyMigrations(Connection& connection, std::span<const schema::Migration> migrations) {
  CheckMigrationList(migrations);
  int version = static_cast<int>(connection.PragmaInt("user_version"));
  if (version >= static_cast<int>(migrations.size())) return version;

  // Foreign-key enforcement is switched off while migrating (it cannot change
  // inside a transaction) so a migration may rebuild a table the SQLite way
  // (create new, copy, drop old, rename); PRAGMA foreign_key_check then
  // verifies the result before each commit.
  connection.Execute("PRAGMA foreign_keys = OFF");
  try {
    for (;;) {
      Transaction transaction(connection);
      // Read again under the write lock: another process opening the same
      // new catalogue at the same moment may have applied it meanwhile.
      version = static_cast<int>(connection.PragmaInt("user_version"));
      if (version >= static_cast<int>(migrations.size())) break;
      const schema::Migration& migration = migrations[static_cast<std::size_t>(version)];
      connection.Execute(migration.sql);
      {
        auto violations = connection.Prepare("PRAGMA foreign_key_check");
        if (violations->Step())
          throw DatabaseError("migration '" + std::string(migration.name) +
                                  "' leaves a foreign-key violation in table '" + violations->ColumnText(0) +
                                  "'.",
                              SQLITE_CONSTRAINT_FOREIGNKEY);
      }
      // PRAGMA takes no bound parameters; the version is our own integer.
      connection.Execute("PRAGMA user_version = " + std::to_string(migration.version));
      transaction.Commit();
      version = migration.version;
    }
  } catch (...) {
    connection.Execute("PRAGMA foreign_keys = ON");
    throw;
  }
  connection.Execute("PRAGMA foreign_keys = ON");
  return version;
}

}  // namespace napkin::db
