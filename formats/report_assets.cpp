#include "formats/report_assets.h"

#include <string_view>

#include "common/embedded_file.h"

namespace napkin::formats {
namespace {

// kEmbeddedFiles: the files formats/CMakeLists.txt names.
#include "embedded_report_assets.inc"

// The bytes of the embedded file `name`; a name that is not embedded stops
// the build (a throw in a constant expression does not compile).
consteval std::string_view Embedded(std::string_view name) {
  for (const EmbeddedFile& file : kEmbeddedFiles)
    if (file.name == name) return file.bytes;
  throw "not embedded: add it to formats/CMakeLists.txt";
}

}  // namespace

std::string_view DygraphsScript() { return Embedded("dygraph.min.js"); }
std::string_view DygraphsStylesheet() { return Embedded("dygraph.min.css"); }
std::string_view ReportStylesheet() { return Embedded("report.css"); }
std::string_view ReportErrorScript() { return Embedded("report_errors.js"); }
std::string_view ReportDrawScript() { return Embedded("report.js"); }

}  // namespace napkin::formats
