#ifndef SOFTBENCH_UTIL_FILE_DIGEST_H_
#define SOFTBENCH_UTIL_FILE_DIGEST_H_

#include <string>

namespace softbench {

// The SHA-256 of the file at `path` as 64 lowercase hex digits (OpenSSL),
// read in blocks so a video of gigabytes needs no memory. Reports carry it
// so a result can be traced to the exact inputs. Throws InputError naming the
// file when it cannot be read.
std::string Sha256OfFile(const std::string& path);

}  // namespace softbench

#endif  // SOFTBENCH_UTIL_FILE_DIGEST_H_
