#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "util/input_error.h"
#include "vision/video_reader.h"
#include "vision/video_writer.h"

namespace softbench {
namespace {

namespace fs = std::filesystem;

// A frame whose content identifies its index: a bright square moving right
// over a gradient, plus the index written as a bar.
cv::Mat TestFrame(int index, cv::Size size) {
  cv::Mat frame(size, CV_8UC3);
  for (int v = 0; v < size.height; ++v) {
    for (int u = 0; u < size.width; ++u) {
      frame.at<cv::Vec3b>(v, u) = cv::Vec3b(u % 256, v % 256, 128);
    }
  }
  cv::rectangle(frame, cv::Rect(8 + 4 * index, 40, 30, 30),
                cv::Scalar(255, 255, 255), -1);
  cv::rectangle(frame, cv::Rect(0, 0, 2 * index + 2, 8), cv::Scalar(0, 0, 0),
                -1);
  return frame;
}

std::string WriteVideo(const std::string& name, int frames,
                       const VideoWriterOptions& options = {}) {
  const std::string path = (fs::temp_directory_path() / name).string();
  VideoWriter writer(path, 320, 240, options);
  for (int k = 0; k < frames; ++k) writer.Write(TestFrame(k, {320, 240}));
  writer.Close();
  return path;
}

// True when `frame` decodes frame `index` of TestFrame: closer to it than to
// its neighbours, and close in absolute terms (4:2:0 chroma limits the PSNR
// of the colourful test pattern to about 30 dB).
bool IsFrame(const cv::Mat& frame, int index, cv::Size size, int rotate = -1) {
  const auto reference = [&](int k) {
    cv::Mat m = TestFrame(k, size);
    if (rotate >= 0) cv::rotate(m, m, rotate);
    return m;
  };
  const double own = cv::PSNR(frame, reference(index));
  return own > 28.0 && own > cv::PSNR(frame, reference(index + 1)) + 3.0 &&
         (index == 0 || own > cv::PSNR(frame, reference(index - 1)) + 3.0);
}

TEST(VideoIo, WrittenVideoReadsBackWithItsFactsAndTimes) {
  VideoWriterOptions options;
  options.fps = 30;
  options.keyframe_interval_s = 0.5;
  const std::string path = WriteVideo("softbench_io_h264.mp4", 45, options);
  VideoReader reader(path);
  EXPECT_EQ(reader.info().codec, "h264");
  EXPECT_EQ(reader.info().width_px, 320);
  EXPECT_EQ(reader.info().height_px, 240);
  EXPECT_DOUBLE_EQ(reader.info().fps, 30.0);
  EXPECT_EQ(reader.info().frame_count, 45);
  EXPECT_NEAR(reader.info().duration_s, 1.5, 1e-9);
  VideoFrame frame;
  int k = 0;
  while (reader.Read(&frame)) {
    EXPECT_EQ(frame.index, k);
    EXPECT_NEAR(frame.time_s, k / 30.0, 1e-9);
    EXPECT_TRUE(IsFrame(frame.bgr, k, {320, 240})) << k;
    ASSERT_EQ(frame.luma.type(), CV_8UC1);
    ++k;
  }
  EXPECT_EQ(k, 45);
  EXPECT_FALSE(reader.Read(&frame));  // stays at the end, no loop
}

TEST(VideoIo, HevcRoundTrips) {
  VideoWriterOptions options;
  options.codec = "hevc";
  const std::string path = WriteVideo("softbench_io_hevc.mp4", 20, options);
  VideoReader reader(path);
  EXPECT_EQ(reader.info().codec, "hevc");
  VideoFrame frame;
  int k = 0;
  while (reader.Read(&frame)) {
    EXPECT_TRUE(IsFrame(frame.bgr, k, {320, 240})) << k;
    ++k;
  }
  EXPECT_EQ(k, 20);
}

TEST(VideoIo, QuickTimeMovRoundTrips) {
  const std::string path = WriteVideo("softbench_io.mov", 12);
  VideoReader reader(path);
  EXPECT_EQ(reader.info().frame_count, 12);
  VideoFrame frame;
  int k = 0;
  while (reader.Read(&frame)) EXPECT_TRUE(IsFrame(frame.bgr, k++, {320, 240}));
  EXPECT_EQ(k, 12);
}

TEST(VideoIo, SeekLandsOnTheRequestedFrame) {
  VideoWriterOptions options;
  options.keyframe_interval_s = 0.3;
  const std::string path = WriteVideo("softbench_io_seek.mp4", 60, options);
  VideoReader reader(path);
  // Backwards, forwards across key frames, and forwards within one.
  for (double t : {1.0, 0.2, 1.9, 0.0, 1.0 + 0.4 / 30, 1.1, 1.2}) {
    const VideoFrame frame = reader.SeekTo(t);
    const int expected = static_cast<int>(std::lround(t * 30));
    EXPECT_EQ(frame.index, expected) << t;
    EXPECT_TRUE(IsFrame(frame.bgr, expected, {320, 240})) << t;
    VideoFrame next;
    ASSERT_TRUE(reader.Read(&next) || expected == 59);
    if (expected < 59) {
      EXPECT_EQ(next.index, expected + 1);
    }
  }
  EXPECT_THROW(reader.SeekTo(2.5), InputError);
  EXPECT_THROW(reader.SeekTo(-1.0), InputError);
}

TEST(VideoIo, RotationMetadataIsApplied) {
  VideoWriterOptions options;
  options.rotation_deg = 90;
  const std::string path = WriteVideo("softbench_io_rotated.mp4", 5, options);
  VideoReader reader(path);
  EXPECT_EQ(reader.info().rotation_deg, 90);
  EXPECT_EQ(reader.info().width_px, 240);
  EXPECT_EQ(reader.info().height_px, 320);
  VideoFrame frame;
  ASSERT_TRUE(reader.Read(&frame));
  EXPECT_TRUE(IsFrame(frame.bgr, 0, {320, 240}, cv::ROTATE_90_CLOCKWISE));
  EXPECT_EQ(frame.luma.cols, 240);
}

// Largest per-channel difference between a region's colour and the same
// pixels of the full frame, away from the region's own edge (where chroma
// interpolation has no outside neighbours).
int RegionMismatch(VideoReader* reader, const VideoFrame& frame,
                   const cv::Rect& region) {
  const cv::Mat part = reader->BgrRegion(region);
  EXPECT_EQ(part.size(), (region & cv::Rect({}, frame.bgr.size())).size());
  const cv::Rect inner(2, 2, part.cols - 4, part.rows - 4);
  cv::Mat difference;
  cv::absdiff(part(inner),
              frame.bgr(region & cv::Rect({}, frame.bgr.size()))(inner),
              difference);
  double largest = 0.0;
  cv::minMaxLoc(difference.reshape(1), nullptr, &largest);
  return static_cast<int>(largest);
}

// Mean and largest per-channel difference between a region reduced by the
// reader and OpenCV's area resampling of the same pixels of the full frame.
std::pair<double, int> ReducedMismatch(VideoReader* reader,
                                       const VideoFrame& frame,
                                       const cv::Rect& region,
                                       const cv::Size& size) {
  const cv::Mat reduced = reader->BgrRegionReduced(region, size);
  EXPECT_EQ(reduced.size(), size);
  cv::Mat expected, difference;
  cv::resize(frame.bgr(region), expected, size, 0, 0, cv::INTER_AREA);
  cv::absdiff(reduced, expected, difference);
  double largest = 0.0;
  cv::minMaxLoc(difference.reshape(1), nullptr, &largest);
  return {cv::mean(difference.reshape(1))[0], static_cast<int>(largest)};
}

TEST(VideoIo, ReducedRegionAveragesTheColour) {
  const std::string path = WriteVideo("softbench_io_reduced.mp4", 3);
  VideoReader reader(path);
  VideoFrame frame;
  ASSERT_TRUE(reader.Read(&frame));
  // Even corners convert straight from the planes, averaging the 4:2:0
  // chroma as it comes (close to averaging the upsampled colour: a level or
  // so on average, more at sharp colour edges).
  for (const auto& [region, size] :
       {std::pair{cv::Rect(0, 0, 320, 240), cv::Size(80, 60)},
        std::pair{cv::Rect(32, 40, 120, 90), cv::Size(40, 30)}}) {
    EXPECT_LT(ReducedMismatch(&reader, frame, region, size).first, 2.0)
        << region;
  }
  // Odd ones go through the full-resolution region: exactly OpenCV's.
  const auto [mean, largest] = ReducedMismatch(
      &reader, frame, cv::Rect(33, 41, 67, 67), cv::Size(23, 23));
  EXPECT_EQ(largest, 0);
  EXPECT_TRUE(
      reader.BgrRegionReduced(cv::Rect(400, 400, 10, 10), {2, 2}).empty());
}

TEST(VideoIo, RegionColourMatchesTheFullFrame) {
  const std::string path = WriteVideo("softbench_io_region.mp4", 3);
  VideoReader reader(path);
  VideoFrame frame;
  ASSERT_TRUE(reader.Read(&frame));
  // Odd corners and sizes, and a region cut by the frame's edge.
  for (const cv::Rect& region :
       {cv::Rect(33, 41, 67, 67), cv::Rect(100, 100, 20, 30),
        cv::Rect(290, 200, 60, 60)}) {
    EXPECT_LE(RegionMismatch(&reader, frame, region), 2) << region;
  }
  EXPECT_TRUE(reader.BgrRegion(cv::Rect(400, 400, 10, 10)).empty());
  // Rotated video takes the full-frame path and agrees too.
  VideoWriterOptions rotated;
  rotated.rotation_deg = 90;
  VideoReader turned(WriteVideo("softbench_io_region_rotated.mp4", 2, rotated));
  ASSERT_TRUE(turned.Read(&frame));
  EXPECT_EQ(RegionMismatch(&turned, frame, cv::Rect(31, 17, 50, 40)), 0);
}

TEST(VideoIo, TruncatedFileIsAClearErrorNamingTheLastGoodFrame) {
  const std::string path = WriteVideo("softbench_io_full.mp4", 90);
  const std::string cut =
      (fs::temp_directory_path() / "softbench_io_cut.mp4").string();
  fs::copy_file(path, cut, fs::copy_options::overwrite_existing);
  fs::resize_file(cut, fs::file_size(path) * 6 / 10);
  VideoReader reader(cut);  // the moov atom is first: the file still opens
  VideoFrame frame;
  try {
    while (reader.Read(&frame)) {
    }
    FAIL() << "a truncated file read to the end without an error";
  } catch (const InputError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find(cut), std::string::npos) << message;
    EXPECT_NE(message.find("truncated"), std::string::npos) << message;
    EXPECT_NE(message.find("90 frames"), std::string::npos) << message;
    EXPECT_NE(message.find("after frame"), std::string::npos) << message;
  }
}

TEST(VideoIo, UnreadableFilesAreClearErrors) {
  const std::string junk =
      (fs::temp_directory_path() / "softbench_io_junk.mp4").string();
  std::ofstream(junk) << "this is not a video";
  EXPECT_THROW(VideoReader reader(junk), InputError);
  EXPECT_THROW(VideoReader reader("/nonexistent/softbench.mp4"), InputError);
}

}  // namespace
}  // namespace softbench
