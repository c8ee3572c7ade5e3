#include "pipelines/tune_command.h"

#include <fmt/format.h>

#include <cmath>
#include <filesystem>
#include <numbers>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "pipelines/model_selection.h"
#include "util/atomic_file.h"
#include "util/input_error.h"
#include "vision/color_segmentation.h"
#include "vision/video_reader.h"

namespace softbench {
namespace {

namespace fs = std::filesystem;

void WritePng(const fs::path& path, const cv::Mat& image) {
  std::vector<uchar> bytes;
  cv::imencode(".png", image, bytes);
  WriteFileAtomically(path.string(), std::string(bytes.begin(), bytes.end()));
}

}  // namespace

void AddTuneCommand(CLI::App* app, TuneCommandOptions* options) {
  CLI::App* c = app->add_subcommand(
      "tune",
      "Show one frame's colour segmentation and suggest HSV bounds for a "
      "plan");
  c->add_option("video", options->video_path, "bench video")->required();
  c->add_option("--at", options->at_s, "time of the frame [s]")
      ->capture_default_str();
  c->add_option("--color", options->color,
                "marker colour: red, green, blue, yellow, magenta")
      ->capture_default_str();
  c->add_option("--hsv", options->hsv,
                "range to try instead of the colour's built-in one: "
                "h_lo,h_hi,s_lo,s_hi,v_lo,v_hi");
  c->add_option("--dot-radius-px", options->dot_radius_px,
                "expected dot radius (default: from the blobs)");
  c->add_option("--output-dir", options->output_dir,
                "folder for the frame, mask and overlay PNGs")
      ->capture_default_str();
}

int RunTune(const TuneCommandOptions& options, std::ostream& out) {
  std::optional<HsvRange> range = BuiltinHsvRange(options.color);
  if (!range) {
    throw InputError("--color: '" + options.color +
                     "' is not red, green, blue, yellow or magenta");
  }
  if (!options.hsv.empty()) {
    const std::vector<double> b = ParseNumberList(options.hsv, "--hsv");
    if (b.size() != 6) {
      throw InputError("--hsv: give six numbers h_lo,h_hi,s_lo,s_hi,v_lo,v_hi");
    }
    std::array<int, 6> bounds{};
    for (size_t i = 0; i < 6; ++i) bounds[i] = static_cast<int>(b[i]);
    range = HsvRange::FromBounds(bounds);
    if (auto problem = range->Check()) throw InputError("--hsv: " + *problem);
  }
  if (options.dot_radius_px < 0.0) {
    throw InputError("--dot-radius-px: must be > 0");
  }
  VideoReader reader(options.video_path);
  const VideoFrame frame = reader.SeekTo(options.at_s);
  cv::Mat mask = ColorMask(frame.bgr, *range);
  SegmentationOptions segmentation;
  segmentation.dot_radius_px = options.dot_radius_px > 0.0
                                   ? options.dot_radius_px
                                   : EstimateDotRadius(mask);
  if (segmentation.dot_radius_px < 1.5) {
    throw InputError(fmt::format(
        "{}: no {} blobs at t = {:.3f} s with hue {}..{}, saturation >= {}, "
        "value >= {}; try another --at, or a wider --hsv",
        options.video_path, options.color, frame.time_s, range->hue_low,
        range->hue_high, range->saturation_low, range->value_low));
  }
  CleanMask(segmentation, &mask);
  const BlobSummary blobs = FindBlobs(mask, segmentation);

  // The dots' cores (eroded away from the chroma-blurred rim) are the
  // cluster the range is learned from.
  cv::Mat cores = cv::Mat::zeros(mask.size(), CV_8UC1);
  cv::Mat regions = cores.clone();
  const double radius = segmentation.dot_radius_px;
  for (const Blob& blob : blobs.accepted) {
    const cv::Point c(static_cast<int>(std::lround(blob.centroid.x())),
                      static_cast<int>(std::lround(blob.centroid.y())));
    cv::circle(cores, c, std::max(1, static_cast<int>(0.7 * radius)), 255,
               cv::FILLED);
    cv::circle(regions, c, static_cast<int>(std::ceil(radius + 3)), 255,
               cv::FILLED);
  }
  cores &= mask;
  const LearnedHsvRange learned = LearnHsvRange(frame.bgr, cores, regions);

  cv::Mat overlay = frame.bgr.clone();
  std::vector<std::vector<cv::Point>> contours;
  cv::findContours(mask, contours, cv::RETR_EXTERNAL, cv::CHAIN_APPROX_NONE);
  cv::drawContours(overlay, contours, -1, cv::Scalar(255, 255, 0), 1);
  for (size_t i = 0; i < blobs.accepted.size(); ++i) {
    const Blob& blob = blobs.accepted[i];
    const cv::Point c(static_cast<int>(std::lround(blob.centroid.x())),
                      static_cast<int>(std::lround(blob.centroid.y())));
    cv::circle(overlay, c,
               static_cast<int>(std::lround(segmentation.dot_radius_px + 4)),
               cv::Scalar(0, 255, 0), 2);
    cv::putText(overlay, std::to_string(i + 1), c + cv::Point(14, -14),
                cv::FONT_HERSHEY_SIMPLEX, 0.6, cv::Scalar(0, 255, 0), 2);
  }
  const fs::path dir(options.output_dir);
  std::error_code error;
  fs::create_directories(dir, error);
  if (error) {
    throw InputError("--output-dir: cannot create " + dir.string() + " (" +
                     error.message() + ")");
  }
  const std::string stem =
      fmt::format("tune_{}_{:.2f}s", options.color, frame.time_s);
  WritePng(dir / (stem + "_frame.png"), frame.bgr);
  WritePng(dir / (stem + "_mask.png"), mask);
  WritePng(dir / (stem + "_overlay.png"), overlay);

  out << fmt::format(
      "t = {:.3f} s, {}: {} dot{} (radius {:.1f} px), {} blob{} rejected by "
      "size, {} by shape; images: {}/{}_{{frame,mask,overlay}}.png\n",
      frame.time_s, options.color, blobs.accepted.size(),
      blobs.accepted.size() == 1 ? "" : "s", segmentation.dot_radius_px,
      blobs.rejected_area, blobs.rejected_area == 1 ? "" : "s",
      blobs.rejected_shape, dir.string(), stem);
  if (learned.dot_pixels == 0) {
    out << "no dots to learn a range from; try another --at or --hsv\n";
    return 0;
  }
  const HsvRange& r = learned.range;
  out << fmt::format(
      "suggested range (from {} dot pixels; covers {:.1f} % of them, {} "
      "other pixels inside) - paste into the plan's marker:\n"
      "  hsv: [{}, {}, {}, {}, {}, {}]\n",
      learned.dot_pixels, 100.0 * learned.dot_coverage, learned.outside_pixels,
      r.hue_low, r.hue_high, r.saturation_low, r.saturation_high, r.value_low,
      r.value_high);
  return 0;
}

}  // namespace softbench
