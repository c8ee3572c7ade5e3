#include "pipelines/commands/tune_command.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <filesystem>
#include <sstream>
#include <vector>

#include "pipelines/commands/common_flags.h"
#include "pipelines/commands/model_flags.h"
#include "pipelines/formats/dot_colors.h"
#include "pipelines/reports/tune_page.h"
#include "util/atomic_file.h"
#include "util/input_error.h"
#include "vision/color_tuning.h"
#include "vision/image_codec.h"
#include "vision/photo_reader.h"
#include "vision/video_reader.h"

namespace softbench {
namespace {

namespace fs = std::filesystem;

void WritePng(const fs::path& path, const cv::Mat& image) {
  const std::vector<uint8_t> bytes = EncodePng(image);
  WriteFileAtomically(path.string(), std::string(bytes.begin(), bytes.end()));
}

}  // namespace

void AddTuneCommand(CLI::App* c, TuneCommandOptions* options) {
  c->add_option("source", options->source_path,
                "bench video, or a photo of the bench (.png, .jpg, .heic)")
      ->required();
  c->add_option("--at", options->at_s, "video: time of the frame [s]")
      ->capture_default_str();
  c->add_option("--color", options->color,
                "marker colours, comma-separated: " + DotColorNames())
      ->capture_default_str();
  c->add_option("--hsv", options->hsv,
                "range to try instead of the colour's built-in one (one "
                "--color): h_lo,h_hi,s_lo,s_hi,v_lo,v_hi");
  c->add_option("--dot-radius-px", options->dot_radius_px,
                "expected dot radius (default: from the blobs)");
  AddOutOption(c, &options->output_dir,
               "folder for tune.html and the frame, mask and overlay PNGs")
      ->capture_default_str();
}

namespace {

struct Picture {
  cv::Mat bgr;
  double time_s = 0.0;
};

// The frame at --at of a video, or a photo as it is.
Picture LoadPicture(const TuneCommandOptions& options) {
  if (IsPhotoPath(options.source_path)) {
    return {ReadPhoto(options.source_path), 0.0};
  }
  VideoReader reader(options.source_path);
  const VideoFrame frame = reader.SeekTo(options.at_s);
  return {frame.bgr, frame.time_s};
}

// The --hsv range, or the colour's built-in one.
HsvRange RangeToTry(const TuneCommandOptions& options, const DotColor& color) {
  if (options.hsv.empty()) return HsvRange::FromBounds(color.hsv_bounds);
  const std::vector<double> b = ParseNumberList(options.hsv, "--hsv");
  if (b.size() != 6) {
    throw InputError("--hsv: give six numbers h_lo,h_hi,s_lo,s_hi,v_lo,v_hi");
  }
  std::array<int, 6> bounds{};
  for (size_t i = 0; i < 6; ++i) bounds[i] = static_cast<int>(b[i]);
  if (auto problem = CheckHsvBounds(bounds)) {
    throw InputError("--hsv: " + *problem);
  }
  return HsvRange::FromBounds(bounds);
}

std::array<int, 6> Bounds(const HsvRange& r) {
  return {r.hue_low,         r.hue_high,  r.saturation_low,
          r.saturation_high, r.value_low, r.value_high};
}

}  // namespace

int RunTune(const TuneCommandOptions& options, std::ostream& out) {
  CheckFolderToAddTo(options.output_dir, "--out");
  std::vector<const DotColor*> colors;
  std::stringstream list(options.color);
  for (std::string name; std::getline(list, name, ',');) {
    const DotColor* color = FindDotColor(name);
    if (color == nullptr) {
      throw InputError("--color: '" + name + "' is not " + DotColorNames());
    }
    colors.push_back(color);
  }
  if (colors.empty()) throw InputError("--color: name a colour");
  if (!options.hsv.empty() && colors.size() != 1) {
    throw InputError("--hsv: give it with one --color");
  }
  ColorTuningOptions tuning_options;
  tuning_options.dot_radius_px = options.dot_radius_px;
  if (auto problem = tuning_options.Problem()) {
    throw InputError("--dot-radius-px: " + *problem);
  }
  const Picture picture = LoadPicture(options);
  std::vector<ColorTuning> tunings;
  std::vector<TunedColor> tuned;
  for (const DotColor* color : colors) {
    const HsvRange range = RangeToTry(options, *color);
    ColorTuning& t =
        tunings.emplace_back(TuneColor(picture.bgr, range, tuning_options));
    const bool learned = t.found && t.learned.dot_pixels > 0;
    tuned.push_back({std::string(color->name),
                     Bounds(learned ? t.learned.range : range), t.found,
                     t.why_not, t.segmentation.dot_radius_px,
                     static_cast<int>(t.blobs.accepted.size())});
  }
  if (std::none_of(tuned.begin(), tuned.end(),
                   [](const TunedColor& c) { return c.found; })) {
    throw InputError(fmt::format(
        "{}: {} at t = {:.3f} s ({}); try another --at, or a wider --hsv",
        options.source_path, tunings.front().why_not, picture.time_s,
        options.color));
  }
  const fs::path dir(options.output_dir);
  std::error_code error;
  fs::create_directories(dir, error);
  if (error) {
    throw InputError("--out: cannot create " + dir.string() + " (" +
                     error.message() + ")");
  }
  SegmentationOptions segmentation;
  WriteFileAtomically((dir / "tune.html").string(),
                      TunePageHtml(picture.bgr, options.source_path,
                                   picture.time_s, tuned, segmentation));
  const std::string frame_stem = fmt::format("tune_{:.2f}s", picture.time_s);
  WritePng(dir / (frame_stem + "_frame.png"), picture.bgr);
  for (size_t i = 0; i < tuned.size(); ++i) {
    const ColorTuning& tuning = tunings[i];
    if (!tuning.found) {
      out << fmt::format("{}: absent ({})\n", tuned[i].name, tuning.why_not);
      continue;
    }
    const std::string stem =
        fmt::format("tune_{}_{:.2f}s", tuned[i].name, picture.time_s);
    WritePng(dir / (stem + "_mask.png"), tuning.mask);
    WritePng(dir / (stem + "_overlay.png"), tuning.overlay);
    const BlobSummary& blobs = tuning.blobs;
    out << fmt::format(
        "t = {:.3f} s, {}: {} dot{} (radius {:.1f} px), {} blob{} rejected by "
        "size, {} by shape; images: {}/{}_{{mask,overlay}}.png\n",
        picture.time_s, tuned[i].name, blobs.accepted.size(),
        blobs.accepted.size() == 1 ? "" : "s",
        tuning.segmentation.dot_radius_px, blobs.rejected_area,
        blobs.rejected_area == 1 ? "" : "s", blobs.rejected_shape, dir.string(),
        stem);
    if (!tuning.other_hue.empty()) {
      out << fmt::format(
          "{} dot-sized blob{} of another hue (h {:.0f}) left out of the "
          "dots and of the suggested range: another colour inside {}'s\n",
          tuning.other_hue.size(), tuning.other_hue.size() == 1 ? "" : "s",
          tuning.other_hues.front(), tuned[i].name);
    }
    const LearnedHsvRange& learned = tuning.learned;
    if (learned.dot_pixels == 0) {
      out << "no dots to learn a range from; try another --at or --hsv\n";
      continue;
    }
    const HsvRange& r = learned.range;
    out << fmt::format(
        "suggested range (from {} dot pixels; covers {:.1f} % of them, {} "
        "other pixels inside) - paste into the plan's marker:\n"
        "  hsv: [{}, {}, {}, {}, {}, {}]\n",
        learned.dot_pixels, 100.0 * learned.dot_coverage,
        learned.outside_pixels, r.hue_low, r.hue_high, r.saturation_low,
        r.saturation_high, r.value_low, r.value_high);
  }
  out << fmt::format("page with sliders: {}/tune.html\n", dir.string());
  return 0;
}

}  // namespace softbench
