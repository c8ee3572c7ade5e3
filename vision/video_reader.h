#ifndef SOFTBENCH_VISION_VIDEO_READER_H_
#define SOFTBENCH_VISION_VIDEO_READER_H_

#include <cstdint>
#include <memory>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "vision/color_transfer.h"

namespace softbench {

// One decoded frame. `luma` is the full-resolution Y plane (the channel that
// locates edges; chroma is subsampled in 4:2:0 video) at the video's full
// precision: CV_8UC1 for 8-bit video, CV_16UC1 with its codes as decoded for
// deeper video (VideoInfo::luma_code_bits; vision/luma.h reads either). `bgr`
// is the colour image converted to SDR BT.709 (color_transfer.h), so colour
// bounds tuned on any footage hold on HDR footage too. Each is filled only when
// VideoReaderOptions asks for it. For an unrotated 8-bit video `luma` is a
// view of the decoder's buffer, valid until the reader's next Read() or
// SeekTo(): clone() it to keep it.
struct VideoFrame {
  int64_t index = 0;    // 0-based frame number in presentation order
  double time_s = 0.0;  // presentation time from the start of the stream
  cv::Mat luma;         // CV_8UC1 or CV_16UC1
  cv::Mat bgr;          // CV_8UC3
  // The decoder reported errors in this frame (bit flips, a lost packet):
  // its pixels are partly concealed and must not be measured.
  bool damaged = false;
  // Coded without reference to other frames (an I picture: a key frame or
  // an intra refresh). A still scene's later frames repeat what the codec
  // drew here until the next one, so a measurement's codec error changes at
  // these frames (pipelines/validation/uncertainty_budget.h).
  bool intra = false;
};

struct VideoReaderOptions {
  bool want_luma = true;
  bool want_bgr = true;
  // Decoder threads; 0: one per core, counted as the project's workers are
  // (CoreCount, util/parallel_tasks.h). FFmpeg's own choice is one more,
  // which leaves the thread that takes and measures the frames and the
  // decoder's preempting each other: on 2 cores, `validate` on HEVC took
  // 6-7 % more wall time and 3-4 % more CPU with it (docs/benchmarks.md,
  // "One decoder thread per core").
  int threads = 0;
};

// Facts about an opened video, after rotation metadata is applied.
struct VideoInfo {
  std::string codec;  // "h264", "hevc", ...
  int width_px = 0;   // as displayed (rotation applied)
  int height_px = 0;
  double fps = 0.0;         // average frame rate
  int64_t frame_count = 0;  // from the container's sample table
  double duration_s = 0.0;
  int rotation_deg = 0;  // clockwise rotation applied to decoded frames
  // The pixel format ("yuv420p10le"), its luma bits and chroma subsampling
  // ("4:2:0"), the range and the colours ("HLG BT.2020").
  std::string pixel_format;
  int bit_depth = 8;
  // The bits of VideoFrame::luma's codes: the depth, or 16 where the format
  // stores its samples in the high bits of 16 (P010).
  int luma_code_bits = 8;
  std::string chroma;
  bool full_range = false;
  ColorEncoding encoding;
  // Every frame's presentation time in order, from the container's packets:
  // phones write variable frame rate, so frame k is not at k / fps.
  std::vector<double> frame_times_s;
  // The key frames' presentation times in order, from the same packets
  // (where a seek lands and a codec draws the picture afresh); empty when
  // the container gives no timestamps.
  std::vector<double> key_frame_times_s;
  // The median interval between frames, and whether the intervals vary by
  // more than 1 % (variable frame rate).
  double frame_interval_s = 0.0;
  bool variable_frame_rate = false;

  // Start time of the last frame (where windows must end).
  double LastFrameS() const;
  // The index of the frame nearest `time_s` (clamped to the video).
  int64_t NearestFrame(double time_s) const;
  // "hevc 1080x1920 yuv420p10le (10-bit 4:2:0, limited range, HLG BT.2020),
  // 29.98 fps variable, rotated 90°".
  std::string Description() const;
  // How the luma's codes encode light: transfer and range.
  LumaEncoding luma_encoding() const {
    return {encoding.transfer, full_range,
            luma_code_bits > 8 ? luma_code_bits : 16};
  }
};

// The one video reader of softbench (MP4/MOV with H.264 or HEVC, anything
// FFmpeg demuxes). Every failure throws InputError naming the file and, for a
// truncated or corrupt file, the last good frame; it never loops or returns a
// silently short read.
class VideoReader {
 public:
  explicit VideoReader(const std::string& path,
                       const VideoReaderOptions& options = {});
  ~VideoReader();
  VideoReader(const VideoReader&) = delete;
  VideoReader& operator=(const VideoReader&) = delete;

  const VideoInfo& info() const;
  const std::string& path() const;

  // Decodes the next frame; false at the end of the stream. Throws when the
  // stream ends before the frame count its container promises, or on corrupt
  // data.
  bool Read(VideoFrame* frame);
  // Decodes the next frame without converting it (for decode-speed
  // measurements and skipping); false at the end.
  bool Skip();

  // Returns the frame nearest `time_s` (Read() then continues after it);
  // throws when the time is outside the video or the decoder lands on
  // another frame than the container's timestamps promise. Decodes forward
  // instead of seeking when no key frame lies between, and skips the
  // non-reference frames before the target (bit-exact: nothing refers to
  // them).
  VideoFrame SeekTo(double time_s);

  // The frames lost to damaged data so far, in the order met: frames the
  // decoder marked as decoded with errors (concealed pixels), and frames the
  // container lists that the decoder never returned between two returned
  // ones. A damaged frame is returned by Read() with `damaged` set; a lost
  // one is not returned at all.
  struct DamagedFrame {
    int64_t index = 0;
    double time_s = 0.0;
    bool lost = false;  // never returned (else decoded with errors)
  };
  const std::vector<DamagedFrame>& damaged_frames() const;

  // The colour of a region (display coordinates, clipped to the frame) of
  // the frame last returned by Read() or SeekTo(), converted with the same
  // matrix as VideoFrame::bgr. Only the region is converted (and turned
  // upright), so tracking a few dots does not pay for a full-frame
  // conversion; an empty Mat when the region misses the frame.
  cv::Mat BgrRegion(const cv::Rect& region);
  // The colour of `region` (clipped to the frame) resampled to `size` by
  // averaging areas: an overview for finding dots at a fraction of the
  // pixels. Converted straight from the planes when the region is made of
  // whole chroma samples (even corners for 4:2:0); an empty Mat when the
  // region misses the frame.
  cv::Mat BgrRegionReduced(const cv::Rect& region, const cv::Size& size);

 private:
  // Whether regions convert from the planes in place (planar YUV).
  bool RegionsConvertInPlace() const;
  // A rectangle of the displayed frame in the decoded frame's pixels.
  cv::Rect StoredRect(const cv::Rect& display) const;
  // BGR of a region of whole chroma samples, at its size or `dst_size`.
  cv::Mat ConvertRegion(const cv::Rect& aligned, const cv::Size& dst_size);

  struct State;
  std::unique_ptr<State> state_;
};

}  // namespace softbench

#endif  // SOFTBENCH_VISION_VIDEO_READER_H_
