#pragma once
// The HTTP/1.1 server under `napkin serve` (docs/serve.md "Safety"), on Boost.Beast and Boost.Asio,
// which stay private: no header of serve/ includes them. One thread reads and writes every
// connection asynchronously; a request holds a request thread only once it has arrived complete
// (its header within a total deadline, not a per-read timeout), so slow or idle clients hold
// none. Requests on one connection are answered in order (pipelining), the open connections are
// capped, and Stop() closes everything within a bounded time whatever the clients do.
#include <cstddef>
#include <functional>
#include <memory>
#include <string>
#include <string_view>
#include <utility>
#include <variant>
#include <vector>

#include "serve/api.h"

namespace napkin::serve {

namespace detail {
struct HttpServerState;  // http_server.cpp's
}  // namespace detail

// A request as it arrived complete.
struct HttpRequest {
  std::string method;  // as sent: GET, HEAD, POST, ...
  std::string target;  // the raw request target: path and query, still percent-encoded
  std::string path;    // the target's path (before '?'), percent-decoded as a whole
  std::vector<std::pair<std::string, std::string>> fields;  // the header fields as sent, in order

  // The values of the fields named `name` (in any case, RFC 9110 5.1), in order.
  std::vector<std::string_view> Values(std::string_view name) const;
};

// Work for a request thread: the answer of a request that reads the catalogue.
using RequestWork = std::function<Response()>;
// What a request gets: its answer at once (cheap: /healthz, a refusal) or work for a request thread.
using Routed = std::variant<Response, RequestWork>;

struct HttpServerOptions {
  std::string host;  // as --listen names it (a name is resolved; the first address that binds)
  int port = 0;      // 0: any free port
  int threads = 4;   // request threads
  // Called on the I/O thread for each complete request within the limits: must not block.
  std::function<Routed(const HttpRequest&)> route;
  // Called on the I/O thread for every answer sent (also the refusals); `request` is empty for a
  // refusal before a request was read (a connection beyond the cap, a malformed request).
  std::function<void(const HttpRequest& request, int status)> on_answered;
};

class HttpServer {
 public:
  // Listens (bound before it returns). Throws InputError when no address of the host binds.
  explicit HttpServer(HttpServerOptions options);
  HttpServer(const HttpServer&) = delete;
  HttpServer& operator=(const HttpServer&) = delete;
  ~HttpServer();

  // The port bound (the one the system chose for port 0).
  int port() const;

  // Serves on the calling thread until Stop(); returns within 1 s of it. Returns how many
  // requests were still being answered by their request thread then (a long report, a catalogue
  // locked by another process): their threads still run, and the caller must end the process
  // (std::_Exit) rather than return through this object's destructor.
  std::size_t Run();

  // From any thread (the signal thread): no new connections; connections waiting for a request
  // are closed at once, those whose answer is in progress get half a second to send it.
  void Stop();

 private:
  std::unique_ptr<detail::HttpServerState> state_;
};

}  // namespace napkin::serve
