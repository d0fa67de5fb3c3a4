// Catalogue: the inbox's failures of tests that never became a test row
// (schema/016_inbox_failures.sql; docs/serve.md "Inbox").
#include "db/catalogue.h"
#include "db/catalogue_internal.h"

namespace napkin::db {
namespace {

constexpr const char* kInboxFailureColumns =
    "source, test_name, series, variant, kind, error, signature, failed_at";

InboxFailure ReadInboxFailureRow(Statement& row) {
  InboxFailure failure;
  failure.source = row.ColumnText(0);
  failure.test_name = row.ColumnText(1);
  failure.series = row.ColumnText(2);
  failure.variant = row.ColumnText(3);
  failure.kind = row.ColumnText(4);
  failure.error = row.ColumnText(5);
  failure.signature = row.ColumnText(6);
  failure.failed_at = row.ColumnText(7);
  return failure;
}

}  // namespace

void Catalogue::WriteInboxFailure(const InboxFailure& failure) {
  // One statement: the test's earlier failure is replaced atomically.
  auto upsert =
      connection_.Prepare(std::string("INSERT OR REPLACE INTO inbox_failures (") + kInboxFailureColumns +
                          ") VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, " + internal::IsoTimestampSql("?8") + ")");
  upsert->BindAll(failure.source, failure.test_name, failure.series, failure.variant, failure.kind,
                  failure.error, failure.signature, clock_());
  upsert->Execute();
}

void Catalogue::DeleteInboxFailure(const std::string& source) {
  auto remove = connection_.Prepare("DELETE FROM inbox_failures WHERE source = ?1");
  remove->Bind(1, source);
  remove->Execute();
}

std::optional<InboxFailure> Catalogue::ReadInboxFailure(const std::string& source) {
  auto select = connection_.Prepare(std::string("SELECT ") + kInboxFailureColumns +
                                    " FROM inbox_failures WHERE source = ?1");
  select->Bind(1, source);
  if (!select->Step()) return std::nullopt;
  return ReadInboxFailureRow(*select);
}

std::vector<InboxFailure> Catalogue::ReadInboxFailures() {
  auto select = connection_.Prepare(std::string("SELECT ") + kInboxFailureColumns +
                                    " FROM inbox_failures ORDER BY source");
  std::vector<InboxFailure> failures;
  while (select->Step()) failures.push_back(ReadInboxFailureRow(*select));
  return failures;
}

}  // namespace napkin::db
