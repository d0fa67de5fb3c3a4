#pragma once
// The folder napkin's scratch files go in: $TMPDIR when set and not empty,
// else /tmp (POSIX; what std::filesystem::temp_directory_path reads, but
// refused in a sentence rather than an exception without one).
#include <filesystem>

namespace napkin::util {

// Throws InputError naming the folder, and TMPDIR when it came from there,
// when it does not exist or is not a folder.
std::filesystem::path TemporaryDirectory();

}  // namespace napkin::util
