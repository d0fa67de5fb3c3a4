#include "tests/support/test_support.h"

#include <random>
#include <system_error>

namespace napkin::test_support {

TempDir::TempDir() {
  std::random_device device;
  std::mt19937_64 random(device());
  for (;;) {
    path_ = std::filesystem::temp_directory_path() / ("napkin-test-" + std::to_string(random()));
    std::error_code error;
    if (std::filesystem::create_directory(path_, error)) return;
  }
}

TempDir::~TempDir() {
  std::error_code error;
  std::filesystem::remove_all(path_, error);
}

}  // namespace napkin::test_support
