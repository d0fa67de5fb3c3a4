#pragma once
// The files of the HTML report's page, embedded into the binary at build time
// by cmake/embed_files.cmake (formats/CMakeLists.txt; docs/formats.md "HTML
// report"): the charting library, Debian's libjs-dygraphs (dygraph.min.js
// and dygraph.min.css, MIT licence), and napkin's own stylesheet and scripts
// (formats/report/). Each file's bytes go into the page verbatim, so the
// page's files carry no comments of their own: formats/html_report.cpp says
// what each is for where it writes it.
#include <string_view>

namespace napkin::formats {

// The files' bytes, verbatim.
std::string_view DygraphsScript();
std::string_view DygraphsStylesheet();
std::string_view ReportStylesheet();   // formats/report/report.css
std::string_view ReportErrorScript();  // formats/report/report_errors.js
std::string_view ReportDrawScript();   // formats/report/report.js

}  // namespace napkin::formats
