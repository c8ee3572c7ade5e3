#include "util/file_digest.h"

#include <fmt/format.h>
#include <openssl/evp.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <memory>

#include "util/check.h"
#include "util/input_error.h"
#include "util/input_file.h"

namespace softbench {

std::optional<std::string> Sha256OfFile(const std::string& path,
                                        const std::atomic<bool>* stop) {
  CheckInputFile(path, "input");
  std::ifstream file(path, std::ios::binary);
  if (!file) {
    throw InputError(
        fmt::format("{}: cannot open it to record its SHA-256 ({})", path,
                    std::strerror(errno)));
  }
  const std::unique_ptr<EVP_MD_CTX, decltype(&EVP_MD_CTX_free)> context(
      EVP_MD_CTX_new(), &EVP_MD_CTX_free);
  SOFTBENCH_CHECK(context != nullptr &&
                  EVP_DigestInit_ex(context.get(), EVP_sha256(), nullptr) == 1)
      << "OpenSSL's SHA-256 is unavailable";
  // Not zeroed: reading a small file (a plan) touches only its own pages of
  // the block, where zeroing a megabyte per file cost more than hashing it.
  constexpr size_t kBlockBytes = size_t{1} << 20;
  const std::unique_ptr<char[]> block =
      std::make_unique_for_overwrite<char[]>(kBlockBytes);
  while (file) {
    if (stop != nullptr && stop->load(std::memory_order_relaxed)) {
      return std::nullopt;
    }
    file.read(block.get(), static_cast<std::streamsize>(kBlockBytes));
    if (file.gcount() > 0) {
      EVP_DigestUpdate(context.get(), block.get(),
                       static_cast<size_t>(file.gcount()));
    }
  }
  if (file.bad()) {
    throw InputError(path + ": read error while computing its SHA-256");
  }
  unsigned char digest[EVP_MAX_MD_SIZE];
  unsigned int length = 0;
  EVP_DigestFinal_ex(context.get(), digest, &length);
  std::string hex;
  for (unsigned int i = 0; i < length; ++i)
    hex += fmt::format("{:02x}", digest[i]);
  return hex;
}

}  // namespace softbench
