#include "util/input_file.h"

#include <fmt/format.h>

#include <filesystem>
#include <system_error>

#include "util/input_error.h"

namespace softbench {
namespace {

namespace fs = std::filesystem;

std::string_view KindOf(fs::file_type type) {
  switch (type) {
    case fs::file_type::directory:
      return "a folder";
    case fs::file_type::character:
    case fs::file_type::block:
      return "a device";
    case fs::file_type::fifo:
      return "a pipe (FIFO)";
    case fs::file_type::socket:
      return "a socket";
    default:
      return "not a regular file";
  }
}

// Length of the UTF-8 sequence `lead` starts, or 0 when it cannot start one
// (RFC 3629: no overlong two-byte leads, nothing beyond U+10FFFF).
int SequenceLength(unsigned char lead) {
  if (lead < 0x80) return 1;
  if (lead >= 0xC2 && lead <= 0xDF) return 2;
  if (lead >= 0xE0 && lead <= 0xEF) return 3;
  if (lead >= 0xF0 && lead <= 0xF4) return 4;
  return 0;
}

}  // namespace

int64_t CheckInputFile(const std::string& path, std::string_view what,
                       std::optional<int64_t> max_bytes) {
  std::error_code error;
  const fs::file_status status = fs::status(path, error);
  if (error || !fs::exists(status)) {
    throw InputError(fmt::format("{}: no such {}; check the path", path, what));
  }
  if (!fs::is_regular_file(status)) {
    throw InputError(
        fmt::format("{}: is {}, not a regular file; give the {}'s path", path,
                    KindOf(status.type()), what));
  }
  const auto size = static_cast<int64_t>(fs::file_size(path, error));
  if (error) {
    throw InputError(fmt::format("{}: cannot read the {} ({})", path, what,
                                 error.message()));
  }
  if (max_bytes && size > *max_bytes) {
    throw InputError(fmt::format(
        "{}: {} bytes is too large for a {} (at most {} bytes); check that "
        "this is the right file",
        path, size, what, *max_bytes));
  }
  return size;
}

std::optional<NonText> FindNonText(std::string_view text) {
  int line = 1;
  for (size_t i = 0; i < text.size();) {
    const auto byte = static_cast<unsigned char>(text[i]);
    if (byte == '\n') ++line;
    if (byte < 0x20 && byte != '\n' && byte != '\r' && byte != '\t') {
      return NonText{line, fmt::format("control character 0x{:02X}{}", byte,
                                       byte == 0 ? " (NUL): this is not text"
                                                 : "; remove it")};
    }
    const int length = SequenceLength(byte);
    bool valid = length > 0 && i + length <= text.size();
    for (int k = 1; valid && k < length; ++k) {
      valid = (static_cast<unsigned char>(text[i + k]) & 0xC0) == 0x80;
    }
    if (!valid) {
      return NonText{line, fmt::format("byte 0x{:02X} is not UTF-8; save the "
                                       "file as UTF-8 text",
                                       byte)};
    }
    i += length;
  }
  return std::nullopt;
}

}  // namespace softbench
