#include "util/text_file.h"

#include <fstream>
#include <sstream>

#include "util/input_error.h"

namespace softbench {

std::string ReadTextFile(const std::string& path, std::string_view what) {
  std::ifstream stream(path);
  if (!stream) {
    throw InputError(path + ": cannot open the " + std::string(what) +
                     "; check the path");
  }
  std::stringstream text;
  text << stream.rdbuf();
  if (stream.bad()) throw InputError(path + ": read error");
  return text.str();
}

}  // namespace softbench
