#ifndef SOFTBENCH_UTIL_JOIN_NAMES_H_
#define SOFTBENCH_UTIL_JOIN_NAMES_H_

#include <string>
#include <string_view>
#include <vector>

namespace softbench {

// A list of names for people: "a", "a or b", "a, b or c". Help texts and
// error messages list the valid names of a choice with it, so that an unknown
// name is always answered with the known ones.
inline std::string JoinNames(const std::vector<std::string_view>& names) {
  std::string text;
  for (size_t i = 0; i < names.size(); ++i) {
    if (i > 0) text += i + 1 == names.size() ? " or " : ", ";
    text += names[i];
  }
  return text;
}

}  // namespace softbench

#endif  // SOFTBENCH_UTIL_JOIN_NAMES_H_
