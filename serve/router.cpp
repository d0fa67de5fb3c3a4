#include "serve/router.h"

#include <stdexcept>
#include <utility>

namespace napkin::serve {

const std::string& RouteRequest::Capture(std::string_view name) const {
  const auto found = captures.find(name);
  if (found == captures.end())
    throw std::logic_error("route " + path + " has no capture '" + std::string(name) + "'");
  return found->second;
}

Router::Router(std::vector<Route> routes) : routes_(std::move(routes)) {
  for (const Route& route : routes_) {
    const auto bad = [&](const std::string& why) {
      return std::logic_error("route pattern '" + route.pattern + "' " + why);
    };
    if (!route.pattern.starts_with("/")) throw bad("does not start with '/'");
    std::vector<Segment>& pattern = patterns_.emplace_back();
    std::string_view rest = std::string_view(route.pattern).substr(1);
    for (;;) {
      const std::size_t slash = rest.find('/');
      const std::string_view text = rest.substr(0, slash);
      if (text.empty()) throw bad("has an empty segment");
      const bool capture = text.front() == '{';
      if (capture && (text.size() < 3 || text.back() != '}'))
        throw bad("has a capture that is not a whole segment's {name}");
      Segment segment{std::string(capture ? text.substr(1, text.size() - 2) : text), capture};
      if (segment.text.find_first_of("{}") != std::string::npos)
        throw bad("has a '{' or '}' inside a segment");
      for (const Segment& earlier : pattern)
        if (capture && earlier.capture && earlier.text == segment.text) throw bad("names a capture twice");
      pattern.push_back(std::move(segment));
      if (slash == std::string_view::npos) break;
      rest.remove_prefix(slash + 1);
    }
  }
  // No path matches two patterns: then no order of the table decides which answers.
  for (std::size_t a = 0; a < patterns_.size(); ++a)
    for (std::size_t b = a + 1; b < patterns_.size(); ++b) {
      if (patterns_[a].size() != patterns_[b].size()) continue;
      bool overlap = true;
      for (std::size_t i = 0; overlap && i < patterns_[a].size(); ++i) {
        const Segment& x = patterns_[a][i];
        const Segment& y = patterns_[b][i];
        overlap = x.capture || y.capture || x.text == y.text;
      }
      if (overlap)
        throw std::logic_error("routes '" + routes_[a].pattern + "' and '" + routes_[b].pattern +
                               "' can both match one path");
    }
}

std::optional<Router::Match> Router::Find(std::string_view target) const {
  const std::vector<std::string> segments = PathSegments(target);
  for (std::size_t r = 0; r < routes_.size(); ++r) {
    const std::vector<Segment>& pattern = patterns_[r];
    if (pattern.size() != segments.size()) continue;
    Match match{&routes_[r], {}};
    bool matches = true;
    for (std::size_t i = 0; matches && i < pattern.size(); ++i) {
      if (!pattern[i].capture)
        matches = segments[i] == pattern[i].text;
      else if (segments[i].empty())
        matches = false;
      else
        match.captures.emplace(pattern[i].text, segments[i]);
    }
    if (matches) return match;
  }
  return std::nullopt;
}

}  // namespace napkin::serve
