#ifndef SOFTBENCH_UTIL_ATOMIC_FILE_H_
#define SOFTBENCH_UTIL_ATOMIC_FILE_H_

#include <string>
#include <string_view>

namespace softbench {

// Writes `contents` to `path` so that readers see either the old file or the
// complete new one: the bytes go to a temporary file in the same directory,
// are flushed to disk, and the temporary is renamed over `path`. A failure
// removes the temporary and throws InputError naming the path. "-" writes to
// standard output.
void WriteFileAtomically(const std::string& path, std::string_view contents);

}  // namespace softbench

#endif  // SOFTBENCH_UTIL_ATOMIC_FILE_H_
