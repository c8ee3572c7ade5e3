#ifndef SOFTBENCH_PIPELINES_COMMANDS_COMMON_FLAGS_H_
#define SOFTBENCH_PIPELINES_COMMANDS_COMMON_FLAGS_H_

#include <CLI/CLI.hpp>
#include <string>
#include <vector>

#include "calibration/camera_calibration.h"
#include "util/csv.h"

namespace softbench {

// The options several commands share, each defined once here so its name,
// help text and checks are the same in every command: a command's input is
// a positional argument, its plan is --plan, and what it writes is --out.

// --plan: the test plan YAML (required).
void AddPlanOption(CLI::App* command, std::string* path);
// --out: what the command writes; `what` says what it is.
CLI::Option* AddOutOption(CLI::App* command, std::string* path,
                          const std::string& what);
// --threads: worker threads, 0 for one per core.
void AddThreadsOption(CLI::App* command, int* threads);
// --rest-s: seconds at rest at the video's start, for plans without times.
void AddRestOption(CLI::App* command, double* rest_s);
// --no-registration: take the camera to be still.
void AddNoRegistrationFlag(CLI::App* command, bool* no_registration);
// --decimal-comma: the input CSVs write numbers as 6,5 (fields separated by
// ';' or tabs); without it a decimal comma is refused, never guessed.
void AddDecimalCommaFlag(CLI::App* command, bool* decimal_comma);
// The decimal mark the flag declares.
DecimalMark DecimalMarkFromFlag(bool decimal_comma);

// --board COLUMNSxROWS of inner corners ("9x6") with --square-mm, as
// calibrate-camera and targets take them; unchecked beyond the syntax.
BoardOptions ParseBoardFlag(const std::string& board, double square_mm);

// Checks, before any work, that a file can be written at `path` ('-' is
// standard output): its folder exists and is writable and `path` is not a
// folder. `option` names the flag in the InputError.
void CheckOutputFile(const std::string& path, const std::string& option);
// The same for a directory written whole (a report): `path` is a folder or
// does not exist yet, and its parent folder is writable.
void CheckOutputDirectory(const std::string& path, const std::string& option);

// The same for a folder that files are added to, one atomic file each
// (tune's --out): a folder or not there yet, and writable (its parent, for a
// new one).
void CheckFolderToAddTo(const std::string& path, const std::string& option);

// A path a command reads or writes, with the option (or argument) that gave
// it, for messages.
struct NamedPath {
  std::string option;  // "--out", "the video"
  std::string path;    // '' or '-' (standard output) is never checked
};

// Checks, before any work, that no output overwrites an input or another
// output: the same file (by any name: relative, through '..' or a link), or
// an input inside a directory that is written whole (a report replacing
// the folder that holds the video it reports on).
void CheckOutputsSpareInputs(const std::vector<NamedPath>& inputs,
                             const std::vector<NamedPath>& output_files,
                             const std::vector<NamedPath>& output_directories);

}  // namespace softbench

#endif  // SOFTBENCH_PIPELINES_COMMANDS_COMMON_FLAGS_H_
