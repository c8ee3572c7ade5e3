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

// softbench itself is installed incompletely (a file it ships or installs
// with scripts/bootstrap.sh is missing): neither the user's input nor a bug.
// The message names the missing file and how to install it; the command
// line exits with code 4.
class InstallationError : public std::runtime_error {
 public:
  explicit InstallationError(const std::string& message)
      : std::runtime_error(message) {}
};

}  // namespace softbench

#endif  // SOFTBENCH_UTIL_INPUT_ERROR_H_
