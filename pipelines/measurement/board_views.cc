#include "pipelines/measurement/board_views.h"

#include <fmt/format.h>

#include <algorithm>
#include <filesystem>

#include "util/check.h"
#include "util/input_error.h"
#include "util/progress.h"
#include "vision/image_codec.h"
#include "vision/luma.h"
#include "vision/video_reader.h"

namespace softbench {
namespace {

namespace fs = std::filesystem;

void AddView(const cv::Mat& gray, const std::string& where,
             const std::string& name, const BoardViewsOptions& options,
             BoardViews* views) {
  if (views->size.empty()) views->size = gray.size();
  if (gray.size() != views->size) {
    throw InputError(fmt::format(
        "{}: {}x{} differs from the first view's {}x{}; calibrate one "
        "resolution at a time",
        where, gray.cols, gray.rows, views->size.width, views->size.height));
  }
  ++views->looked_at;
  if (views->looked_at <= options.counted_views) {
    if (const std::optional<cv::Size> count = CountBoardCorners(gray)) {
      views->counted.push_back(*count);
    }
  }
  std::vector<cv::Point2f> corners = FindBoardCorners(gray, options.board);
  if (corners.empty()) {
    views->missed.push_back(name);
    return;
  }
  views->corners.push_back(std::move(corners));
  views->names.push_back(name);
}

}  // namespace

std::optional<cv::Size> PrintedBoardSize(const BoardViews& views) {
  for (const cv::Size& candidate : views.counted) {
    const auto votes = std::count_if(
        views.counted.begin(), views.counted.end(),
        [&](const cv::Size& other) { return SameBoardSize(candidate, other); });
    if (votes >= 2 && 2 * static_cast<size_t>(votes) > views.counted.size()) {
      return candidate;
    }
  }
  return std::nullopt;
}

std::optional<std::string> BoardViewsOptions::Problem() const {
  if (!(every_s > 0.0)) return "every_s: must be > 0";
  if (counted_views < 0) return "counted_views: must be >= 0";
  if (auto problem = board.Problem()) return "board: " + *problem;
  return std::nullopt;
}

BoardViews BoardViewsFromVideo(const std::string& video_path,
                               const BoardViewsOptions& options) {
  SOFTBENCH_CHECK(!options.Problem()) << *options.Problem();
  BoardViews views;
  const std::string& source = video_path;
  VideoReaderOptions reader_options;
  reader_options.want_bgr = false;
  VideoReader reader(video_path, reader_options);
  ProgressBar progress("boards", reader.info().frame_count, options.progress);
  VideoFrame frame;
  double next_s = 0.0;
  while (reader.Read(&frame)) {
    progress.Update(frame.index + 1);
    if (frame.time_s + 1e-9 < next_s) continue;
    next_s = frame.time_s + options.every_s;
    AddView(LumaFilling16Bits(frame.luma, reader.info().luma_encoding()),
            fmt::format("{} at t = {:.3f} s", source, frame.time_s),
            fmt::format("t = {:.3f} s", frame.time_s), options, &views);
  }
  progress.Finish();
  return views;
}

BoardViews BoardViewsFromImages(const std::string& directory,
                                const BoardViewsOptions& options) {
  SOFTBENCH_CHECK(!options.Problem()) << *options.Problem();
  BoardViews views;
  std::error_code error;
  std::vector<fs::path> files;
  for (const auto& entry : fs::directory_iterator(directory, error)) {
    std::string ext = entry.path().extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), ::tolower);
    if (ext == ".png" || ext == ".jpg" || ext == ".jpeg") {
      files.push_back(entry.path());
    }
  }
  if (error) {
    throw InputError("--images: cannot list " + directory + " (" +
                     error.message() + ")");
  }
  std::sort(files.begin(), files.end());
  for (const fs::path& file : files) {
    const ImageRead read = ReadImageFile(file.string(), ImageColor::kGray);
    if (read.image.empty()) {
      throw InputError(file.string() + ": " + read.why_not +
                       "; remove it or re-export it");
    }
    AddView(read.image, file.string(), file.filename().string(), options,
            &views);
  }
  return views;
}

}  // namespace softbench
