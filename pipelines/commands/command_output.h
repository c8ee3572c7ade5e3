#ifndef SOFTBENCH_PIPELINES_COMMANDS_COMMAND_OUTPUT_H_
#define SOFTBENCH_PIPELINES_COMMANDS_COMMAND_OUTPUT_H_

#include <ostream>
#include <string>
#include <string_view>

namespace softbench {

// A command's output file: written atomically to `path`, or to `out` (the
// command's standard output) when `path` is "-".
void WriteCommandOutput(const std::string& path, std::string_view contents,
                        std::ostream& out);

}  // namespace softbench

#endif  // SOFTBENCH_PIPELINES_COMMANDS_COMMAND_OUTPUT_H_
