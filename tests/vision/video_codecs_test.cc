// The codec table (vision/video_codecs.h): every row is what the writer
// encodes and the reader reads back, and nothing outside it is accepted.
#include "vision/video_codecs.h"

#include <gtest/gtest.h>

#include <opencv2/core.hpp>

#include "tests/support/scratch_directory.h"
#include "vision/video_reader.h"
#include "vision/video_writer.h"

namespace softbench {
namespace {

TEST(VideoCodecs, EveryRowWritesWhatItSaysAndReadsBack) {
  ASSERT_FALSE(VideoCodecs().empty());
  for (const VideoCodec& codec : VideoCodecs()) {
    for (int bits : codec.bit_depths) {
      for (std::string_view chroma : codec.chroma) {
        VideoWriterOptions options;
        options.codec = std::string(codec.name);
        options.bit_depth = bits;
        options.chroma = std::string(chroma);
        options.preset = "ultrafast";
        ASSERT_FALSE(options.Problem()) << *options.Problem();
        const std::string path = TestScratch().Path(
            std::string(codec.name) + "_" + std::to_string(bits) + "_" +
            std::to_string(chroma[2] - '0') + ".mp4");
        {
          VideoWriter writer(path, 64, 48, options);
          for (int k = 0; k < 3; ++k) {
            writer.Write(cv::Mat(48, 64, CV_8UC3, cv::Scalar(40 * k, 90, 160)));
          }
          writer.Close();
        }
        const VideoInfo info = VideoReader(path).info();
        EXPECT_EQ(info.codec, codec.name) << path;
        EXPECT_EQ(info.bit_depth, bits) << path;
        EXPECT_EQ(info.frame_count, 3) << path;
      }
    }
  }
}

TEST(VideoCodecs, ANameOutsideTheTableIsRefusedWithTheNames) {
  VideoWriterOptions options;
  options.codec = "av1";
  ASSERT_TRUE(options.Problem());
  EXPECT_EQ(*options.Problem(), "codec must be " + VideoCodecNames());
  EXPECT_EQ(FindVideoCodec("av1"), nullptr);
  options.codec = "h264";
  options.bit_depth = 12;
  ASSERT_TRUE(options.Problem());
  EXPECT_EQ(*options.Problem(), "12 bits need hevc");
}

}  // namespace
}  // namespace softbench
