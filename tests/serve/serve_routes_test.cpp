// The route table of `napkin serve` (serve/router.h, serve/service.cpp's ServiceRoutes): every
// route is matched on decoded segments with exact segment counts, so that no route shadows another
// whatever the table's order (issue 43 point 9: /tests/(.+)/channels had to come before
// /tests/(.+)), and docs/serve.md lists exactly the table's routes.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <regex>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include "serve/router.h"
#include "serve/service.h"
#include "tests/support/run_command.h"
#include "tests/support/test_support.h"

namespace napkin::serve {
namespace {

using ::testing::HasSubstr;
using ::testing::ThrowsMessage;

// Routes of `patterns` whose answer names the pattern and its captures ("/a/{x} x=1").
std::vector<Route> EchoRoutes(const std::vector<std::string>& patterns) {
  std::vector<Route> routes;
  for (const std::string& pattern : patterns)
    routes.push_back({pattern, [pattern](const RouteRequest& request) {
                        std::string body = pattern;
                        for (const auto& [name, value] : request.captures) body += " " + name + "=" + value;
                        return Response{200, "text/plain", body};
                      }});
  return routes;
}

// What `router` answers for `target`: the echo, or "none".
std::string Answer(const Router& router, const std::string& target) {
  const std::optional<Router::Match> match = router.Find(target);
  if (!match) return "none";
  return match->route->answer(RouteRequest{"GET", DecodedPath(target), ParseQuery(target), match->captures})
      .body;
}

// A route's pattern as docs/serve.md writes it: "/api/v1/tests/{id}" is "/api/v1/tests/ID".
std::string AsDocumented(const std::string& pattern) {
  std::string documented;
  bool in_capture = false;
  for (const char c : pattern) {
    if (c == '{' || c == '}') {
      in_capture = c == '{';
      continue;
    }
    documented += in_capture ? static_cast<char>(std::toupper(static_cast<unsigned char>(c))) : c;
  }
  return documented;
}

TEST(ServeRoutes, TheTestRoutesNeverShadowEachOtherInEitherOrder) {
  std::vector<std::string> patterns = ServiceRoutePatterns();
  ASSERT_THAT(patterns, ::testing::IsSupersetOf(
                            {std::string("/api/v1/tests/{id}"), std::string("/api/v1/tests/{id}/channels")}));
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"/api/v1/tests", "/api/v1/tests"},
      {"/api/v1/tests/T11", "/api/v1/tests/{id} id=T11"},
      {"/api/v1/tests/T11/channels", "/api/v1/tests/{id}/channels id=T11"},
      {"/api/v1/tests/T11/channels?format=json", "/api/v1/tests/{id}/channels id=T11"},
      // An encoded '/' is part of the id, wherever it stands.
      {"/api/v1/tests/T11%2Fchannels", "/api/v1/tests/{id} id=T11/channels"},
      {"/api/v1/tests/T%2F11%2Fchannels", "/api/v1/tests/{id} id=T/11/channels"},
      {"/api/v1/tests/T11%2Fchannels/channels", "/api/v1/tests/{id}/channels id=T11/channels"},
      {"/api/v1/tests/%2F/channels", "/api/v1/tests/{id}/channels id=/"},
      // A test named "channels" is a test like any other.
      {"/api/v1/tests/channels", "/api/v1/tests/{id} id=channels"},
      {"/api/v1/tests/channels/channels", "/api/v1/tests/{id}/channels id=channels"},
      {"/api/v1/tests/%63hannels", "/api/v1/tests/{id} id=channels"},
      {"/api/v1/query/hic?where=hic15>0", "/api/v1/query/{kind} kind=hic"},
      {"/api/v1/query/no-such-kind", "/api/v1/query/{kind} kind=no-such-kind"},
      // No route: a segment more or less, an empty id or kind, a trailing '/'.
      {"/api/v1/tests/T11/channels/more", "none"},
      {"/api/v1/tests/T11/", "none"},
      {"/api/v1/tests/", "none"},
      {"/api/v1/tests//channels", "none"},
      {"/api/v1/query/", "none"},
      {"/api/v1/query/hic/more", "none"},
      {"/api%2Fv1/tests", "none"},
      {"/", "none"},
      {"/healthz/", "none"},
  };
  // The table's order and its reverse answer alike: no route depends on coming first.
  for (int order = 0; order < 2; ++order) {
    SCOPED_TRACE(order == 0 ? "table order" : "reversed");
    const Router router(EchoRoutes(patterns));
    for (const auto& [target, answer] : cases) EXPECT_EQ(Answer(router, target), answer) << target;
    std::reverse(patterns.begin(), patterns.end());
  }
}

TEST(ServeRoutes, ATableWhereOnePathMatchesTwoRoutesIsRefused) {
  const auto build = [](const std::vector<std::string>& patterns) { Router router(EchoRoutes(patterns)); };
  // What the regex table allowed: a test route and a literal one under it that it swallowed.
  EXPECT_THAT(
      [&] {
        build({"/api/v1/tests/{id}", "/api/v1/tests/summary"});
      },
      ThrowsMessage<std::logic_error>(
          HasSubstr("routes '/api/v1/tests/{id}' and '/api/v1/tests/summary' can both match one path")));
  EXPECT_THAT(
      [&] {
        build({"/a/{x}/c", "/a/b/{y}"});
      },
      ThrowsMessage<std::logic_error>(HasSubstr("routes '/a/{x}/c' and '/a/b/{y}'")));
  EXPECT_THAT(
      [&] {
        build({"/a", "/b", "/a"});
      },
      ThrowsMessage<std::logic_error>(HasSubstr("routes '/a' and '/a'")));
  // Different segment counts, or a literal that differs somewhere, never overlap.
  EXPECT_NO_THROW(build({"/a/{x}", "/a/{x}/c", "/a", "/b/{x}", "/a/{x}/d"}));
  // Malformed patterns.
  EXPECT_THAT([&] { build({"a/b"}); }, ThrowsMessage<std::logic_error>(HasSubstr("does not start with '/'")));
  EXPECT_THAT([&] { build({"/a//b"}); }, ThrowsMessage<std::logic_error>(HasSubstr("has an empty segment")));
  EXPECT_THAT([&] { build({"/a/"}); }, ThrowsMessage<std::logic_error>(HasSubstr("has an empty segment")));
  EXPECT_THAT([&] { build({"/a/{x"}); }, ThrowsMessage<std::logic_error>(HasSubstr("not a whole segment")));
  EXPECT_THAT([&] { build({"/a/x{y}"}); }, ThrowsMessage<std::logic_error>(HasSubstr("'{' or '}' inside")));
  EXPECT_THAT([&] { build({"/a/{x}/{x}"}); },
              ThrowsMessage<std::logic_error>(HasSubstr("names a capture twice")));
}

// Each route of the table is a row of docs/serve.md "HTTP API", and each row a route.
TEST(ServeRoutes, DocsListEveryRouteOfTheTable) {
  const std::string docs = test_support::ReadText(test_support::SourceDir() / "docs" / "serve.md");
  std::set<std::string> documented;
  const std::regex row(R"(\n\| `GET (/[^ ?`]*))");
  for (std::sregex_iterator it(docs.begin(), docs.end(), row), end; it != end; ++it)
    documented.insert((*it)[1].str());
  std::set<std::string> table;
  for (const std::string& pattern : ServiceRoutePatterns()) table.insert(AsDocumented(pattern));
  EXPECT_EQ(documented, table);
}

}  // namespace
}  // namespace napkin::serve
