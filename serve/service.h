#pragma once
// `napkin serve` (docs/serve.md): the HTTP API of serve/api.h on a listening
// socket (serve/http_server.h), its routes one table (ServiceRoutes in
// serve/service.cpp, matched by serve/router.h), safe by default (docs/serve.md "Safety"):
// loopback unless a bearer token guards it, requests bounded in size, headers,
// connections and time (a total header deadline), no route mapped to a file,
// the catalogue opened read-only for each request. It runs until SIGTERM or
// SIGINT, then stops accepting, closes the connections waiting for a request,
// gives the answers in progress half a second and returns (within 2 s).
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace napkin::serve {

struct ListenAddress {
  std::string host;
  int port = 0;  // 0: any free port (the log line "listening on" names it)
};

// "HOST:PORT" ("[::1]:PORT" for an IPv6 address). Throws UsageError naming
// --listen for anything else (a port outside 0..65535, no port).
ListenAddress ParseListenAddress(std::string_view text);

// Whether `host` is a loopback address (127.0.0.0/8, ::1, localhost): only
// these may listen without a token.
bool IsLoopbackHost(std::string_view host);

// The bearer token in `path`: its text without trailing white space. Throws
// InputError naming the file when it cannot be read, is empty, or is shorter
// than 16 characters (a token must not be guessable).
std::string ReadTokenFile(const std::string& path);

// Whether `given` equals `expected`, in time that depends on their lengths only
// (never on where they first differ).
bool TokensEqual(std::string_view given, std::string_view expected);

struct ServeOptions {
  std::string db_path;
  std::string listen = "127.0.0.1:8080";
  std::optional<std::string> token_file;
  int threads = 4;              // request threads
  int busy_timeout_ms = 10000;  // a request's wait for a locked catalogue before 503
  // --inbox: tests imported and processed as they arrive (serve/inbox.h); empty: none.
  std::string inbox;
  double settle_s = 5.0;
  std::optional<double> poll_s;  // --poll: look every poll_s seconds instead of inotify
  // Called once the service listens (after the start's checks, whose refusals are the command
  // line's one sentence): the front end makes every later log line carry its time.
  std::function<void()> on_listening;
};

// The patterns of the service's routes, in the order of its table ("/api/v1/tests/{id}/channels";
// serve/router.h), that table checked as RunService checks it (no two routes match one path).
std::vector<std::string> ServiceRoutePatterns();

// The service until SIGTERM or SIGINT. Throws UsageError (before listening)
// for a bad --listen, a non-loopback address without --token-file or --threads
// outside 1..256; InputError for an unreadable token file or a catalogue that
// cannot be opened; returns after a signal (exit status 0).
void RunService(const ServeOptions& options);

}  // namespace napkin::serve
