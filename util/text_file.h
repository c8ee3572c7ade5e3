#ifndef SOFTBENCH_UTIL_TEXT_FILE_H_
#define SOFTBENCH_UTIL_TEXT_FILE_H_

#include <string>
#include <string_view>

namespace softbench {

// The whole contents of a text file. `what` says what the file is for
// ("mechanism file"), for the InputError thrown when it cannot be read.
std::string ReadTextFile(const std::string& path, std::string_view what);

}  // namespace softbench

#endif  // SOFTBENCH_UTIL_TEXT_FILE_H_
