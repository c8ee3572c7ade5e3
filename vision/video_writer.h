#ifndef SOFTBENCH_VISION_VIDEO_WRITER_H_
#define SOFTBENCH_VISION_VIDEO_WRITER_H_

#include <memory>
#include <opencv2/core.hpp>
#include <optional>
#include <string>

#include "vision/color_transfer.h"

namespace softbench {

struct VideoWriterOptions {
  std::string codec = "h264";  // a name of VideoCodecs() (video_codecs.h)
  double fps = 30.0;
  // Constant rate factor: lower is better quality and larger files (x264 and
  // x265 scale; 18 is visually lossless for x264).
  int crf = 20;
  // > 0: an average bitrate [Mb/s] instead of the CRF, with a VBV buffer as
  // a phone's hardware encoder keeps (an iPhone writes about 10 Mb/s at
  // 1080p30 in HEVC, 16 in H.264).
  double bitrate_mbps = 0.0;
  // Seconds between key frames: seeking decodes from the previous one. Phones
  // write about 1 s.
  double keyframe_interval_s = 2.0;
  std::string preset = "medium";  // encoder speed/size trade-off
  // Encoder threads. Output is bit-for-bit reproducible for a fixed value.
  int threads = 1;
  // Rotation metadata to store (clockwise degrees: 0, 90, 180, 270), as a
  // phone held upright writes it.
  int rotation_deg = 0;
  // Bits per sample: 8, 10 or 12 (12 with HEVC only).
  int bit_depth = 8;
  // Chroma subsampling: "4:2:0" (phones), "4:2:2" or "4:4:4".
  std::string chroma = "4:2:0";
  // Full-range YUV (0-255) instead of limited (16-235), as some lab cameras
  // write.
  bool full_range = false;
  // The colours written: SDR BT.709, or what a phone's HDR mode writes (HLG
  // or PQ with BT.2020 primaries and matrix), converted from the SDR frames
  // given with SDR white at BT.2408's reference white.
  ColorEncoding encoding;
  // Timestamp ticks per second: 0 gives one tick per frame (constant frame
  // rate); > 0 lets Write() place each frame at its own time (variable frame
  // rate; iPhones use 600).
  int time_base_hz = 0;

  std::optional<std::string> Problem() const;
};

// Encodes BGR frames into MP4, or QuickTime MOV for a ".mov" path (H.264 or
// HEVC; 8 to 12 bits; 4:2:0, 4:2:2 or 4:4:4; limited or full range; SDR
// BT.709 or HDR; moov atom first). Writes to `path` directly; callers wanting
// atomic output write to a temporary path and rename it.
class VideoWriter {
 public:
  VideoWriter(const std::string& path, int width_px, int height_px,
              const VideoWriterOptions& options = {});
  ~VideoWriter();
  VideoWriter(const VideoWriter&) = delete;
  VideoWriter& operator=(const VideoWriter&) = delete;

  // Appends one frame of the writer's size: SDR BT.709 BGR, CV_8UC3 or
  // CV_16UC3 (65535 = white, for deeper video). `time_s` places it on a
  // variable-rate clock (time_base_hz > 0; times must increase); by default
  // frames are 1 / fps apart.
  void Write(const cv::Mat& bgr, double time_s = -1.0);
  // Flushes the encoder and finalises the file; called by the destructor if
  // needed (errors there are swallowed, so call it to see them).
  void Close();

 private:
  struct State;
  std::unique_ptr<State> state_;
};

}  // namespace softbench

#endif  // SOFTBENCH_VISION_VIDEO_WRITER_H_
