#ifndef SOFTBENCH_VISION_VIDEO_READER_STATE_H_
#define SOFTBENCH_VISION_VIDEO_READER_STATE_H_

// VideoReader's insides, shared by its three files: probing the file
// (video_reader_probe.cc), decoding and seeking (video_reader.cc) and
// converting frames (video_reader_convert.cc). Not for other code.
#include <atomic>
#include <opencv2/core.hpp>
#include <optional>
#include <string>
#include <utility>
#include <vector>

extern "C" {
#include <libavcodec/avcodec.h>
#include <libavformat/avformat.h>
#include <libswscale/swscale.h>
}

#include "vision/color_transfer.h"
#include "vision/video_reader.h"

namespace softbench {

struct VideoReader::State {
  std::string path;
  VideoReaderOptions options;
  VideoInfo info;
  AVFormatContext* format = nullptr;
  AVCodecContext* codec = nullptr;
  AVPacket* packet = nullptr;
  AVFrame* frame = nullptr;
  // What a swscale context converts: its sizes, formats and method, and
  // the colour matrix and range set on it.
  struct SwsKey {
    int w = 0, h = 0, format = 0, dst_w = 0, dst_h = 0, dst_format = 0;
    int flags = 0, colorspace = 0, range = 0;
    bool operator==(const SwsKey&) const = default;
  };
  // Contexts for what was converted lately, the most recent first: a
  // head's crop and the report's snapshot alternate in size, and remaking
  // a context for each (sws_init_context and its colour tables) took ten
  // times as long as the conversion itself.
  static constexpr size_t kMaxSwsContexts = 16;
  std::vector<std::pair<SwsKey, SwsContext*>> sws_contexts;
  int stream = -1;
  AVRational time_base{1, 1};
  int64_t start_pts = 0;
  // Every frame's timestamp in presentation order (empty when the
  // container has none): frames are numbered by their place in it.
  std::vector<int64_t> frame_pts;
  const AVPixFmtDescriptor* desc = nullptr;
  cv::Mat luma_upright;  // reused: rotated luma
  // Colour of anything but SDR BT.709 goes through SDR (color_transfer.h).
  std::optional<SdrConverter> to_sdr;
  std::optional<double> hdr_white;  // HdrWhite(), once measured
  int64_t last_good_index = -1;     // for truncation messages
  // The frame Read() or SeekTo() returned last (-1 after a seek starts):
  // frames the container lists between it and the next are lost.
  int64_t last_returned_index = -1;
  // Set by a seek: the frames skipped to get there are not lost. Before any
  // seek, frames the container lists before the first one decoded are (a
  // damaged key frame at the start).
  bool seeked = false;
  // The picture size the stream's header declares (as stored, before the
  // display rotation): every decoded frame must have it.
  int header_width = 0, header_height = 0;
  std::vector<VideoReader::DamagedFrame> damaged;
  bool tainted = false;  // damaged data since the last key frame
  // Errors the decoder logged while decoding (counted from any of its
  // threads, through FFmpeg's log callback), those already attributed to
  // frames returned, and how many frames still to be returned may hold
  // the last of them (NoteReturned).
  std::atomic<int64_t> decode_errors{0};
  int64_t errors_noted = 0;
  int suspect_frames = 0;
  double last_good_time = 0.0;
  int64_t last_good_pts = AV_NOPTS_VALUE;
  // While seeking: packets presented before this are decoded only when
  // other frames refer to them (non-reference frames are skipped, exactly).
  int64_t discard_before_pts = INT64_MIN;
  bool flushing = false;
  bool finished = false;

  // Opens the file and its decoder: a folder, a device, an empty file, a
  // file FFmpeg cannot read and an absurd picture size are refused by name.
  void Open();

  // Counts the errors the decoder logs on this reader (decode_errors);
  // before the decoder is opened, so its threads' contexts inherit it.
  void CountDecoderErrors();

  // The stream's codec, frame rate, length, rotation and upright size.
  void ReadStreamInfo();

  // The pixel format, checked here so an unreadable video is refused by
  // name before any measurement starts.
  void CheckPixelFormat();

  // Every frame's time (from the timestamps, else the constant rate), and
  // whether the rate varies.
  void ReadFrameTimes();

  ~State();

  [[noreturn]] void Fail(const std::string& what) const;

  // Every way the data can run out or break says the same: where, of how
  // many, and what to do.
  [[noreturn]] void FailBroken(const std::string& detail) const;

  // Decodes one frame into `frame`; false at a clean end of stream.
  bool DecodeNext();

  // Whether the frame about to be returned shows damaged data: the decoder
  // reported errors in it or logged errors while it may have been decoding
  // it, or did either for a frame since the last key frame (errors
  // propagate through the frames predicted from a concealed one, and the
  // decoder does not flag those).
  bool FrameDamaged() const { return tainted; }
  bool FrameIntra() const { return frame->pict_type == AV_PICTURE_TYPE_I; }

  // Records the frame about to be returned: the frames the container lists
  // before it since the last one returned are lost, and it is damaged if
  // the decoder says so or if it is predicted from damaged data.
  void NoteReturned();

  double FrameTime() const;

  // After a flush of the decoder: the frames it held are gone, and with
  // them what its logged errors could be blamed on.
  void ForgetSuspects() {
    errors_noted = decode_errors.load();
    suspect_frames = 0;
  }

  // Decodes the next frame and checks that the stream did not end early.
  bool Next();

  int64_t IndexOf(int64_t pts, double time_s) const;

  // A stream may change format mid-way; what was checked at open must hold.
  void CheckFormat() const;

  // The full-precision luma of the decoded frame, upright (see
  // VideoFrame::luma): a view of the plane for unrotated video, else turned
  // (OpenCV's tiled transpose).
  cv::Mat Luma();

  // Back to the first frame, as if just opened.
  void Rewind();

  // Every frame's timestamp, from the packets (no decoding). Stops quietly
  // at damaged data: reading reports it where the frames run out.
  void ScanFrameTimes();

  // The level HDR footage shows as SDR white: BT.2408's reference white, or
  // the brightest 1 % of the first frame's luma when that is clearly (1.5
  // times) brighter, so footage graded with its white at the top of the
  // range is not clipped. One value for the whole video, from frame 0.
  double HdrWhiteOf(const cv::Mat& first_luma) const;

  // The HDR white, measured when this reader decoded frame 0 (a reader that
  // starts at the beginning: the video is opened once); else frame 0 is
  // read by a reader of its own, so this one's position is kept.
  double HdrWhite();

  void Convert(VideoFrame* out);

  // The context for `key`, made (with its colour matrix) when it is not
  // among the recent ones.
  SwsContext* SwsFor(const SwsKey& key);

  // Converts a w x h picture (planes `data`) to BGR of dst_size (the
  // picture's own size when empty), averaging areas when it reduces.
  cv::Mat ConvertBgr(const uint8_t* const* data, const int* linesize, int w,
                     int h, cv::Size dst_size = {});

  // Applies the rotation metadata (clockwise degrees) like ffmpeg's autorotate.
  void Rotate(const cv::Mat& in, cv::Mat* out) const;
};

}  // namespace softbench

#endif  // SOFTBENCH_VISION_VIDEO_READER_STATE_H_
