#ifndef SOFTBENCH_UTIL_TEXT_FILE_H_
#define SOFTBENCH_UTIL_TEXT_FILE_H_

#include <cstdint>
#include <string>
#include <string_view>

namespace softbench {

// The whole contents of a UTF-8 text file of at most `max_bytes`. `what` says
// what the file is for ("mechanism file"). A path that is not a regular file,
// a file that is too large, or one that is not UTF-8 text (Latin-1 bytes, a
// NUL) throws an InputError naming the file and line.
std::string ReadTextFile(const std::string& path, std::string_view what,
                         int64_t max_bytes);

}  // namespace softbench

#endif  // SOFTBENCH_UTIL_TEXT_FILE_H_
