#include "schema/migrations.h"

#include <array>
#include <cstddef>
#include <iterator>
#include <string_view>

#include "common/embedded_file.h"

namespace napkin::schema {
namespace {

// kEmbeddedFiles: the NNN_*.sql files in order (schema/CMakeLists.txt).
#include "embedded_migrations.inc"

// The NNN prefix of a migration's file name; schema/CMakeLists.txt has
// checked every name and the numbering before the build.
constexpr int VersionOf(std::string_view name) {
  return (name[0] - '0') * 100 + (name[1] - '0') * 10 + (name[2] - '0');
}

constexpr std::array<Migration, std::size(kEmbeddedFiles)> MigrationTable() {
  std::array<Migration, std::size(kEmbeddedFiles)> migrations{};
  for (std::size_t i = 0; i < migrations.size(); ++i)
    migrations[i] = {VersionOf(kEmbeddedFiles[i].name), kEmbeddedFiles[i].name, kEmbeddedFiles[i].bytes};
  return migrations;
}

constexpr auto kMigrations = MigrationTable();

constexpr bool NumberedOneToN() {
  for (std::size_t i = 0; i < kMigrations.size(); ++i)
    if (kMigrations[i].version != static_cast<int>(i) + 1) return false;
  return true;
}
static_assert(NumberedOneToN(), "the migrations must be numbered 1..N in order (schema/CMakeLists.txt)");

}  // namespace

std::span<const Migration> Migrations() { return kMigrations; }

}  // namespace napkin::schema
