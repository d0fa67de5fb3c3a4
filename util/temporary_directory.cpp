#include "util/temporary_directory.h"

#include <sys/stat.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <string>

#include "common/error.h"

namespace napkin::util {

std::filesystem::path TemporaryDirectory() {
  const char* variable = std::getenv("TMPDIR");
  const bool from_variable = variable != nullptr && *variable != '\0';
  const std::filesystem::path folder = from_variable ? variable : "/tmp";
  const std::string named =
      "the temporary folder '" + folder.string() + "'" + (from_variable ? " (TMPDIR)" : "");
  struct stat status {};
  if (::stat(folder.c_str(), &status) != 0)
    throw InputError(named + " cannot be used (" + std::strerror(errno) +
                     "); set TMPDIR to a folder napkin may write.");
  if (!S_ISDIR(status.st_mode))
    throw InputError(named + " is not a folder; set TMPDIR to a folder napkin may write.");
  return folder;
}

}  // namespace napkin::util
