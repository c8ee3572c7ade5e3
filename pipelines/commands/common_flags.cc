#include "pipelines/commands/common_flags.h"

#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>

#include "util/input_error.h"

namespace softbench {
namespace {

namespace fs = std::filesystem;

// The folder `path` is written into: its parent, or "." for a bare name.
fs::path FolderOf(const fs::path& path) {
  fs::path target = path;
  if (!target.has_filename()) target = target.parent_path();
  return target.has_parent_path() ? target.parent_path() : fs::path(".");
}

void CheckWritableFolder(const fs::path& folder, const std::string& path,
                         const std::string& option) {
  std::error_code error;
  if (!fs::is_directory(folder, error)) {
    throw InputError(option + ": " + path + ": folder '" + folder.string() +
                     "' does not exist; create it or choose another path");
  }
  // Create and remove a file there: permission bits alone do not tell
  // (root passes access(2); /proc and read-only mounts refuse anyway).
  std::string probe = (folder / ".softbench-write-check-XXXXXX").string();
  const int fd = mkstemp(probe.data());
  if (fd < 0) {
    throw InputError(option + ": " + path + ": folder '" + folder.string() +
                     "' is not writable (" + std::strerror(errno) +
                     "); choose another path");
  }
  close(fd);
  unlink(probe.c_str());
}

}  // namespace

void AddPlanOption(CLI::App* command, std::string* path) {
  command->add_option("--plan", *path, "test plan YAML")->required();
}

BoardOptions ParseBoardFlag(const std::string& board, double square_mm) {
  int columns = 0, rows = 0;
  char x = 0;
  char rest = 0;
  if (std::sscanf(board.c_str(), "%d%c%d%c", &columns, &x, &rows, &rest) != 3 ||
      x != 'x') {
    throw InputError("--board: '" + board +
                     "' is not COLUMNSxROWS of inner corners, e.g. 9x6");
  }
  // The square is checked here, under its own flag, so that a wrong size is
  // not blamed on --board; no printed board has squares of a metre.
  if (!(square_mm > 0.0 && square_mm <= 1000.0)) {
    throw InputError(fmt::format(
        "--square-mm: {} is not a square's side; give the printed square's "
        "side in mm, > 0 and at most 1000 (measure it on the print)",
        square_mm));
  }
  return {columns, rows, square_mm};
}

CLI::Option* AddOutOption(CLI::App* command, std::string* path,
                          const std::string& what) {
  return command->add_option("--out", *path, what);
}

void AddThreadsOption(CLI::App* command, int* threads) {
  command->add_option("--threads", *threads, "worker threads (0: all cores)")
      ->capture_default_str();
}

void AddRestOption(CLI::App* command, double* rest_s) {
  command
      ->add_option("--rest-s", *rest_s,
                   "plan without times: seconds at rest at the video's start")
      ->capture_default_str();
}

void AddNoRegistrationFlag(CLI::App* command, bool* no_registration) {
  command->add_flag("--no-registration", *no_registration,
                    "take the camera to be still instead of registering "
                    "every frame to the bench (the thesis's method)");
}

void AddDecimalCommaFlag(CLI::App* command, bool* decimal_comma) {
  command->add_flag("--decimal-comma", *decimal_comma,
                    "the CSVs write numbers with a decimal comma (6,5) and "
                    "separate fields with ';' or tabs, as spreadsheets in "
                    "many locales export them");
}

DecimalMark DecimalMarkFromFlag(bool decimal_comma) {
  return decimal_comma ? DecimalMark::kComma : DecimalMark::kPoint;
}

void CheckOutputFile(const std::string& path, const std::string& option) {
  if (path == "-") return;
  if (path.empty()) throw InputError(option + ": give a file name");
  std::error_code error;
  if (fs::is_directory(path, error)) {
    throw InputError(option + ": " + path +
                     " is a folder; give a file name inside it");
  }
  CheckWritableFolder(FolderOf(path), path, option);
}

void CheckOutputDirectory(const std::string& path, const std::string& option) {
  if (path.empty()) throw InputError(option + ": give a folder name");
  std::error_code error;
  if (fs::exists(path, error) && !fs::is_directory(path, error)) {
    throw InputError(option + ": " + path +
                     " exists and is not a folder; choose another name");
  }
  CheckWritableFolder(FolderOf(path), path, option);
}

void CheckFolderToAddTo(const std::string& path, const std::string& option) {
  CheckOutputDirectory(path, option);
  std::error_code error;
  if (fs::is_directory(path, error)) CheckWritableFolder(path, path, option);
}

namespace {

// `path` made absolute with '.', '..' and links of its existing part
// resolved, so two names of one file compare equal.
fs::path Resolved(const std::string& path) {
  std::error_code error;
  fs::path resolved = fs::weakly_canonical(fs::absolute(path, error), error);
  return error ? fs::absolute(path).lexically_normal() : resolved;
}

bool Checked(const NamedPath& named) {
  return !named.path.empty() && named.path != "-";
}

// True when `inner` is `folder` or lies inside it.
bool Inside(const fs::path& inner, const fs::path& folder) {
  auto [end, _] =
      std::mismatch(folder.begin(), folder.end(), inner.begin(), inner.end());
  return end == folder.end();
}

}  // namespace

void CheckOutputsSpareInputs(const std::vector<NamedPath>& inputs,
                             const std::vector<NamedPath>& output_files,
                             const std::vector<NamedPath>& output_directories) {
  std::vector<std::pair<const NamedPath*, fs::path>> earlier;
  for (const NamedPath& input : inputs) {
    if (Checked(input)) earlier.emplace_back(&input, Resolved(input.path));
  }
  const size_t num_inputs = earlier.size();
  for (const NamedPath& output : output_files) {
    if (!Checked(output)) continue;
    const fs::path path = Resolved(output.path);
    for (auto& i : earlier) {
      if (i.second != path) continue;
      throw InputError(fmt::format(
          "{}: {} is also {} ({}); write to another file", output.option,
          output.path, i.first->option, i.first->path));
    }
    earlier.emplace_back(&output, path);
  }
  for (const NamedPath& directory : output_directories) {
    if (!Checked(directory)) continue;
    const fs::path folder = Resolved(directory.path);
    for (size_t i = 0; i < earlier.size(); ++i) {
      if (!Inside(earlier[i].second, folder)) continue;
      throw InputError(fmt::format(
          "{}: {} is replaced whole, and it holds {} ({}){}; write the "
          "{} elsewhere",
          directory.option, directory.path, earlier[i].first->option,
          earlier[i].first->path, i < num_inputs ? ", which would be lost" : "",
          directory.option == "--report" ? "report" : "output"));
    }
  }
}

}  // namespace softbench
