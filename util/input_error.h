#ifndef SOFTBENCH_UTIL_INPUT_ERROR_H_
#define SOFTBENCH_UTIL_INPUT_ERROR_H_

#include <stdexcept>
#include <string>

namespace softbench {

// Bad user input: a file, a row, a field or an option. The message is one
// line that names the place ("file:line: field ...") and what to change; the
// command line prints it and exits non-zero. Never used for programmer errors.
class InputError : public std::runtime_error {
 public:
  explicit InputError(const std::string& message)
      : std::runtime_error(message) {}
};

}  // namespace softbench

#endif  // SOFTBENCH_UTIL_INPUT_ERROR_H_
