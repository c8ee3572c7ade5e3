#include "pipelines/commands/tune_command.h"

#include <fmt/format.h>

#include <array>
#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <vector>

#include "pipelines/commands/common_flags.h"
#include "pipelines/commands/model_flags.h"
#include "pipelines/formats/dot_colors.h"
#include "util/atomic_file.h"
#include "util/input_error.h"
#include "vision/color_tuning.h"
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

void AddTuneCommand(CLI::App* c, TuneCommandOptions* options) {
  c->add_option("video", options->video_path, "bench video")->required();
  c->add_option("--at", options->at_s, "time of the frame [s]")
      ->capture_default_str();
  c->add_option("--color", options->color, "marker colour: " + DotColorNames())
      ->capture_default_str();
  c->add_option("--hsv", options->hsv,
                "range to try instead of the colour's built-in one: "
                "h_lo,h_hi,s_lo,s_hi,v_lo,v_hi");
  c->add_option("--dot-radius-px", options->dot_radius_px,
                "expected dot radius (default: from the blobs)");
  AddOutOption(c, &options->output_dir,
               "folder for the frame, mask and overlay PNGs")
      ->capture_default_str();
}

int RunTune(const TuneCommandOptions& options, std::ostream& out) {
  const DotColor* color = FindDotColor(options.color);
  if (color == nullptr) {
    throw InputError("--color: '" + options.color + "' is not " +
                     DotColorNames());
  }
  HsvRange range = HsvRange::FromBounds(color->hsv_bounds);
  if (!options.hsv.empty()) {
    const std::vector<double> b = ParseNumberList(options.hsv, "--hsv");
    if (b.size() != 6) {
      throw InputError("--hsv: give six numbers h_lo,h_hi,s_lo,s_hi,v_lo,v_hi");
    }
    std::array<int, 6> bounds{};
    for (size_t i = 0; i < 6; ++i) bounds[i] = static_cast<int>(b[i]);
    if (auto problem = CheckHsvBounds(bounds)) {
      throw InputError("--hsv: " + *problem);
    }
    range = HsvRange::FromBounds(bounds);
  }
  ColorTuningOptions tuning_options;
  tuning_options.dot_radius_px = options.dot_radius_px;
  if (auto problem = tuning_options.Check()) {
    throw InputError("--dot-radius-px: " + *problem);
  }
  VideoReader reader(options.video_path);
  const VideoFrame frame = reader.SeekTo(options.at_s);
  const ColorTuning tuning = TuneColor(frame.bgr, range, tuning_options);
  if (!tuning.found) {
    throw InputError(fmt::format(
        "{}: {} at t = {:.3f} s ({}); try another --at, or a wider --hsv",
        options.video_path, tuning.why_not, frame.time_s, options.color));
  }
  const fs::path dir(options.output_dir);
  std::error_code error;
  fs::create_directories(dir, error);
  if (error) {
    throw InputError("--out: cannot create " + dir.string() + " (" +
                     error.message() + ")");
  }
  const std::string stem =
      fmt::format("tune_{}_{:.2f}s", options.color, frame.time_s);
  WritePng(dir / (stem + "_frame.png"), frame.bgr);
  WritePng(dir / (stem + "_mask.png"), tuning.mask);
  WritePng(dir / (stem + "_overlay.png"), tuning.overlay);

  const BlobSummary& blobs = tuning.blobs;
  out << fmt::format(
      "t = {:.3f} s, {}: {} dot{} (radius {:.1f} px), {} blob{} rejected by "
      "size, {} by shape; images: {}/{}_{{frame,mask,overlay}}.png\n",
      frame.time_s, options.color, blobs.accepted.size(),
      blobs.accepted.size() == 1 ? "" : "s", tuning.segmentation.dot_radius_px,
      blobs.rejected_area, blobs.rejected_area == 1 ? "" : "s",
      blobs.rejected_shape, dir.string(), stem);
  const LearnedHsvRange& learned = tuning.learned;
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
