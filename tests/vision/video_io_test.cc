#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <random>
#include <set>

#include "tests/support/input_error_matchers.h"
#include "tests/support/scratch_directory.h"
#include "util/input_error.h"
#include "vision/luma.h"
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
  const std::string path = (TestScratch().dir() / name).string();
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
  // A key frame every 15 frames, known before any is decoded.
  const std::vector<double> key_frames_s = {0.0, 0.5, 1.0};
  ASSERT_EQ(reader.info().key_frame_times_s.size(), key_frames_s.size());
  for (size_t i = 0; i < key_frames_s.size(); ++i) {
    EXPECT_NEAR(reader.info().key_frame_times_s[i], key_frames_s[i], 1e-9);
  }
  VideoFrame frame;
  int k = 0;
  while (reader.Read(&frame)) {
    EXPECT_EQ(frame.index, k);
    EXPECT_NEAR(frame.time_s, k / 30.0, 1e-9);
    EXPECT_TRUE(IsFrame(frame.bgr, k, {320, 240})) << k;
    ASSERT_EQ(frame.luma.type(), CV_8UC1);
    if (k % 15 == 0) {
      EXPECT_TRUE(frame.intra) << k;
    }
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

// x265 writes open GOPs: the frames shown just before a key frame (CRA) are
// decoded after it and need the GOP before, so a decoder started at that
// key frame drops them. Seeking must still land on every one of them.
TEST(VideoIo, SeekLandsOnEveryFrameOfOpenGopHevc) {
  VideoWriterOptions options;
  options.codec = "hevc";
  options.keyframe_interval_s = 0.3;
  const std::string path = WriteVideo("softbench_io_open_gop.mp4", 40, options);
  VideoReader reader(path);
  for (int k = 39; k >= 0; k -= 2) {  // backwards: a real seek every time
    const VideoFrame frame = reader.SeekTo(k / 30.0);
    EXPECT_EQ(frame.index, k);
    EXPECT_TRUE(IsFrame(frame.bgr, k, {320, 240})) << k;
  }
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
  // Rotated video (a phone's portrait) converts the region as stored and
  // turns it upright: the same colours as the upright full frame, reduced
  // regions too.
  for (const int rotation : {90, 180, 270}) {
    VideoWriterOptions rotated;
    rotated.rotation_deg = rotation;
    VideoReader turned(
        WriteVideo("softbench_io_region_rotated.mp4", 2, rotated));
    ASSERT_TRUE(turned.Read(&frame));
    for (const cv::Rect& region :
         {cv::Rect(31, 17, 50, 40), cv::Rect(100, 64, 32, 48),
          cv::Rect(190, 200, 60, 60)}) {
      EXPECT_LE(RegionMismatch(&turned, frame, region), 2)
          << rotation << " " << region;
    }
    // (Upside down, 4:2:0's left-sited chroma lands half a sample off: a
    // little more colour difference at the pattern's sharp colour edges.)
    EXPECT_LT(ReducedMismatch(&turned, frame, cv::Rect(32, 40, 120, 90),
                              cv::Size(40, 30))
                  .first,
              3.0)
        << rotation;
  }
}

TEST(VideoIo, TruncatedFileIsAClearErrorNamingTheLastGoodFrame) {
  const std::string path = WriteVideo("softbench_io_full.mp4", 90);
  const std::string cut =
      (TestScratch().dir() / "softbench_io_cut.mp4").string();
  fs::copy_file(path, cut, fs::copy_options::overwrite_existing);
  fs::resize_file(cut, fs::file_size(path) * 6 / 10);
  VideoReader reader(cut);  // the moov atom is first: the file still opens
  VideoFrame frame;
  const std::string message = InputErrorOf([&] {
    while (reader.Read(&frame)) {
    }
  });
  EXPECT_NE(message.find(cut), std::string::npos) << message;
  EXPECT_NE(message.find("truncated"), std::string::npos) << message;
  EXPECT_NE(message.find("90 frames"), std::string::npos) << message;
  EXPECT_NE(message.find("after frame"), std::string::npos) << message;
}

// Bit flips in the stream: the frames the decoder conceals, and those
// predicted from them up to the next key frame, are marked damaged (never
// handed on as good pixels); a clean copy has none.
TEST(VideoIo, DamagedDataIsMarkedUpToTheNextKeyFrame) {
  const std::string path = WriteVideo("softbench_io_clean.mp4", 120);
  const auto damaged_frames = [](const std::string& file) {
    VideoReader reader(file);
    VideoFrame frame;
    std::vector<int64_t> marked;
    while (reader.Read(&frame)) {
      if (frame.damaged) marked.push_back(frame.index);
    }
    EXPECT_EQ(marked.size(),
              reader.damaged_frames().size() -
                  std::count_if(reader.damaged_frames().begin(),
                                reader.damaged_frames().end(),
                                [](const auto& d) { return d.lost; }));
    return reader.damaged_frames().size();
  };
  EXPECT_EQ(damaged_frames(path), 0u);
  const std::string flipped =
      (TestScratch().dir() / "softbench_io_flipped.mp4").string();
  fs::copy_file(path, flipped, fs::copy_options::overwrite_existing);
  std::fstream bytes(flipped, std::ios::in | std::ios::out | std::ios::binary);
  const auto size = static_cast<std::streamoff>(fs::file_size(flipped));
  std::mt19937 random(7);
  // Flip bits in the middle half, where the frames' data lies (the moov
  // atom with the sample table is at the start).
  std::uniform_int_distribution<std::streamoff> where(size / 4, 3 * size / 4);
  for (int k = 0; k < 40; ++k) {
    const std::streamoff at = where(random);
    char c = 0;
    bytes.seekg(at);
    bytes.get(c);
    bytes.seekp(at);
    bytes.put(static_cast<char>(c ^ 0x5A));
  }
  bytes.close();
  // Either marked as damaged, or refused as damaged beyond decoding.
  const std::string message =
      InputErrorOf([&] { EXPECT_GT(damaged_frames(flipped), 0u); });
  if (!message.empty()) {
    EXPECT_NE(message.find("corrupt"), std::string::npos) << message;
  }
}

// With frame threads the decoder's flags on a concealed frame race with its
// output and are sometimes missing; every frame a single-threaded decoder
// flags (exactly, without a race) must still be marked damaged when read
// with threads. The bundled delta sample with 40 flipped bits has a
// damaged key frame at 72 s whose flag two threads lost in 2 runs of 4.
TEST(VideoIo, ThreadedDecodingMarksEveryFrameOneThreadFlags) {
  std::ifstream in(
      std::string(SOFTBENCH_SOURCE_DIR) + "/samples/delta/delta.mp4",
      std::ios::binary);
  std::string video((std::istreambuf_iterator<char>(in)),
                    std::istreambuf_iterator<char>());
  std::mt19937 random(3);
  std::uniform_int_distribution<size_t> where(video.size() / 3,
                                              2 * video.size() / 3);
  for (int i = 0; i < 40; ++i) video[where(random)] ^= 0x10;
  const std::string flipped =
      (TestScratch().dir() / "softbench_io_threads.mp4").string();
  std::ofstream(flipped, std::ios::binary) << video;
  const auto damaged = [&](int threads) {
    VideoReaderOptions options;
    options.want_bgr = false;
    options.threads = threads;
    VideoReader reader(flipped, options);
    std::set<int64_t> marked;
    VideoFrame frame = reader.SeekTo(70.0);
    do {
      if (frame.damaged) marked.insert(frame.index);
    } while (reader.Read(&frame) && frame.time_s < 76.0);
    return marked;
  };
  const std::set<int64_t> flagged = damaged(1);
  ASSERT_GT(flagged.size(), 30u);  // the key frame at 72 s and its GOP
  for (int run = 0; run < 3; ++run) {
    const std::set<int64_t> threaded = damaged(2);
    for (int64_t index : flagged) {
      EXPECT_TRUE(threaded.contains(index))
          << "frame " << index << ", run " << run;
    }
  }
}

TEST(VideoIo, UnreadableFilesAreClearErrors) {
  const std::string junk =
      (TestScratch().dir() / "softbench_io_junk.mp4").string();
  std::ofstream(junk) << "this is not a video";
  EXPECT_THROW(VideoReader reader(junk), InputError);
  EXPECT_THROW(VideoReader reader("/nonexistent/softbench.mp4"), InputError);
  // An empty file, a folder and a device are named as such.
  const std::string empty =
      (TestScratch().dir() / "softbench_io_empty.mp4").string();
  std::ofstream{empty};
  const auto open = [](const std::string& path) {
    return [path] { VideoReader reader(path); };
  };
  EXPECT_THAT(open(empty),
              ThrowsInputErrorWith(empty, "", "the file is empty (0 bytes)"));
  EXPECT_THAT(
      open(TestScratch().dir().string()),
      ThrowsInputErrorWith(TestScratch().dir().string(), "", "is a folder"));
  EXPECT_THAT(open("/dev/null"),
              ThrowsInputErrorWith("/dev/null", "", "not a regular file"));
  // A photo (a PNG is refused as rgb24 above the container's kind).
  const std::string still =
      (TestScratch().dir() / "softbench_io_still.jpg").string();
  cv::imwrite(still, TestFrame(0, {320, 240}));
  EXPECT_THAT(open(still), ThrowsInputErrorWith(still, "", "is a still image"));
  // A stream whose header declares an absurd size (YUV4MPEG2: the size is a
  // header field, within FFmpeg's own limit but beyond any camera's) is
  // refused at open, not allocated.
  const std::string absurd =
      (TestScratch().dir() / "softbench_io_absurd.y4m").string();
  std::ofstream(absurd, std::ios::binary)
      << "YUV4MPEG2 W20000 H10000 F30:1 Ip A1:1 C420jpeg\nFRAME\n"
      << std::string(4096, '\x80');
  EXPECT_THAT(open(absurd), ThrowsInputErrorWith("softbench_io_absurd.y4m", "",
                                                 "declares a 20000x10000 "
                                                 "picture"));
}

// Four flat patches: white, black, a dot's red and mid grey.
cv::Mat Patches() {
  cv::Mat frame(128, 128, CV_8UC3);
  frame(cv::Rect(0, 0, 64, 64)).setTo(cv::Scalar(255, 255, 255));
  frame(cv::Rect(64, 0, 64, 64)).setTo(cv::Scalar(0, 0, 0));
  frame(cv::Rect(0, 64, 64, 64)).setTo(cv::Scalar(40, 60, 200));
  frame(cv::Rect(64, 64, 64, 64)).setTo(cv::Scalar(128, 128, 128));
  return frame;
}

// Every format phones and lab cameras write reads back with its facts and,
// through SDR, the colours it was made from: 8, 10 and 12 bits; 4:2:0,
// 4:2:2 and 4:4:4; limited and full range; SDR, HLG and PQ.
TEST(VideoIo, EveryPhoneAndCameraFormatReadsBackItsColours) {
  struct Format {
    std::string codec;
    int bits;
    std::string chroma;
    bool full_range;
    ColorEncoding encoding;
    std::string pixel_format;
  };
  const ColorEncoding sdr, hlg{Transfer::kHlg, Primaries::kBt2020},
      pq{Transfer::kPq, Primaries::kBt2020},
      sdr2020{Transfer::kSdr, Primaries::kBt2020};
  const std::vector<Format> formats = {
      {"h264", 8, "4:2:0", false, sdr, "yuv420p"},
      {"h264", 8, "4:2:2", true, sdr, "yuvj422p"},
      {"h264", 10, "4:4:4", false, sdr, "yuv444p10le"},
      {"hevc", 10, "4:2:0", false, hlg, "yuv420p10le"},
      {"hevc", 10, "4:2:2", true, pq, "yuv422p10le"},
      {"hevc", 12, "4:4:4", false, hlg, "yuv444p12le"},
      {"hevc", 12, "4:2:0", true, sdr2020, "yuv420p12le"},
  };
  const cv::Mat patches = Patches();
  for (const Format& f : formats) {
    VideoWriterOptions options;
    options.codec = f.codec;
    options.bit_depth = f.bits;
    options.chroma = f.chroma;
    options.full_range = f.full_range;
    options.encoding = f.encoding;
    options.crf = 0;
    const std::string path =
        (TestScratch().dir() / "softbench_io_format.mp4").string();
    {
      VideoWriter writer(path, 128, 128, options);
      for (int k = 0; k < 3; ++k) writer.Write(patches);
      writer.Close();
    }
    VideoReader reader(path);
    const VideoInfo& info = reader.info();
    const std::string what = f.codec + " " + f.pixel_format + " " +
                             f.encoding.Name() + " " + info.Description();
    EXPECT_EQ(info.bit_depth, f.bits) << what;
    EXPECT_EQ(info.chroma, f.chroma) << what;
    EXPECT_EQ(info.full_range, f.full_range) << what;
    EXPECT_EQ(info.encoding.Name(), f.encoding.Name()) << what;
    VideoFrame frame;
    ASSERT_TRUE(reader.Read(&frame)) << what;
    EXPECT_EQ(frame.luma.type(), f.bits > 8 ? CV_16UC1 : CV_8UC1) << what;
    for (const cv::Point centre : {cv::Point(32, 32), cv::Point(96, 32),
                                   cv::Point(32, 96), cv::Point(96, 96)}) {
      const cv::Vec3b got = frame.bgr.at<cv::Vec3b>(centre);
      const cv::Vec3b want = patches.at<cv::Vec3b>(centre);
      for (int c = 0; c < 3; ++c) {
        EXPECT_NEAR(got[c], want[c], 3) << what << " at " << centre;
      }
    }
    // A region converts like the whole frame.
    const cv::Mat region = reader.BgrRegion(cv::Rect(20, 80, 24, 24));
    EXPECT_NEAR(region.at<cv::Vec3b>(12, 12)[2], 200, 3) << what;
  }
}

// Deeper video keeps luma between 8-bit levels: two patches half a level
// apart read half a level apart (limited range: 219 / 255 of it), where
// 8-bit luma would round both to one level or a whole one apart. Its codes
// are read as decoded, 10 bits, and the encoding says so.
TEST(VideoIo, DeepLumaKeepsFractionsOfAnEightBitLevel) {
  VideoWriterOptions options;
  options.bit_depth = 10;
  options.crf = 0;  // x264 at 10 bits and CRF 0 is lossless
  const std::string path =
      (TestScratch().dir() / "softbench_io_deep.mp4").string();
  cv::Mat grey(64, 128, CV_16UC3);
  grey.colRange(0, 64).setTo(cv::Scalar::all(100.0 * 257));
  grey.colRange(64, 128).setTo(cv::Scalar::all(100.5 * 257));
  {
    VideoWriter writer(path, 128, 64, options);
    writer.Write(grey);
    writer.Close();
  }
  VideoReader reader(path);
  VideoFrame frame;
  ASSERT_TRUE(reader.Read(&frame));
  ASSERT_EQ(frame.luma.type(), CV_16UC1);
  EXPECT_EQ(reader.info().luma_code_bits, 10);
  double highest = 0.0;
  cv::minMaxLoc(frame.luma, nullptr, &highest);
  EXPECT_LT(highest, 1024);
  const double levels = LevelsPerCode(CV_16U, reader.info().luma_encoding());
  const double left = frame.luma.at<uint16_t>(32, 32) * levels;
  const double right = frame.luma.at<uint16_t>(32, 96) * levels;
  EXPECT_NEAR(right - left, 0.5 * 219 / 255, 0.15);
  EXPECT_NEAR(left, 16 + 100.0 * 219 / 255, 0.5);
}

// Deep luma of a rotated video (a portrait phone video) is the stored luma
// turned exactly, whatever the rotation and sizes not a multiple of the
// 8 x 8 blocks it is turned in.
TEST(VideoIo, DeepLumaOfRotatedVideoIsTurnedExactly) {
  cv::Mat frame(246, 326, CV_16UC3);
  cv::RNG rng(5);
  rng.fill(frame, cv::RNG::UNIFORM, 0, 65536);
  const auto luma_of = [&](int rotation) {
    VideoWriterOptions options;
    options.bit_depth = 10;
    options.crf = 0;  // lossless
    options.rotation_deg = rotation;
    const std::string path =
        (TestScratch().dir() / "softbench_io_deep_rotated.mp4").string();
    {
      VideoWriter writer(path, 326, 246, options);
      writer.Write(frame);
      writer.Close();
    }
    VideoReader reader(path);
    VideoFrame decoded;
    EXPECT_TRUE(reader.Read(&decoded));
    return decoded.luma.clone();
  };
  const cv::Mat upright = luma_of(0);
  ASSERT_EQ(upright.type(), CV_16UC1);
  for (const auto& [rotation, code] :
       {std::pair{90, cv::ROTATE_90_CLOCKWISE}, std::pair{180, cv::ROTATE_180},
        std::pair{270, cv::ROTATE_90_COUNTERCLOCKWISE}}) {
    cv::Mat expected;
    cv::rotate(upright, expected, code);
    const cv::Mat turned = luma_of(rotation);
    ASSERT_EQ(turned.size(), expected.size()) << rotation;
    EXPECT_EQ(cv::norm(turned, expected, cv::NORM_INF), 0.0) << rotation;
  }
}

// A variable frame rate as phones write it: every frame's time is its
// timestamp, frames are numbered in order, and seeking finds the nearest.
TEST(VideoIo, VariableFrameRateTimesComeFromTheTimestamps) {
  VideoWriterOptions options;
  options.time_base_hz = 600;
  options.keyframe_interval_s = 0.5;
  const std::string path =
      (TestScratch().dir() / "softbench_io_vfr.mp4").string();
  std::vector<double> times;
  cv::RNG rng(3);
  for (int k = 0; k < 40; ++k) {
    // Jittered by up to a third of a frame, one frame dropped.
    if (k == 20) continue;
    times.push_back(std::round((k + rng.uniform(-0.33, 0.33)) * 20.0) / 600);
  }
  times[0] = 0.0;
  {
    VideoWriter writer(path, 320, 240, options);
    for (size_t k = 0; k < times.size(); ++k) {
      writer.Write(TestFrame(static_cast<int>(k), {320, 240}), times[k]);
    }
    writer.Close();
  }
  VideoReader reader(path);
  const VideoInfo& info = reader.info();
  EXPECT_TRUE(info.variable_frame_rate);
  ASSERT_EQ(info.frame_times_s.size(), times.size());
  EXPECT_NEAR(info.LastFrameS(), times.back(), 1e-9);
  VideoFrame frame;
  for (size_t k = 0; k < times.size(); ++k) {
    EXPECT_NEAR(info.frame_times_s[k], times[k], 1e-9);
    ASSERT_TRUE(reader.Read(&frame));
    EXPECT_EQ(frame.index, static_cast<int64_t>(k));
    EXPECT_NEAR(frame.time_s, times[k], 1e-9);
  }
  // Seeking: to a little after frame 25's time, and into the dropped gap.
  for (const size_t k : {25u, 3u, 19u, 20u}) {
    const VideoFrame found = reader.SeekTo(times[k] + 0.004);
    EXPECT_EQ(found.index, static_cast<int64_t>(k));
    EXPECT_NEAR(found.time_s, times[k], 1e-9);
    EXPECT_TRUE(IsFrame(found.bgr, static_cast<int>(k), {320, 240})) << k;
  }
}

// A format softbench cannot read is refused when the file is opened, by
// name (here an RGB picture, as a user might pass by mistake).
TEST(VideoIo, RefusesAnUnsupportedPixelFormatByName) {
  const std::string path =
      (TestScratch().dir() / "softbench_io_rgb.png").string();
  cv::imwrite(path, Patches());
  const std::string message = InputErrorOf([&] { VideoReader reader(path); });
  EXPECT_NE(message.find(path), std::string::npos) << message;
  EXPECT_NE(message.find("'rgb24'"), std::string::npos) << message;
  EXPECT_NE(message.find("re-encode"), std::string::npos) << message;
}

}  // namespace
}  // namespace softbench
