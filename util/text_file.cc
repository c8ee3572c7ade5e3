#include "util/text_file.h"

#include <fstream>
#include <sstream>

#include "util/input_error.h"
#include "util/input_file.h"

namespace softbench {

std::string ReadTextFile(const std::string& path, std::string_view what,
                         int64_t max_bytes) {
  CheckInputFile(path, what, max_bytes);
  std::ifstream stream(path, std::ios::binary);
  if (!stream) {
    throw InputError(path + ": cannot open the " + std::string(what) +
                     "; check its permissions");
  }
  std::stringstream text;
  text << stream.rdbuf();
  if (stream.bad()) throw InputError(path + ": read error");
  std::string contents = text.str();
  if (std::ssize(contents) > max_bytes) {  // it grew while being read
    throw InputError(path + ": the " + std::string(what) +
                     " changed while being read; try again");
  }
  if (const std::optional<NonText> non_text = FindNonText(contents)) {
    throw InputError(path + ":" + std::to_string(non_text->line) + ": " +
                     non_text->problem);
  }
  return contents;
}

}  // namespace softbench
