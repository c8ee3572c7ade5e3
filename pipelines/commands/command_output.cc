#include "pipelines/commands/command_output.h"

#include "util/atomic_file.h"

namespace softbench {

void WriteCommandOutput(const std::string& path, std::string_view contents,
                        std::ostream& out) {
  if (path == "-") {
    out << contents << std::flush;
    return;
  }
  WriteFileAtomically(path, contents);
}

}  // namespace softbench
