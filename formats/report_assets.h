#pragma once
// The HTML report's charting library, Debian's libjs-dygraphs (dygraph.min.js
// and dygraph.min.css, MIT licence), embedded into the binary at build time
// by embed_assets.cmake (docs/formats.md "HTML report").
#include <string_view>

namespace napkin::formats {

// The files' bytes, verbatim.
std::string_view DygraphsScript();
std::string_view DygraphsStylesheet();

}  // namespace napkin::formats
