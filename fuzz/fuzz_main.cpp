// libFuzzer entry point of one fuzz target; NAPKIN_FUZZ_TARGET names it
// (fuzz/CMakeLists.txt builds one executable per target).
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "fuzz/fuzz_inputs.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const napkin::fuzz::FuzzTarget& target = napkin::fuzz::GetFuzzTarget(NAPKIN_FUZZ_TARGET);
  target.run(std::string_view(reinterpret_cast<const char*>(data), size));
  return 0;
}
