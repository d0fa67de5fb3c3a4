#pragma once
// The napkin version (docs/formats.md "Version string"): the project version and the git
// revision the binary was built from, captured at build time (cmake/write_version.cmake).
// `napkin --version` prints it, and every result records it (results.napkin_version).
#include <string>

namespace napkin {

// "0.1.0": the CMake project version.
std::string ProjectVersion();
// "g1a2b3c4" (the abbreviated commit), "g1a2b3c4-dirty" (tracked files differed from it),
// or "unknown" (built outside git, e.g. from a source tarball).
std::string GitRevision();
// ProjectVersion() + "+" + GitRevision(), e.g. "0.1.0+g1a2b3c4": identifies a napkin version.
std::string Version();

}  // namespace napkin
