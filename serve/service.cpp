#include "serve/service.h"

#include <fcntl.h>
#include <signal.h>
#include <spdlog/spdlog.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <nlohmann/json.hpp>
#include <string_view>
#include <thread>
#include <vector>

#include "app/failure.h"
#include "app/request_options.h"
#include "app/status.h"
#include "common/error.h"
#include "common/version.h"
#include "db/catalogue.h"
#include "formats/json_file.h"
#include "formats/presets.h"
#include "records/config_record.h"
#include "serve/api.h"
#include "serve/http_server.h"
#include "serve/inbox.h"
#include "serve/router.h"
#include "util/text.h"

namespace napkin::serve {
namespace {

using Json = nlohmann::ordered_json;

// Exactly one Authorization field, scheme "Bearer" in any case (RFC 9110 11.1), then the token:
// the field's whole value is compared (a NUL in a field is refused as malformed before this).
bool BearerTokenMatches(const HttpRequest& req, const std::string& token) {
  const std::vector<std::string_view> authorization = req.Values("Authorization");
  if (authorization.size() != 1) return false;
  constexpr std::string_view kBearer = "Bearer ";
  if (!util::EqualsIgnoreCase(authorization[0].substr(0, kBearer.size()), kBearer)) return false;
  return TokensEqual(authorization[0].substr(kBearer.size()), token);
}

// The answer to a request no route takes (another method than GET or HEAD, an unknown path).
Response NoRoute(const HttpRequest& req) {
  return JsonError(
      404, "there is no route " + req.method + " " + req.path + " (see docs/serve.md for the routes).");
}

// Requests answered, by status code, and their time (GET /metrics).
class Counters {
 public:
  void Count(int status) {
    std::lock_guard<std::mutex> lock(mutex_);
    ++by_status_[status];
  }
  void Time(double seconds) {
    std::lock_guard<std::mutex> lock(mutex_);
    seconds_ += seconds;
  }
  std::int64_t Total() const {
    std::lock_guard<std::mutex> lock(mutex_);
    std::int64_t total = 0;
    for (const auto& [status, count] : by_status_) total += count;
    return total;
  }
  std::string Prometheus() const {
    std::lock_guard<std::mutex> lock(mutex_);
    std::string text =
        "# HELP napkin_http_requests_total HTTP requests answered, by status code.\n"
        "# TYPE napkin_http_requests_total counter\n";
    for (const auto& [status, count] : by_status_)
      text += "napkin_http_requests_total{code=\"" + std::to_string(status) + "\"} " + std::to_string(count) +
              "\n";
    text +=
        "# HELP napkin_http_request_seconds_total Time spent answering HTTP requests.\n"
        "# TYPE napkin_http_request_seconds_total counter\n"
        "napkin_http_request_seconds_total " +
        std::to_string(seconds_) + "\n";
    return text;
  }

 private:
  mutable std::mutex mutex_;
  std::map<int, std::int64_t> by_status_;
  double seconds_ = 0;
};

// The catalogue's state for a processing config preset (`config`: empty for the default), the
// object `napkin status --config PRESET --format json` prints (app/status.h). The service reads no
// file a request names: `config` must be a preset.
Json CatalogueStatus(const ApiOptions& options, const std::string& config = "") {
  if (!config.empty()) {
    const std::vector<std::string> presets = formats::PresetNames(formats::PresetKind::kProcessingConfig);
    if (std::find(presets.begin(), presets.end(), config) == presets.end())
      throw UsageError(app::NotOneOfProblem("parameter 'config'", presets, config) +
                       " (a processing config preset: the service reads no file a request names).");
  }
  const records::ResolvedConfig resolved = records::ResolveConfig(config);
  db::CatalogueOptions open;
  open.read_only = true;
  open.busy_timeout_ms = options.busy_timeout_ms;
  db::Catalogue catalogue = db::Catalogue::Open(options.db_path, open);
  return app::StatusJson(app::ReadStatus(catalogue, resolved));
}

// The status answers while another process holds the catalogue locked: after a
// short wait, the catalogue's part is the sentence saying why it is missing. A
// bad request (an unknown config) is the request's error, not the catalogue's.
Json CatalogueStatusOrError(ApiOptions options, const std::string& config = "") {
  options.busy_timeout_ms = std::min(options.busy_timeout_ms, 1000);
  try {
    return CatalogueStatus(options, config);
  } catch (const UsageError&) {
    throw;
  } catch (...) {
    return Json{{"path", options.db_path},
                {"error", app::DescribeFailure(std::current_exception(), options.db_path).sentence}};
  }
}

// GET /api/v1/status?config=PRESET: the config the catalogue's part counts for (empty: the default).
std::string StatusConfigParameter(const Params& params) {
  app::RequestOptions options(app::FrontEnd::kService);
  for (const auto& [name, value] : params) options.Add(name, value);
  options.CheckKnown({"config"});
  return options.One("config").value_or("");
}

// Without the catalogue's counts (CatalogueStatusOrError's error): no lines.
std::string CatalogueMetrics(const Json& status) {
  if (status.contains("error")) return {};
  std::string text =
      "# HELP napkin_catalogue_tests Tests in the catalogue by state under the default config.\n"
      "# TYPE napkin_catalogue_tests gauge\n";
  for (const char* state : {"done", "failed", "pending", "running"})
    text += std::string("napkin_catalogue_tests{state=\"") + state + "\"} " +
            std::to_string(status.at(state).get<std::int64_t>()) + "\n";
  return text;
}

// Blocks SIGTERM and SIGINT in this thread and every thread it starts: they are
// taken by sigtimedwait in the signal thread only.
sigset_t BlockStopSignals() {
  sigset_t set;
  sigemptyset(&set);
  sigaddset(&set, SIGTERM);
  sigaddset(&set, SIGINT);
  pthread_sigmask(SIG_BLOCK, &set, nullptr);
  return set;
}

// A token is a line of text: a file larger than this is not one (/dev/zero, a log named by mistake).
constexpr off_t kMaxTokenFileBytes = 4096;

// A file's permission bits as chmod writes them, e.g. "0644".
std::string ModeText(mode_t mode) {
  char text[8];
  std::snprintf(text, sizeof text, "%04o", static_cast<unsigned>(mode & 07777));
  return text;
}

// What the status and metrics routes read besides the API (GET /api/v1/status, /metrics).
struct ServiceState {
  ApiOptions api_options;
  Counters counters{};
  std::chrono::system_clock::time_point started = std::chrono::system_clock::now();
  std::string listening;  // --listen as given, then the address bound (before the first request)
  const Inbox* inbox = nullptr;
};

// The test id of a route's "{id}": a decoded NUL or newline would cut or split the sentences that
// name the id.
const std::string& TestIdOf(const RouteRequest& request) {
  const std::string& test_id = request.Capture("id");
  if (util::HasControlCharacter(test_id))
    throw UsageError("test id " + util::Quoted(test_id) +
                     " holds a control character, which no test id has.");
  return test_id;
}

// The routes of docs/serve.md "HTTP API", every one GET (and HEAD). Routed on the raw target's
// segments, each decoded on its own (serve/router.h): an encoded '/' (%2F) stays in the test id
// (/api/v1/tests/T%2F11%2Fchannels is test T/11/channels, not T/11's channels), and no route can
// shadow another. Adding a route is adding its row here (docs/developing.md "Adding a route").
std::vector<Route> ServiceRoutes(const Api& api, ServiceState& service) {
  return {
      {.pattern = "/healthz",
       .answer =
           [](const RouteRequest&) {
             return Response{200, "application/json", "{\"status\":\"ok\"}\n"};
           },
       .open = true,
       .immediate = true},
      {"/api/v1/tests", [&api](const RouteRequest& request) { return api.Tests(request.params); }},
      {"/api/v1/query/{kind}",
       [&api](const RouteRequest& request) { return api.Query(request.Capture("kind"), request.params); }},
      {"/api/v1/tests/{id}",
       [&api](const RouteRequest& request) {
         if (!request.params.empty()) throw UsageError("this route takes no parameters.");
         return api.TestSummary(TestIdOf(request));
       }},
      {"/api/v1/tests/{id}/channels",
       [&api](const RouteRequest& request) { return api.Channels(TestIdOf(request), request.params); }},
      {"/api/v1/report/version",
       [&api](const RouteRequest& request) { return api.ReportVersion(request.params); }},
      {"/report", [&api](const RouteRequest& request) { return api.Report(request.params); }},
      {"/api/v1/compare", [&api](const RouteRequest& request) { return api.Compare(request.params); }},
      {"/api/v1/status",
       [&listening = service.listening, &started = service.started, &counters = service.counters,
        &api_options = service.api_options, inbox = service.inbox](const RouteRequest& request) {
         const std::string config = StatusConfigParameter(request.params);
         const Json status = {
             {"service",
              {{"version", napkin::Version()},
               {"listen", listening},
               {"started",
                std::chrono::duration_cast<std::chrono::seconds>(started.time_since_epoch()).count()},
               {"requests", counters.Total()}}},
             {"catalogue", CatalogueStatusOrError(api_options, config)},
             {"inbox", inbox ? inbox->Status() : Json(nullptr)}};
         return Response{200, "application/json",
                         status.dump(2, ' ', false, Json::error_handler_t::replace) + "\n"};
       }},
      {"/metrics",
       [&counters = service.counters, &api_options = service.api_options,
        inbox = service.inbox](const RouteRequest&) {
         return Response{200, "text/plain; version=0.0.4",
                         counters.Prometheus() + CatalogueMetrics(CatalogueStatusOrError(api_options)) +
                             (inbox ? inbox->Metrics() : std::string())};
       }},
  };
}

// A route's answer computed on a request thread: its answer or the failure's JSON, timed for /metrics.
RequestWork TimedWork(const Route& route, RouteRequest request, ServiceState& service) {
  return [&route, request = std::move(request), &service] {
    const auto start = std::chrono::steady_clock::now();
    Response response;
    try {
      response = route.answer(request);
    } catch (...) {
      response = ErrorResponse(std::current_exception(), service.api_options.db_path);
    }
    service.counters.Time(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    return response;
  };
}

// A request's route, on the I/O thread (it must not block): the token checked first (but for an
// open route), then the method and the route; what needs the catalogue goes to a request thread.
Routed Dispatch(const HttpRequest& req, const Router& router, const std::string& token,
                ServiceState& service) {
  const std::optional<Router::Match> match = router.Find(req.target);
  if (!token.empty() && !(match && match->route->open) && !BearerTokenMatches(req, token)) {
    Response refused = JsonError(401,
                                 "this napkin serve needs the header 'Authorization: Bearer TOKEN' with the "
                                 "token of its --token-file.");
    refused.headers.emplace_back("WWW-Authenticate", "Bearer");
    return refused;
  }
  if ((req.method != "GET" && req.method != "HEAD") || !match) return NoRoute(req);
  // From the raw target: each parameter split at its first '=' (where=hic15>=700), repeated ones
  // all kept, also when identical (where limits count as the command line's).
  RouteRequest request{req.method, req.path, ParseQuery(req.target), match->captures};
  if (match->route->immediate) return match->route->answer(request);
  return TimedWork(*match->route, std::move(request), service);
}

// The checks of RunService before it listens: the address, the token (or loopback), the numbers.
struct StartChecks {
  ListenAddress address;
  std::string token;  // empty: none (loopback only)
};
StartChecks CheckStart(const ServeOptions& options) {
  StartChecks checked{ParseListenAddress(options.listen), {}};
  if (options.threads < 1 || options.threads > 256)
    throw UsageError("--threads must be from 1 to 256, not " + std::to_string(options.threads) + ".");
  if (options.token_file) {
    checked.token = ReadTokenFile(*options.token_file);
  } else if (!IsLoopbackHost(checked.address.host)) {
    throw UsageError("--listen " + options.listen +
                     " is not a loopback address, which napkin serve answers only with --token-file "
                     "(a bearer token every request must carry).");
  }
  if (!(options.settle_s >= 0 && options.settle_s <= 86400))
    throw UsageError("--settle must be from 0 to 86400 seconds.");
  if (options.poll_s && !(*options.poll_s >= 0.1 && *options.poll_s <= 3600))
    throw UsageError("--poll must be from 0.1 to 3600 seconds.");
  return checked;
}

// The inbox of --inbox, not yet started; null without one.
std::unique_ptr<Inbox> MakeInbox(const ServeOptions& options) {
  if (options.inbox.empty()) return nullptr;
  InboxOptions inbox_options;
  inbox_options.db_path = options.db_path;
  inbox_options.inbox = options.inbox;
  inbox_options.settle_s = options.settle_s;
  inbox_options.poll_s = options.poll_s;
  return std::make_unique<Inbox>(inbox_options);
}

// Serves until SIGTERM or SIGINT, taken by a signal thread, stops the server (no new connections;
// those waiting for a request closed at once, the answers in progress given half a second; Run
// returns within 1 s). Returns how many answers the stop abandoned (HttpServer::Run).
std::size_t ServeUntilStopped(HttpServer& server, const sigset_t& stop_signals) {
  std::atomic<bool> done{false};
  std::thread signal_thread([&] {
    const timespec wait{0, 200'000'000};
    while (!done) {
      const int signal = sigtimedwait(&stop_signals, nullptr, &wait);
      if (signal == SIGTERM || signal == SIGINT) {
        spdlog::info("{}: stopping (no new connections; the answers in progress get half a second)",
                     signal == SIGTERM ? "SIGTERM" : "SIGINT");
        server.Stop();
        return;
      }
    }
  });
  const std::size_t abandoned = server.Run();
  done = true;
  signal_thread.join();
  return abandoned;
}

}  // namespace

ListenAddress ParseListenAddress(std::string_view text) {
  const auto bad = [&](const std::string& why) {
    return UsageError("--listen '" + std::string(text) + "' " + why +
                      " (give HOST:PORT, e.g. 127.0.0.1:8080).");
  };
  const std::size_t colon = text.rfind(':');
  if (colon == std::string_view::npos || colon == 0) throw bad("has no host and port");
  std::string host(text.substr(0, colon));
  const std::string_view port_text = text.substr(colon + 1);
  if (host.front() == '[') {
    if (host.back() != ']') throw bad("has an unclosed '['");
    host = host.substr(1, host.size() - 2);
  } else if (host.find(':') != std::string::npos) {
    throw bad("has an IPv6 address without brackets");
  }
  if (host.empty()) throw bad("has no host");
  if (port_text.empty() || port_text.size() > 5) throw bad("has no port from 0 to 65535");
  int port = 0;
  for (const char c : port_text) {
    if (!std::isdigit(static_cast<unsigned char>(c))) throw bad("has no port from 0 to 65535");
    port = port * 10 + (c - '0');
  }
  if (port > 65535) throw bad("has no port from 0 to 65535");
  return ListenAddress{host, port};
}

bool IsLoopbackHost(std::string_view host) {
  if (host == "localhost" || host == "::1") return true;
  // 127.0.0.0/8, written as a dotted quad.
  if (!host.starts_with("127.")) return false;
  int dots = 0;
  for (const char c : host) {
    if (c == '.')
      ++dots;
    else if (!std::isdigit(static_cast<unsigned char>(c)))
      return false;
  }
  return dots == 3;
}

std::string ReadTokenFile(const std::string& path) {
  const std::string named = "--token-file '" + util::EscapeControl(path) + "'";
  // Judged on the descriptor opened (O_NONBLOCK: a FIFO never blocks the start), never on the path.
  const formats::OpenedForReading file = formats::OpenForReading(path);
  if (file.error != 0) throw InputError(named + " cannot be opened (" + std::strerror(file.error) + ").");
  const struct stat& status = file.status;
  if (S_ISDIR(status.st_mode)) throw InputError(named + " is a folder; give the file that holds the token.");
  if (!S_ISREG(status.st_mode))
    throw InputError(named + " is not a regular file (a FIFO, a device or a socket); the token is read " +
                     "from a regular file only.");
  if (status.st_size > kMaxTokenFileBytes)
    throw InputError(named + " is " + std::to_string(status.st_size) + " bytes, more than the " +
                     std::to_string(kMaxTokenFileBytes) + " a token file may have.");
  // As ssh treats a private key: a token others may change is no secret of this service's.
  if (status.st_mode & (S_IWGRP | S_IWOTH))
    throw InputError(named + " may be written by other users (mode " + ModeText(status.st_mode) +
                     "); make it writable by its owner only, e.g. `chmod 600 " + util::EscapeControl(path) +
                     "`.");
  if (status.st_mode & (S_IRGRP | S_IROTH))
    spdlog::warn("{} may be read by other users (mode {}): they can use the token; e.g. `chmod 600 {}`",
                 named, ModeText(status.st_mode), util::EscapeControl(path));
  std::string token = formats::ReadDescriptor(file.fd.get(), static_cast<std::uintmax_t>(kMaxTokenFileBytes),
                                              named, "a token file may have");
  while (!token.empty() && std::isspace(static_cast<unsigned char>(token.back()))) token.pop_back();
  if (token.size() < 16)
    throw InputError("--token-file '" + path + "' holds " +
                     (token.empty() ? "no token" : "a token shorter than 16 characters") +
                     "; write a long random one, e.g. with `head -c 32 /dev/urandom | base64`.");
  for (const char c : token)
    if (std::isspace(static_cast<unsigned char>(c)) || std::iscntrl(static_cast<unsigned char>(c)))
      throw InputError("--token-file '" + path +
                       "' holds white space or a control character inside its token.");
  return token;
}

bool TokensEqual(std::string_view given, std::string_view expected) {
  // Every byte of `expected` is compared whatever `given` holds.
  unsigned char difference = given.size() == expected.size() ? 0 : 1;
  for (std::size_t i = 0; i < expected.size(); ++i)
    difference |= static_cast<unsigned char>(expected[i] ^ (i < given.size() ? given[i] : 0));
  return difference == 0;
}

std::vector<std::string> ServiceRoutePatterns() {
  const Api api(ApiOptions{});
  ServiceState service;
  const Router router(ServiceRoutes(api, service));
  std::vector<std::string> patterns;
  for (const Route& route : router.routes()) patterns.push_back(route.pattern);
  return patterns;
}

void RunService(const ServeOptions& options) {
  const StartChecks start = CheckStart(options);
  ServiceState service{.api_options = {options.db_path, options.busy_timeout_ms},
                       .listening = options.listen};
  // A missing or damaged catalogue is refused at start, not at the first request.
  (void)CatalogueStatus(service.api_options);
  const Api api(service.api_options);
  const sigset_t stop_signals = BlockStopSignals();
  const std::unique_ptr<Inbox> inbox = MakeInbox(options);
  service.inbox = inbox.get();
  signal(SIGPIPE, SIG_IGN);  // a client that hangs up is its own business
  const Router router(ServiceRoutes(api, service));

  HttpServerOptions server_options;
  server_options.host = start.address.host;
  server_options.port = start.address.port;
  server_options.threads = options.threads;
  server_options.route = [&](const HttpRequest& req) { return Dispatch(req, router, start.token, service); };
  server_options.on_answered = [&service](const HttpRequest& req, int status) {
    service.counters.Count(status);
    spdlog::debug("{} {} {}", req.method, req.path, status);
  };
  HttpServer server(std::move(server_options));  // listening from here
  // The address as bound (port 0: the port the system chose), for the status.
  const std::string& host = start.address.host;
  service.listening =
      (host.find(':') != std::string::npos ? "[" + host + "]" : host) + ":" + std::to_string(server.port());
  spdlog::info("listening on http://{}:{} (catalogue {}, {} request threads{})", host, server.port(),
               options.db_path, options.threads, start.token.empty() ? "" : ", bearer token required");

  if (options.on_listening) options.on_listening();
  if (inbox) inbox->Start();
  const std::size_t abandoned = ServeUntilStopped(server, stop_signals);
  // The inbox's run in progress commits the tests in flight and releases the others' leases.
  if (inbox) inbox->Stop();
  if (abandoned > 0) {
    // Their request threads still use this function's objects (the API, the counters, the inbox's
    // status): the process ends here, without unwinding them. Each only reads the catalogue.
    spdlog::warn(
        "the stop abandons {} request{} still being answered (a long report, or a catalogue another "
        "process holds locked)",
        abandoned, abandoned == 1 ? "" : "s");
    spdlog::info("stopped");
    spdlog::default_logger()->flush();
    std::fflush(nullptr);
    std::_Exit(0);
  }
  spdlog::info("stopped");
}

}  // namespace napkin::serve
