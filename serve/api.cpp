#include "serve/api.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <set>
#include <vector>

#include "app/comparison.h"
#include "app/export.h"
#include "app/failure.h"
#include "app/limits.h"
#include "app/query.h"
#include "app/report_builder.h"
#include "app/request_options.h"
#include "app/result_selection.h"
#include "app/table_output.h"
#include "common/error.h"
#include "common/joined.h"
#include "db/catalogue.h"
#include "db/query_kinds.h"
#include "formats/csv.h"
#include "formats/zip_archive.h"
#include "util/text.h"

namespace napkin::serve {
namespace {

using Json = nlohmann::ordered_json;

// Text that may hold bytes that are not UTF-8 (stored names of an older napkin): U+FFFD, never a failure.
std::string Dump(const Json& json) {
  return json.dump(-1, ' ', false, Json::error_handler_t::replace) + "\n";
}

// The catalogue opened read-only for one request: a request never writes it
// (docs/serve.md "Safety").
db::Catalogue OpenForRequest(const ApiOptions& options) {
  db::CatalogueOptions open;
  open.read_only = true;
  open.busy_timeout_ms = options.busy_timeout_ms;
  return db::Catalogue::Open(options.db_path, open);
}

// The error for parameter `name`, which is not one of `known`.
UsageError UnknownParameter(const std::string& name, std::initializer_list<std::string_view> known) {
  std::string list;
  for (std::string_view k : known) {
    if (!list.empty()) list += ", ";
    list += k;
  }
  return UsageError("unknown parameter '" + name + "' (this route takes " + list + ").");
}

// Every parameter of `params` is one of `known`; a misspelt one is a 400, not a silent no-op.
void CheckParameters(const Params& params, std::initializer_list<std::string_view> known) {
  for (const auto& [name, value] : params)
    if (std::find(known.begin(), known.end(), name) == known.end()) throw UnknownParameter(name, known);
}

std::vector<std::string> All(const Params& params, const std::string& name) {
  std::vector<std::string> values;
  const auto [first, last] = params.equal_range(name);
  for (auto it = first; it != last; ++it) values.push_back(it->second);
  return values;
}

// A parameter given at most once; empty when absent.
std::optional<std::string> One(const Params& params, const std::string& name) {
  if (params.count(name) > 1) throw UsageError("parameter '" + name + "' is given more than once.");
  const auto it = params.find(name);
  if (it == params.end()) return std::nullopt;
  return it->second;
}

// The series a report route names: exactly one, never empty.
std::string SeriesOf(const Params& params) {
  CheckParameters(params, {"series"});
  const std::optional<std::string> series = One(params, "series");
  if (!series || series->empty())
    throw UsageError("parameter 'series' is required (the series the report shows).");
  return *series;
}

// `text` as a JavaScript string literal inside an HTML <script>: JSON, ASCII only, and no "</"
// that could end the script.
std::string ScriptString(const std::string& text) {
  std::string literal = Json(text).dump(-1, ' ', true, Json::error_handler_t::replace);
  for (std::size_t at = literal.find("</"); at != std::string::npos; at = literal.find("</", at + 3))
    literal.replace(at, 2, "<\\/");
  return literal;
}

// How often the live report asks whether its series changed.
constexpr int kReportPollMs = 3000;

// The live report's script. Every few seconds it asks ReportVersion; when the answer changes it
// fetches the current page, puts its <main> and chart data in place of the open page's and runs
// the page's own drawing script again (the script after #napkin-data, formats/html_report.cpp):
// the reader keeps the page, its scroll position and the charting library, no reload. A note in
// the corner says when the page last changed, or that the service does not answer.
// <html data-live-updates="N"> counts the updates (tests/serve: the page was never reloaded).
constexpr const char* kLiveReportScript =
    R"js(<div id="napkin-live" style="position: fixed; right: 8px; bottom: 8px; padding: 2px 8px; font: 12px sans-serif; color: #555; background: rgba(255, 255, 255, 0.9); border: 1px solid #ccd; border-radius: 3px;">live: updates as tests arrive</div>
<script>
(function () {
  'use strict';
  var version = @VERSION@, series = @SERIES@, updates = 0, busy = false;
  var note = document.getElementById('napkin-live');
  var versionUrl = '/api/v1/report/version?series=' + encodeURIComponent(series);
  var pageUrl = '/report?series=' + encodeURIComponent(series);
  function clock() { return new Date().toLocaleTimeString(); }
  function replaceReport(text, newVersion) {
    var fresh = new DOMParser().parseFromString(text, 'text/html');
    var main = fresh.querySelector('main'), data = fresh.getElementById('napkin-data');
    var draw = data ? data.nextElementSibling : null;
    if (!main || !draw || draw.tagName !== 'SCRIPT') throw new Error('the service sent a page without a report');
    document.querySelectorAll('.napkin-script-error').forEach(function (box) { box.remove(); });
    document.querySelector('main').replaceWith(document.adoptNode(main));
    document.getElementById('napkin-data').textContent = data.textContent;
    var run = document.createElement('script');
    run.textContent = draw.textContent;
    document.body.appendChild(run);
    run.remove();
    version = newVersion;
    document.documentElement.setAttribute('data-live-updates', String(++updates));
    note.textContent = 'live: updated at ' + clock();
  }
  setInterval(function () {
    if (busy) return;
    busy = true;
    fetch(versionUrl).then(function (r) { return r.json(); }).then(function (answer) {
      if (!answer.version || answer.version === version) return null;
      return fetch(pageUrl).then(function (r) {
        if (!r.ok) throw new Error('HTTP ' + r.status);
        return r.text();
      }).then(function (text) { replaceReport(text, answer.version); });
    }).catch(function (e) {
      note.textContent = 'live: the service does not answer (' + clock() + ')';
      if (!(e instanceof TypeError)) window.napkinReportError('live update: ' + (e && e.message ? e.message : e));
    }).finally(function () { busy = false; });
  }, @POLL_MS@);
})();
</script>
)js";

// `text` percent-decoded; '+' a space when `plus_is_space` (a query). A '%'
// not followed by two hex digits stays as it is.
std::string PercentDecoded(std::string_view text, bool plus_is_space) {
  const auto hex = [](char c) -> int {
    if (c >= '0' && c <= '9') return c - '0';
    if (c >= 'a' && c <= 'f') return c - 'a' + 10;
    if (c >= 'A' && c <= 'F') return c - 'A' + 10;
    return -1;
  };
  std::string decoded;
  decoded.reserve(text.size());
  for (std::size_t i = 0; i < text.size(); ++i) {
    if (text[i] == '%' && i + 2 < text.size() && hex(text[i + 1]) >= 0 && hex(text[i + 2]) >= 0) {
      decoded += static_cast<char>(hex(text[i + 1]) * 16 + hex(text[i + 2]));
      i += 2;
    } else if (text[i] == '+' && plus_is_space) {
      decoded += ' ';
    } else {
      decoded += text[i];
    }
  }
  return decoded;
}

}  // namespace

Params ParseQuery(std::string_view target) {
  Params params;
  const std::size_t question = target.find('?');
  if (question == std::string_view::npos) return params;
  std::string_view query = target.substr(question + 1);
  if (const std::size_t hash = query.find('#'); hash != std::string_view::npos) query = query.substr(0, hash);
  while (!query.empty()) {
    const std::size_t amp = query.find('&');
    const std::string_view pair = query.substr(0, amp);
    query = amp == std::string_view::npos ? std::string_view() : query.substr(amp + 1);
    if (pair.empty()) continue;
    const std::size_t equals = pair.find('=');
    const std::string name = PercentDecoded(pair.substr(0, equals), true);
    const std::string value =
        equals == std::string_view::npos ? std::string() : PercentDecoded(pair.substr(equals + 1), true);
    params.emplace(name, value);
  }
  return params;
}

std::vector<std::string> PathSegments(std::string_view target) {
  std::string_view path = target.substr(0, target.find('?'));
  std::vector<std::string> segments;
  if (path.starts_with("/")) path.remove_prefix(1);
  for (;;) {
    const std::size_t slash = path.find('/');
    segments.push_back(PercentDecoded(path.substr(0, slash), false));
    if (slash == std::string_view::npos) break;
    path.remove_prefix(slash + 1);
  }
  return segments;
}

std::string DecodedPath(std::string_view target) {
  return PercentDecoded(target.substr(0, target.find('?')), false);
}

Response JsonError(int status, const std::string& sentence) {
  return Response{status, "application/json", Dump(Json{{"error", sentence}})};
}

Response ErrorResponse(const std::exception_ptr& error, const std::string& db_path) {
  const app::Failure failure = app::DescribeFailure(error, db_path);
  int status = 500;
  switch (failure.category) {
    case app::FailureCategory::kUsage:
    case app::FailureCategory::kInput:
    case app::FailureCategory::kScreening:
      status = 400;
      break;
    case app::FailureCategory::kNotFound:
      status = 404;
      break;
    case app::FailureCategory::kCatalogueBusy:
      status = 503;
      break;
    case app::FailureCategory::kCatalogue:
    case app::FailureCategory::kOutOfMemory:
    case app::FailureCategory::kInternal:
      status = 500;
      break;
  }
  return JsonError(status, failure.sentence);
}

Response Api::Query(std::string_view kind, const Params& params) const {
  // An unknown kind is an unknown resource (404), refused in the sentence `napkin query` and
  // napkin.Catalogue.query give (db/query_kinds.h).
  const db::QueryKindSpec* spec = db::FindQueryKind(kind);
  if (!spec) throw NotFoundError(db::UnknownQueryKindSentence(kind));
  CheckParameters(params, {"where", "sort", "limit", "series", "variant", "config", "limits"});
  app::Query query;
  query.kind = spec->name;
  query.filters.where = All(params, "where");
  query.filters.sort = All(params, "sort");
  query.filters.tests.series = All(params, "series");
  query.filters.tests.variants = All(params, "variant");
  query.filters.front_end = app::FrontEnd::kService;
  query.filters.limit = One(params, "limit").value_or("");
  query.filters.config = One(params, "config").value_or("");
  query.limits = One(params, "limits");
  // A limit set by preset name only: no request makes the service read a file it names
  // (docs/serve.md "Safety").
  if (query.limits) {
    const std::vector<std::string> presets = app::LimitPresets();
    if (std::find(presets.begin(), presets.end(), *query.limits) == presets.end())
      throw UsageError("parameter 'limits' must be a limits preset (" + Joined(presets) + "), not " +
                       util::Quoted(*query.limits) + "; the service reads no file a request names.");
  }
  // Checked before the catalogue is opened, as `napkin query` does (app/query.h).
  const app::PreparedQuery prepared = app::PrepareQuery(query);
  db::Catalogue catalogue = OpenForRequest(options_);
  return Response{200, "application/json",
                  app::FormatTable(app::RunQuery(catalogue, prepared), app::TableFormat::kJson)};
}

Response Api::TestSummary(const std::string& test_id) const {
  db::Catalogue catalogue = OpenForRequest(options_);
  if (!catalogue.FindTestByExternalId(test_id))
    throw NotFoundError("test '" + test_id + "' is not in catalogue '" + catalogue.path() + "'.");
  Json summary;
  summary["test_id"] = test_id;
  // The kinds the table gives the summary (db::QueryKindSpec::test_summary), in its order.
  for (const db::QueryKindSpec& kind : db::QueryKinds()) {
    if (kind.test_summary == db::TestSummaryPart::kNone) continue;
    app::Query query;
    query.kind = kind.name;
    app::PreparedQuery prepared = app::PrepareQuery(query);
    prepared.request.tests.external_ids = {test_id};
    const db::Table table = app::RunQuery(catalogue, prepared);
    if (kind.test_summary == db::TestSummaryPart::kAllRows) {
      // A test has any number of findings: all of them.
      Json rows = Json::array();
      for (const std::vector<db::Cell>& row : table.rows) rows.push_back(app::TableRowJson(table, row));
      summary[kind.name] = std::move(rows);
    } else {
      summary[kind.name] = table.rows.empty() ? Json(nullptr) : app::TableRowJson(table, table.rows.front());
    }
  }
  return Response{200, "application/json", Dump(summary)};
}

Response Api::Channels(const std::string& test_id, const Params& params) const {
  // The parameters as `napkin export`'s options, one parser and one writer for both
  // (app/export.h); the format csv unless given.
  app::RequestOptions options(app::FrontEnd::kService);
  if (params.count("format") == 0) options.Add("format", "csv");
  for (const auto& [name, value] : params) options.Add(name, value);
  const app::ExportRequest request = app::ParseExportRequest(test_id, options);
  db::Catalogue catalogue = OpenForRequest(options_);
  std::vector<app::ExportedFile> files = app::ExportToMemory(catalogue, request);
  const std::string content_type(request.format->content_type);
  if (!request.format->folder) return Response{200, content_type, std::move(files.front().bytes)};
  // A folder format: its files as one zip archive, each under its path in the folder.
  std::vector<formats::ZipMemberBytes> members;
  members.reserve(files.size());
  for (app::ExportedFile& file : files) members.push_back({std::move(file.name), std::move(file.bytes)});
  return Response{200, content_type, formats::ZipArchiveBytes(members)};
}

Response Api::Compare(const Params& params) const {
  // The parameters as `napkin compare`'s options, one parser for both (app/request_options.h).
  app::RequestOptions options(app::FrontEnd::kService);
  for (const auto& [name, value] : params) options.Add(name, value);
  const app::CompareRequest request = app::ParseCompareRequest(options);
  db::Catalogue catalogue = OpenForRequest(options_);
  return Response{200, "application/json",
                  app::FormatComparison(app::BuildComparison(catalogue, request), app::TableFormat::kJson)};
}

Response Api::ReportVersion(const Params& params) const {
  return Response{200, "application/json", Dump(Json{{"version", SeriesVersion(SeriesOf(params))}})};
}

std::string Api::SeriesVersion(const std::string& series) const {
  db::Catalogue catalogue = OpenForRequest(options_);
  // Every test of the series and every field of its latest results (query tests and criteria):
  // a test that arrives, a result computed or recomputed changes one of them.
  std::string rows;
  for (const char* kind : {"tests", "criteria"}) {
    app::Query query;
    query.kind = kind;
    query.filters.tests.series = {series};
    const db::Table table = app::RunQuery(catalogue, app::PrepareQuery(query));
    // A series without tests has no report to follow: the sentence `napkin report` gives for it.
    if (std::string_view(kind) == "tests" && table.rows.empty())
      throw InputError("no test in catalogue '" + catalogue.path() + "' matches series " +
                       util::EscapeControl(series) + ".");
    rows += app::FormatTable(table, app::TableFormat::kCsv);
  }
  // FNV-1a, 64 bits: the same rows give the same version in every process.
  std::uint64_t hash = 14695981039346656037ull;
  for (const char c : rows) hash = (hash ^ static_cast<unsigned char>(c)) * 1099511628211ull;
  char hex[17];
  std::snprintf(hex, sizeof hex, "%016llx", static_cast<unsigned long long>(hash));
  return hex;
}

Response Api::Report(const Params& params) const {
  const std::string series = SeriesOf(params);
  const std::string version = SeriesVersion(series);
  app::ReportSelection selection;
  selection.tests.series = {series};
  std::string page;
  app::WriteCatalogueReport(options_.db_path, selection, [&](std::string_view text) { page.append(text); });
  // The page updates itself in place when its series changes (docs/serve.md "Live report"); the
  // script goes before </body>.
  std::string script = kLiveReportScript;
  for (const auto& [placeholder, value] :
       {std::pair<std::string, std::string>{"@POLL_MS@", std::to_string(kReportPollMs)},
        {"@VERSION@", ScriptString(version)},
        {"@SERIES@", ScriptString(series)}}) {  // the series last: its text may hold anything
    const std::size_t at = script.find(placeholder);
    script.replace(at, placeholder.size(), value);
  }
  const std::size_t body_end = page.rfind("</body>");
  page.insert(body_end == std::string::npos ? page.size() : body_end, script);
  return Response{200, "text/html; charset=utf-8", std::move(page)};
}

}  // namespace napkin::serve
