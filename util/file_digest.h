#ifndef SOFTBENCH_UTIL_FILE_DIGEST_H_
#define SOFTBENCH_UTIL_FILE_DIGEST_H_

#include <atomic>
#include <optional>
#include <string>

namespace softbench {

// The SHA-256 of the file at `path` as 64 lowercase hex digits (OpenSSL),
// read in blocks so a video of gigabytes needs no memory. Reports carry it
// so a result can be traced to the exact inputs. Throws InputError naming the
// file when it is not a regular file (a device such as /dev/zero or a FIFO
// would be read forever) or cannot be read. Returns nothing, having stopped
// early, once `stop` (when given) is set: the work the digest runs beside
// failed, and a large file must not hold up its error.
std::optional<std::string> Sha256OfFile(
    const std::string& path, const std::atomic<bool>* stop = nullptr);

}  // namespace softbench

#endif  // SOFTBENCH_UTIL_FILE_DIGEST_H_
