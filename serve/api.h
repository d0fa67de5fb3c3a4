#pragma once
// The read-only HTTP API of `napkin serve` (docs/serve.md "HTTP API"), as
// functions from a request's parameters to a response, without the HTTP
// server (serve/service.cpp routes to them, serve/http_server.h serves them): each answers from the
// catalogue opened read-only for that request, with the rows, keys and bytes
// of the command-line output it mirrors (`napkin query KIND --format json`,
// `napkin compare --format json`, `napkin export --format F`), and each
// failure is JSON {"error": sentence} with the sentence the command line
// would print (app/failure.h) and a status fitting it (ErrorResponse).
#include <exception>
#include <map>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace napkin::serve {

// A request's query parameters, repeated names in order.
using Params = std::multimap<std::string, std::string>;

// The query parameters of a request target ("/path?a=1&b=x%3Dy"): split at
// '&', each at its first '=' only (a value may hold '=': where=hic15>=700),
// then percent-decoded ('+' is a space); repeated and identical parameters
// all kept, in order. A parameter without '=' has an empty value.
Params ParseQuery(std::string_view target);

// The path segments of a request target, split at '/' before each is
// percent-decoded: an encoded '/' (%2F) stays inside its segment (a test id
// "T/11" is the one segment T%2F11, never two).
std::vector<std::string> PathSegments(std::string_view target);

// The path of a request target (before '?'), percent-decoded as a whole ('+' stays '+'): what the
// routes are matched on and the sentences name.
std::string DecodedPath(std::string_view target);

struct Response {
  int status = 200;
  std::string content_type = "application/json";
  std::string body;
  // Further header fields of the answer (WWW-Authenticate of a 401).
  std::vector<std::pair<std::string, std::string>> headers{};
};

// {"error": sentence} with `status`.
Response JsonError(int status, const std::string& sentence);

// `error` as its category asks (app::DescribeFailure): 400 for a bad request
// (a malformed where, sort or limit, an unknown parameter, bad input), 404
// for a test that is not in the catalogue, 503 for a catalogue locked longer
// than the busy timeout, 500 otherwise.
Response ErrorResponse(const std::exception_ptr& error, const std::string& db_path);

struct ApiOptions {
  std::string db_path;
  // How long a request waits for a catalogue another process holds locked before it
  // answers 503 (db::CatalogueOptions::busy_timeout_ms).
  int busy_timeout_ms = 10000;
};

class Api {
 public:
  explicit Api(ApiOptions options) : options_(std::move(options)) {}

  // GET /api/v1/tests: `napkin query tests --format json`.
  Response Tests(const Params& params) const { return Query("tests", params); }
  // GET /api/v1/query/KIND?where=&sort=&limit=&series=&variant=&config=&limits=:
  // `napkin query KIND --format json` with the same options (where, sort,
  // series and variant repeatable, as on the command line), KIND any of
  // db::QueryKinds() (another: NotFoundError, 404, with the sentence of
  // `napkin query`), `limits` a limits preset by name only (never a file).
  Response Query(std::string_view kind, const Params& params) const;
  // GET /api/v1/tests/ID: the test's row of each query kind whose
  // test_summary is kRow (tests, hic, rotation, criteria, risk; null where it
  // has none) and all its rows of those of kAllRows (its quality findings).
  Response TestSummary(const std::string& test_id) const;
  // GET /api/v1/tests/ID/channels?format=&config=&units=&part=&numform=&position=&dummy_type=:
  // the bytes `napkin export --format FORMAT` writes (app/export.h; default
  // csv), a folder format as a zip archive of its files; config= a stored
  // config's name or hash prefix.
  Response Channels(const std::string& test_id, const Params& params) const;
  // GET /api/v1/compare?series=&baseline=&by=&metrics=&scale=&config=&equivalence=&limits=:
  // `napkin compare --format json`, its options read by the command's parser
  // (app::ParseCompareRequest).
  Response Compare(const Params& params) const;

  // GET /report?series=S: `napkin report --series S` (app/report_builder.h),
  // with a script that asks ReportVersion every few seconds and, when the
  // answer changes, puts the current report in place of the open one (docs/serve.md "Live report").
  Response Report(const Params& params) const;
  // GET /api/v1/report/version?series=S: {"version": V}, V changing whenever a
  // test or result of the series does.
  Response ReportVersion(const Params& params) const;

  const ApiOptions& options() const { return options_; }

 private:
  // The version ReportVersion answers for `series` (16 hex digits).
  std::string SeriesVersion(const std::string& series) const;

  ApiOptions options_;
};

}  // namespace napkin::serve
