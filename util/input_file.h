#ifndef SOFTBENCH_UTIL_INPUT_FILE_H_
#define SOFTBENCH_UTIL_INPUT_FILE_H_

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

namespace softbench {

// Checks that `path` names a regular file that can be opened, before any
// byte of it is read: a folder, a device (/dev/zero), a FIFO or a socket is
// refused, and so is a file larger than `max_bytes` (when given), so a wrong
// path ends in a one-line InputError instead of an endless read. `what` says
// what the file is for ("test plan"). Returns the file's size in bytes.
int64_t CheckInputFile(const std::string& path, std::string_view what,
                       std::optional<int64_t> max_bytes = std::nullopt);

// Where and why a text is not UTF-8 text.
struct NonText {
  int line = 0;         // 1-based
  std::string problem;  // what is wrong and what to change
};

// The first place where `text` is not UTF-8 text: a byte sequence that is not
// UTF-8, a NUL or another control character (tab, CR and LF are text).
std::optional<NonText> FindNonText(std::string_view text);

}  // namespace softbench

#endif  // SOFTBENCH_UTIL_INPUT_FILE_H_
