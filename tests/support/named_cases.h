#pragma once
// Table-driven tests: each row of a case table is a value of a
// value-parameterized test (TEST_P), so each row is its own CTest test and a
// failure names the row.
#include <gtest/gtest.h>

#include <string>

namespace napkin::test_support {

// Names a case after its `name` field, for INSTANTIATE_TEST_SUITE_P:
// "Suite/Fixture.Test/<name>". GoogleTest accepts only [A-Za-z0-9_] in it.
struct CaseName {
  template <typename Case>
  std::string operator()(const ::testing::TestParamInfo<Case>& info) const {
    return info.param.name;
  }
};

}  // namespace napkin::test_support
