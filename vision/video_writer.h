#ifndef SOFTBENCH_VISION_VIDEO_WRITER_H_
#define SOFTBENCH_VISION_VIDEO_WRITER_H_

#include <memory>
#include <opencv2/core.hpp>
#include <optional>
#include <string>

namespace softbench {

struct VideoWriterOptions {
  std::string codec = "h264";  // "h264" (libx264) or "hevc" (libx265)
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

  std::optional<std::string> Check() const;
};

// Encodes BGR frames into MP4, or QuickTime MOV for a ".mov" path (H.264 or
// HEVC, yuv420p, BT.709 limited range, moov atom first). Writes to `path`
// directly; callers wanting atomic output write to a temporary path and rename
// it.
class VideoWriter {
 public:
  VideoWriter(const std::string& path, int width_px, int height_px,
              const VideoWriterOptions& options = {});
  ~VideoWriter();
  VideoWriter(const VideoWriter&) = delete;
  VideoWriter& operator=(const VideoWriter&) = delete;

  // Appends one CV_8UC3 frame of the writer's size.
  void Write(const cv::Mat& bgr);
  // Flushes the encoder and finalises the file; called by the destructor if
  // needed (errors there are swallowed, so call it to see them).
  void Close();

 private:
  struct State;
  std::unique_ptr<State> state_;
};

}  // namespace softbench

#endif  // SOFTBENCH_VISION_VIDEO_WRITER_H_
