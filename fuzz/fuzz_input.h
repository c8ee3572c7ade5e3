#ifndef SOFTBENCH_FUZZ_FUZZ_INPUT_H_
#define SOFTBENCH_FUZZ_FUZZ_INPUT_H_

#include <unistd.h>

#include <cstdint>
#include <fstream>
#include <string>
#include <string_view>

#include "util/input_error.h"

namespace softbench {

// Runs `parse` on one input. An InputError is the expected answer to bad
// bytes; anything else (another exception, a crash, a sanitizer report, a
// hang) escapes, and libFuzzer reports it with the input that caused it.
template <typename Parse>
int ParseOrInputError(Parse parse) {
  try {
    parse();
  } catch (const InputError&) {
  }
  return 0;
}

inline std::string_view AsText(const uint8_t* data, size_t size) {
  return {reinterpret_cast<const char*>(data), size};
}

// The bytes as a file (the CSV readers stream files): one path per process,
// rewritten for each input.
inline std::string AsFile(const uint8_t* data, size_t size,
                          std::string_view name) {
  const std::string path = "/tmp/softbench_fuzz_" + std::to_string(getpid()) +
                           "_" + std::string(name);
  std::ofstream(path, std::ios::binary | std::ios::trunc)
      .write(reinterpret_cast<const char*>(data),
             static_cast<std::streamsize>(size));
  return path;
}

}  // namespace softbench

#endif  // SOFTBENCH_FUZZ_FUZZ_INPUT_H_
