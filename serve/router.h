#pragma once
// Routes of `napkin serve` from a table (serve/service.cpp's ServiceRoutes):
// each route a path pattern of segments, "/api/v1/tests/{id}/channels", and
// its answer. A request is matched on its target's path segments, each
// percent-decoded on its own (PathSegments: an encoded '/' stays inside its
// segment), against patterns of exactly as many segments; a literal segment
// matches itself, a capture ("{id}") any one non-empty segment. Two routes
// that could both match a path are refused when the table is built, so no
// route can shadow another and their order in the table means nothing
// (docs/developing.md "Adding a route").
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "serve/api.h"

namespace napkin::serve {

// A request as a route's answer sees it: copied, so that a request thread may answer it later.
struct RouteRequest {
  std::string method;  // GET or HEAD
  std::string path;    // percent-decoded as a whole (DecodedPath): for sentences only
  Params params;       // the query parameters (ParseQuery)
  std::map<std::string, std::string, std::less<>> captures;  // "id" -> its decoded segment

  // The segment the pattern's "{name}" matched.
  const std::string& Capture(std::string_view name) const;
};

struct Route {
  std::string pattern;  // "/" then segments separated by '/': literal text or "{name}"
  std::function<Response(const RouteRequest&)> answer{};
  // Answered without the bearer token (/healthz: a load balancer's probe holds none).
  bool open = false;
  // Answered at once on the I/O thread (cheap, reads no catalogue, never throws); else the answer
  // is computed on a request thread, timed, a failure answered as ErrorResponse says.
  bool immediate = false;
};

class Router {
 public:
  // Throws std::logic_error naming the pattern for one that is malformed (no leading '/', an
  // empty segment, a '{' that is not a whole segment's "{name}", a name twice), and naming both
  // for two routes one path could match (the same segments count, and at every segment the same
  // text or a capture in either).
  explicit Router(std::vector<Route> routes);

  struct Match {
    const Route* route = nullptr;
    std::map<std::string, std::string, std::less<>> captures;
  };
  // The one route whose pattern matches the path of request target `target`; nullopt: none.
  std::optional<Match> Find(std::string_view target) const;

  const std::vector<Route>& routes() const { return routes_; }

 private:
  struct Segment {
    std::string text;  // the literal text, or the capture's name
    bool capture = false;
  };
  std::vector<Route> routes_;
  std::vector<std::vector<Segment>> patterns_;  // routes_[i]'s segments
};

}  // namespace napkin::serve
