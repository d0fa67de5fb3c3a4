#pragma once
// Schema migrations gated on PRAGMA user_version: migration N runs when the
// catalogue's version is N-1, in its own transaction, and sets the version to
// N in that same transaction, so a failed migration leaves the previous
// version intact.
#include <span>

#include "db/sqlite.h"
#include "schema/migrations.h"

namespace napkin::db {

// 'NAPK' in PRAGMA application_id (set by migration 1) marks napkin catalogues.
inline constexpr std::int64_t kCatalogueApplicationId = 0x4E41504B;

// Checks `migrations` are numbered 1..N in order; throws std::invalid_argument otherwise.
void CheckMigrationList(std::span<const schema::Migration> migrations);

// Applies the migrations newer than the catalogue's user_version, oldest
// first. Returns the resulting version. The caller has checked the file is a
// napkin catalogue not newer than the list (see Catalogue::Open).
int ApplyMigrations(Connection& connection, std::span<const schema::Migration> migrations);

}  // namespace napkin::db
