#ifndef SOFTBENCH_TESTS_SUPPORT_INPUT_ERROR_MATCHERS_H_
#define SOFTBENCH_TESTS_SUPPORT_INPUT_ERROR_MATCHERS_H_

#include <gmock/gmock.h>

#include <functional>
#include <string>

#include "util/input_error.h"

namespace softbench {

// Matches a callable that throws an InputError whose one-line message names
// `file`, `place` (a line, key, test or flag) and `words` (what is wrong or
// what to change): the error policy's three parts (docs/error-policy.md).
// Each is a substring; "" is for a message that has no such part.
//   EXPECT_THAT([&] { LoadTestPlan(path); },
//               ThrowsInputErrorWith(path, "test a", "shorter than"));
inline auto ThrowsInputErrorWith(const std::string& file,
                                 const std::string& place,
                                 const std::string& words) {
  return ::testing::ThrowsMessage<InputError>(
      ::testing::AllOf(::testing::HasSubstr(file), ::testing::HasSubstr(place),
                       ::testing::HasSubstr(words)));
}

// The message of the InputError `run` throws; "" when it throws none. For
// tests that compare one message against many inputs.
std::string InputErrorOf(const std::function<void()>& run);

}  // namespace softbench

#endif  // SOFTBENCH_TESTS_SUPPORT_INPUT_ERROR_MATCHERS_H_
