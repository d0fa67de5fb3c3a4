#pragma once
// Helpers of the app/ tests (tests/app/).
#include <string>

namespace napkin::test_support {

// The message of the `Error` that `f` throws ("no error" when it throws none).
template <typename Error, typename F>
std::string ErrorText(F&& f) {
  try {
    f();
  } catch (const Error& error) {
    return error.what();
  }
  return "no error";
}

}  // namespace napkin::test_support
