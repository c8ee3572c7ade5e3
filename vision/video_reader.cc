#include "vision/video_reader.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <opencv2/core.hpp>
#include <opencv2/core/hal/intrin.hpp>
#include <opencv2/imgproc.hpp>
#include <optional>

extern "C" {
#include <libavcodec/avcodec.h>
#include <libavformat/avformat.h>
#include <libavutil/display.h>
#include <libavutil/imgutils.h>
#include <libavutil/pixdesc.h>
#include <libswscale/swscale.h>
}

#include "util/input_error.h"
#include "util/input_file.h"
#include "vision/ffmpeg_util.h"

namespace softbench {
namespace {

// Why softbench cannot read frames of this pixel format, if it cannot: luma
// is read straight from a plane of 8 to 16-bit samples, which every phone,
// camera and lab codec writes (planar or semi-planar YUV, or grey).
std::optional<std::string> WhyUnsupported(const AVPixFmtDescriptor* desc) {
  if (desc == nullptr) return "an unknown pixel format";
  const std::string name = desc->name;
  const uint64_t flags = desc->flags;
  const AVComponentDescriptor& y = desc->comp[0];
  if ((flags & AV_PIX_FMT_FLAG_HWACCEL) != 0) {
    return "pixel format '" + name + "' is a hardware surface";
  }
  if ((flags & (AV_PIX_FMT_FLAG_RGB | AV_PIX_FMT_FLAG_PAL |
                AV_PIX_FMT_FLAG_BAYER | AV_PIX_FMT_FLAG_FLOAT |
                AV_PIX_FMT_FLAG_BITSTREAM | AV_PIX_FMT_FLAG_BE)) != 0 ||
      y.plane != 0 || y.depth < 8 || y.depth > 16 ||
      y.step != (y.depth + y.shift > 8 ? 2 : 1)) {
    return "pixel format '" + name + "' is not YUV or grey with a luma plane";
  }
  return std::nullopt;
}

// 16-bit luma turned a quarter turn (clockwise for 90, counter-clockwise
// for 270) and shifted left by `shift`, in 8 x 8 blocks transposed in SIMD
// registers: one pass instead of cv::rotate's transpose and flip and a
// shift after them (every frame of a portrait 10-bit phone video).
void QuarterTurn16(const cv::Mat& in, int rotation_deg, int shift,
                   cv::Mat* out) {
  const int h = in.rows, w = in.cols;
  out->create(w, h, CV_16UC1);
  const bool clockwise = rotation_deg == 90;
  // Output (i, j) shows input (h - 1 - j, i) clockwise, (j, w - 1 - i)
  // counter-clockwise.
  const auto at = [&](int i, int j) -> uint16_t {
    return clockwise ? in.ptr<uint16_t>(h - 1 - j)[i]
                     : in.ptr<uint16_t>(j)[w - 1 - i];
  };
  int i0 = 0;
  for (; i0 + 8 <= w; i0 += 8) {
    int j0 = 0;
    for (; j0 + 8 <= h; j0 += 8) {
      // Rows of the input whose transpose is the output block.
      cv::v_uint16x8 r[8];
      for (int k = 0; k < 8; ++k) {
        const uint16_t* src = clockwise ? in.ptr<uint16_t>(h - 1 - j0 - k) + i0
                                        : in.ptr<uint16_t>(j0 + k) + w - 8 - i0;
        r[k] = cv::v_load(src) << shift;
      }
      cv::v_uint16x8 a[8];
      for (int k = 0; k < 8; k += 2) cv::v_zip(r[k], r[k + 1], a[k], a[k + 1]);
      cv::v_uint32x4 b[8];
      for (int k = 0; k < 2; ++k) {
        cv::v_zip(cv::v_reinterpret_as_u32(a[k]),
                  cv::v_reinterpret_as_u32(a[k + 2]), b[2 * k], b[2 * k + 1]);
        cv::v_zip(cv::v_reinterpret_as_u32(a[k + 4]),
                  cv::v_reinterpret_as_u32(a[k + 6]), b[2 * k + 4],
                  b[2 * k + 5]);
      }
      cv::v_float64x2 c[8];  // 64-bit lanes: OpenCV zips them as doubles
      for (int k = 0; k < 4; ++k) {
        cv::v_zip(cv::v_reinterpret_as_f64(b[k]),
                  cv::v_reinterpret_as_f64(b[k + 4]), c[2 * k], c[2 * k + 1]);
      }
      for (int m = 0; m < 8; ++m) {
        cv::v_store(out->ptr<uint16_t>(i0 + m) + j0,
                    cv::v_reinterpret_as_u16(c[clockwise ? m : 7 - m]));
      }
    }
    for (; j0 < h; ++j0) {
      for (int m = 0; m < 8; ++m) {
        out->ptr<uint16_t>(i0 + m)[j0] =
            static_cast<uint16_t>(at(i0 + m, j0) << shift);
      }
    }
  }
  for (; i0 < w; ++i0) {
    for (int j = 0; j < h; ++j) {
      out->ptr<uint16_t>(i0)[j] = static_cast<uint16_t>(at(i0, j) << shift);
    }
  }
}

// The transfer and primaries a stream's metadata declares (SDR BT.709 when
// unspecified, as players assume for HD video).
ColorEncoding EncodingOf(const AVCodecParameters& p) {
  ColorEncoding e;
  if (p.color_trc == AVCOL_TRC_ARIB_STD_B67) e.transfer = Transfer::kHlg;
  if (p.color_trc == AVCOL_TRC_SMPTE2084) e.transfer = Transfer::kPq;
  if (p.color_primaries == AVCOL_PRI_BT2020) e.primaries = Primaries::kBt2020;
  return e;
}

}  // namespace

double VideoInfo::LastFrameS() const {
  return frame_times_s.empty() ? 0.0 : frame_times_s.back();
}

int64_t VideoInfo::NearestFrame(double time_s) const {
  if (frame_times_s.empty()) return 0;
  const auto it =
      std::lower_bound(frame_times_s.begin(), frame_times_s.end(), time_s);
  if (it == frame_times_s.begin()) return 0;
  if (it == frame_times_s.end()) return frame_times_s.size() - 1;
  return (it - frame_times_s.begin()) - (time_s - *(it - 1) < *it - time_s);
}

std::string VideoInfo::Description() const {
  return fmt::format(
      "{} {}x{} {} ({}-bit {}, {} range, {}), {:.2f} fps{}{}", codec, width_px,
      height_px, pixel_format, bit_depth, chroma,
      full_range ? "full" : "limited", encoding.Name(), fps,
      variable_frame_rate ? " variable" : "",
      rotation_deg != 0 ? fmt::format(", rotated {}°", rotation_deg) : "");
}

struct VideoReader::State {
  std::string path;
  VideoReaderOptions options;
  VideoInfo info;
  AVFormatContext* format = nullptr;
  AVCodecContext* codec = nullptr;
  AVPacket* packet = nullptr;
  AVFrame* frame = nullptr;
  SwsContext* sws = nullptr;
  SwsContext* region_sws = nullptr;   // cached for the last region size
  SwsContext* reduced_sws = nullptr;  // the same for reduced regions
  int stream = -1;
  AVRational time_base{1, 1};
  int64_t start_pts = 0;
  // Every frame's timestamp in presentation order (empty when the
  // container has none): frames are numbered by their place in it.
  std::vector<int64_t> frame_pts;
  const AVPixFmtDescriptor* desc = nullptr;
  // Luma of deeper video: samples shifted left by this fill 16 bits.
  int luma_shift = 0;
  cv::Mat luma_upright;  // reused: rotated or shifted luma
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
  double last_good_time = 0.0;
  int64_t last_good_pts = AV_NOPTS_VALUE;
  // While seeking: packets presented before this are decoded only when
  // other frames refer to them (non-reference frames are skipped, exactly).
  int64_t discard_before_pts = INT64_MIN;
  bool flushing = false;
  bool finished = false;

  // Opens the file and its decoder: a folder, a device, an empty file, a
  // file FFmpeg cannot read and an absurd picture size are refused by name.
  void Open() {
    // A folder, a device or an empty file is named as such, not as data
    // FFmpeg cannot parse.
    if (CheckInputFile(path, "video") == 0) {
      Fail("the file is empty (0 bytes); re-copy the video");
    }
    int err = avformat_open_input(&format, path.c_str(), nullptr, nullptr);
    if (err < 0) {
      Fail("FFmpeg cannot read it as a video (" + FfmpegError(err) +
           "); check that this is the bench video, or re-copy the file if "
           "it is truncated or damaged");
    }
    err = avformat_find_stream_info(format, nullptr);
    if (err < 0)
      Fail("cannot read stream information (" + FfmpegError(err) + ")");
    stream =
        av_find_best_stream(format, AVMEDIA_TYPE_VIDEO, -1, -1, nullptr, 0);
    if (stream < 0) Fail("no video stream in the file");
    AVStream* st = format->streams[stream];
    // A camera's frame is at most 8K; a larger declared size is damage.
    constexpr int kMaxSide = 16384;
    if (st->codecpar->width <= 0 || st->codecpar->height <= 0 ||
        st->codecpar->width > kMaxSide || st->codecpar->height > kMaxSide) {
      Fail(
          fmt::format("declares a {}x{} picture, which no camera records; "
                      "re-copy or re-export the file",
                      st->codecpar->width, st->codecpar->height));
    }
    header_width = st->codecpar->width;
    header_height = st->codecpar->height;
    const AVCodec* decoder = avcodec_find_decoder(st->codecpar->codec_id);
    if (decoder == nullptr) {
      Fail(std::string("no decoder for codec '") +
           avcodec_get_name(st->codecpar->codec_id) + "'");
    }
    codec = avcodec_alloc_context3(decoder);
    avcodec_parameters_to_context(codec, st->codecpar);
    codec->thread_count = options.threads;
    codec->thread_type = FF_THREAD_FRAME | FF_THREAD_SLICE;
    err = avcodec_open2(codec, decoder, nullptr);
    if (err < 0) Fail("cannot open the decoder (" + FfmpegError(err) + ")");
    packet = av_packet_alloc();
    frame = av_frame_alloc();
    time_base = st->time_base;
    start_pts = st->start_time != AV_NOPTS_VALUE ? st->start_time : 0;
  }

  // The stream's codec, frame rate, length, rotation and upright size.
  void ReadStreamInfo() {
    AVStream* st = format->streams[stream];
    info.codec = avcodec_get_name(st->codecpar->codec_id);
    const AVRational rate =
        st->avg_frame_rate.num > 0 ? st->avg_frame_rate : st->r_frame_rate;
    info.fps = av_q2d(rate);
    if (!(info.fps > 0.0)) Fail("the video has no frame rate");
    info.frame_count = st->nb_frames;
    info.duration_s = st->duration != AV_NOPTS_VALUE
                          ? st->duration * av_q2d(st->time_base)
                          : info.frame_count / info.fps;
    if (info.frame_count <= 0) {
      info.frame_count = std::llround(info.duration_s * info.fps);
    }
    if (const uint8_t* matrix =
            av_stream_get_side_data(st, AV_PKT_DATA_DISPLAYMATRIX, nullptr)) {
      // Counter-clockwise degrees in the matrix; frames turn the other way.
      const double ccw =
          av_display_rotation_get(reinterpret_cast<const int32_t*>(matrix));
      if (std::isfinite(ccw)) {
        info.rotation_deg =
            ((-static_cast<int>(std::lround(ccw)) % 360) + 360) % 360;
      }
    }
    const bool quarter_turn =
        info.rotation_deg == 90 || info.rotation_deg == 270;
    info.width_px = quarter_turn ? st->codecpar->height : st->codecpar->width;
    info.height_px = quarter_turn ? st->codecpar->width : st->codecpar->height;
  }

  // The pixel format, checked here so an unreadable video is refused by
  // name before any measurement starts.
  void CheckPixelFormat() {
    AVStream* st = format->streams[stream];
    // The pixel format is checked here, so an unreadable video is refused by
    // name before any measurement starts.
    desc =
        av_pix_fmt_desc_get(static_cast<AVPixelFormat>(st->codecpar->format));
    if (desc == nullptr) {
      // FFmpeg decodes frames to learn the pixel format: none known means no
      // frame decoded, because the media data is missing or damaged.
      const bool has_data = av_read_frame(format, packet) >= 0;
      av_packet_unref(packet);
      Fail(has_data
               ? fmt::format("none of its first frames decodes (the video "
                             "data is damaged, though the container lists "
                             "{} frames); re-copy or re-export the video",
                             info.frame_count)
               : fmt::format("holds no video data: the container lists {} "
                             "frames, but the file ends before any of them "
                             "(a copy cut short, or an export that did not "
                             "finish); re-copy or re-export the video",
                             info.frame_count));
    }
    if (auto why = WhyUnsupported(desc)) {
      Fail(*why +
           "; softbench reads YUV or grey video of 8 to 16 bits (4:2:0, "
           "4:2:2 or 4:4:4); re-encode it, e.g. ffmpeg -i IN -pix_fmt "
           "yuv444p10le OUT.mp4");
    }
    // A photo opens as a one-frame "video"; say what it is instead of what
    // its single frame lacks.
    const std::string_view container = format->iformat->name;
    if (container == "image2" || container.ends_with("_pipe") ||
        (st->disposition & AV_DISPOSITION_ATTACHED_PIC) != 0) {
      Fail(
          fmt::format("is a still image ({}), not a video; give the bench "
                      "video",
                      container));
    }
    info.pixel_format = desc->name;
    info.bit_depth = desc->comp[0].depth;
    const int sub_w = desc->log2_chroma_w, sub_h = desc->log2_chroma_h;
    info.chroma = desc->nb_components < 3    ? "grey"
                  : sub_w == 1 && sub_h == 1 ? "4:2:0"
                  : sub_w == 1 && sub_h == 0 ? "4:2:2"
                  : sub_w == 0 && sub_h == 0 ? "4:4:4"
                                             : "4:1:1";
    info.full_range = st->codecpar->color_range == AVCOL_RANGE_JPEG ||
                      (desc->name[0] == 'y' && desc->name[1] == 'u' &&
                       desc->name[2] == 'v' && desc->name[3] == 'j');
    if (desc->comp[0].step == 2) {
      luma_shift = 16 - desc->comp[0].depth - desc->comp[0].shift;
    }
    info.encoding = EncodingOf(*st->codecpar);
  }

  // Every frame's time (from the timestamps, else the constant rate), and
  // whether the rate varies.
  void ReadFrameTimes() {
    // Only the video stream is read from here on.
    for (unsigned i = 0; i < format->nb_streams; ++i) {
      if (static_cast<int>(i) != stream) {
        format->streams[i]->discard = AVDISCARD_ALL;
      }
    }
    ScanFrameTimes();
    if (info.frame_times_s.empty()) {  // no timestamps: constant rate
      for (int64_t k = 0; k < info.frame_count; ++k) {
        info.frame_times_s.push_back(k / info.fps);
      }
    } else {
      if (info.frame_count <= 0) info.frame_count = info.frame_times_s.size();
      double shortest = INFINITY, longest = 0.0;
      for (size_t i = 0; i + 1 < info.frame_times_s.size(); ++i) {
        const double dt = info.frame_times_s[i + 1] - info.frame_times_s[i];
        shortest = std::min(shortest, dt);
        longest = std::max(longest, dt);
      }
      info.variable_frame_rate = longest > 1.01 * shortest;
    }
    info.frame_interval_s = 1.0 / info.fps;
    if (info.frame_times_s.size() >= 2) {
      std::vector<double> intervals;
      for (size_t i = 0; i + 1 < info.frame_times_s.size(); ++i) {
        intervals.push_back(info.frame_times_s[i + 1] - info.frame_times_s[i]);
      }
      std::nth_element(intervals.begin(),
                       intervals.begin() + intervals.size() / 2,
                       intervals.end());
      info.frame_interval_s = intervals[intervals.size() / 2];
    }
  }

  ~State() {
    sws_freeContext(sws);
    sws_freeContext(region_sws);
    sws_freeContext(reduced_sws);
    av_frame_free(&frame);
    av_packet_free(&packet);
    avcodec_free_context(&codec);
    avformat_close_input(&format);
  }

  [[noreturn]] void Fail(const std::string& what) const {
    throw InputError(path + ": " + what);
  }

  // Every way the data can run out or break says the same: where, of how
  // many, and what to do.
  [[noreturn]] void FailBroken(const std::string& detail) const {
    const std::string where =
        last_good_index < 0 ? "before the first frame"
                            : fmt::format("after frame {} (t = {:.3f} s)",
                                          last_good_index, last_good_time);
    Fail(
        fmt::format("the video data is truncated or corrupt {} of the {} "
                    "frames the container lists ({}); re-copy or re-export "
                    "the file",
                    where, info.frame_count, detail));
  }

  // Decodes one frame into `frame`; false at a clean end of stream.
  bool DecodeNext() {
    for (;;) {
      const int received = avcodec_receive_frame(codec, frame);
      if (received == 0) return true;
      if (received == AVERROR_EOF) return false;
      if (received != AVERROR(EAGAIN)) FailBroken(FfmpegError(received));
      if (flushing) return false;
      const int read = av_read_frame(format, packet);
      if (read == AVERROR_EOF) {
        flushing = true;
        avcodec_send_packet(codec, nullptr);
        continue;
      }
      if (read < 0) FailBroken(FfmpegError(read));
      if (packet->stream_index == stream) {
        codec->skip_frame =
            packet->pts != AV_NOPTS_VALUE && packet->pts < discard_before_pts
                ? AVDISCARD_NONREF
                : AVDISCARD_DEFAULT;
        const int sent = avcodec_send_packet(codec, packet);
        if (sent < 0 && sent != AVERROR(EAGAIN)) {
          av_packet_unref(packet);
          FailBroken(FfmpegError(sent));
        }
      }
      av_packet_unref(packet);
    }
  }

  // Whether the frame about to be returned shows damaged data: the decoder
  // reported errors in it, or in a frame since the last key frame (errors
  // propagate through the frames predicted from a concealed one, and the
  // decoder does not flag those).
  bool FrameDamaged() const { return tainted; }

  // Records the frame about to be returned: the frames the container lists
  // before it since the last one returned are lost, and it is damaged if
  // the decoder says so or if it is predicted from damaged data.
  void NoteReturned() {
    if (frame->width != header_width || frame->height != header_height) {
      Fail(fmt::format(
          "its header declares {}x{} pictures, but frame {} decodes as "
          "{}x{} (a damaged or edited header); re-copy or re-export the file",
          header_width, header_height, last_good_index, frame->width,
          frame->height));
    }
    bool lost = false;
    for (int64_t i = last_returned_index + 1;
         (last_returned_index >= 0 || !seeked) && i < last_good_index; ++i) {
      const double time_s = i < static_cast<int64_t>(info.frame_times_s.size())
                                ? info.frame_times_s[i]
                                : last_good_time;
      damaged.push_back({i, time_s, true});
      lost = true;
    }
    if (frame->key_frame) tainted = false;
    tainted = tainted || lost || frame->decode_error_flags != 0 ||
              (frame->flags & AV_FRAME_FLAG_CORRUPT) != 0;
    if (tainted) damaged.push_back({last_good_index, last_good_time, false});
    last_returned_index = last_good_index;
  }

  double FrameTime() const {
    const int64_t pts = frame->best_effort_timestamp != AV_NOPTS_VALUE
                            ? frame->best_effort_timestamp
                            : frame->pts;
    return (pts - start_pts) * av_q2d(time_base);
  }

  // Decodes the next frame and checks that the stream did not end early.
  bool Next() {
    if (finished) return false;
    if (!DecodeNext()) {
      finished = true;
      if (info.frame_count > 0 && last_good_index + 1 < info.frame_count) {
        FailBroken("the data ends early");
      }
      return false;
    }
    last_good_time = FrameTime();
    last_good_pts = frame->best_effort_timestamp != AV_NOPTS_VALUE
                        ? frame->best_effort_timestamp
                        : frame->pts;
    last_good_index = IndexOf(last_good_pts, last_good_time);
    CheckFormat();
    return true;
  }

  int64_t IndexOf(int64_t pts, double time_s) const {
    const auto it = std::lower_bound(frame_pts.begin(), frame_pts.end(), pts);
    if (it != frame_pts.end() && *it == pts) return it - frame_pts.begin();
    return std::llround(time_s * info.fps);  // no timestamps to go by
  }

  // A stream may change format mid-way; what was checked at open must hold.
  void CheckFormat() const {
    if (frame->format != static_cast<int>(av_pix_fmt_desc_get_id(desc))) {
      const AVPixFmtDescriptor* now =
          av_pix_fmt_desc_get(static_cast<AVPixelFormat>(frame->format));
      Fail(fmt::format(
          "the pixel format changes from {} to {} at t = {:.3f} s; re-encode "
          "the video with one format (ffmpeg -pix_fmt {})",
          desc->name, now != nullptr ? now->name : "unknown", last_good_time,
          desc->name));
    }
  }

  // The full-precision luma of the decoded frame, upright (see
  // VideoFrame::luma): a view of the plane for unrotated 8-bit and 16-bit
  // video, else turned (OpenCV's tiled transpose) and shifted to 16 bits.
  cv::Mat Luma() {
    const int w = frame->width, h = frame->height;
    const bool deep = desc->comp[0].step == 2;
    cv::Mat plane(h, w, deep ? CV_16UC1 : CV_8UC1, frame->data[0],
                  frame->linesize[0]);
    if (info.rotation_deg == 0 && luma_shift == 0) return plane;
    if (deep && (info.rotation_deg == 90 || info.rotation_deg == 270)) {
      QuarterTurn16(plane, info.rotation_deg, luma_shift, &luma_upright);
      return luma_upright;
    }
    if (info.rotation_deg == 0) {
      luma_upright.create(h, w, CV_16UC1);
    } else {
      Rotate(plane, &luma_upright);
    }
    if (luma_shift > 0) {
      // A shift, not convertTo's scaling through float: every frame of
      // 10-bit video comes through here.
      const cv::Mat& in = info.rotation_deg == 0 ? plane : luma_upright;
      for (int v = 0; v < luma_upright.rows; ++v) {
        const auto* src = in.ptr<uint16_t>(v);
        auto* dst = luma_upright.ptr<uint16_t>(v);
        for (int u = 0; u < luma_upright.cols; ++u) {
          dst[u] = static_cast<uint16_t>(src[u] << luma_shift);
        }
      }
    }
    return luma_upright;
  }

  // Back to the first frame, as if just opened.
  void Rewind() {
    av_seek_frame(format, stream, start_pts, AVSEEK_FLAG_BACKWARD);
    avcodec_flush_buffers(codec);
    flushing = finished = false;
    last_good_index = -1;
    last_good_time = 0.0;
    last_good_pts = AV_NOPTS_VALUE;
  }

  // Every frame's timestamp, from the packets (no decoding). Stops quietly
  // at damaged data: reading reports it where the frames run out.
  void ScanFrameTimes() {
    for (;;) {
      if (av_read_frame(format, packet) < 0) break;
      if (packet->stream_index == stream &&
          (packet->flags & AV_PKT_FLAG_DISCARD) == 0) {
        if (packet->pts == AV_NOPTS_VALUE) {
          frame_pts.clear();  // no timestamps: frames are k / fps
          av_packet_unref(packet);
          break;
        }
        frame_pts.push_back(packet->pts);
      }
      av_packet_unref(packet);
    }
    std::sort(frame_pts.begin(), frame_pts.end());
    frame_pts.erase(std::unique(frame_pts.begin(), frame_pts.end()),
                    frame_pts.end());
    for (const int64_t pts : frame_pts) {
      info.frame_times_s.push_back((pts - start_pts) * av_q2d(time_base));
    }
    Rewind();
  }

  // The level HDR footage shows as SDR white: BT.2408's reference white, or
  // the brightest 1 % of the first frame's luma when that is clearly (1.5
  // times) brighter, so footage graded with its white at the top of the
  // range is not clipped. One value for the whole video, from frame 0.
  double HdrWhiteOf(const cv::Mat& first_luma) const {
    const double reference = ReferenceWhiteLinear(info.encoding.transfer);
    cv::Mat luma = first_luma;
    if (luma.depth() == CV_8U) luma.convertTo(luma, CV_16U, 256);
    std::vector<int> histogram(1024, 0);
    for (int v = 0; v < luma.rows; ++v) {
      const auto* row = luma.ptr<uint16_t>(v);
      for (int u = 0; u < luma.cols; ++u) ++histogram[row[u] >> 6];
    }
    int64_t above = 0, bin = 1023;
    const int64_t wanted = luma.total() / 100;
    for (; bin > 0 && above + histogram[bin] <= wanted; --bin) {
      above += histogram[bin];
    }
    const double code16 = bin * 64.0;  // the bin's bottom: never above it
    const double black = info.full_range ? 0.0 : 16.0 * 256.0;
    const double white = info.full_range ? 65535.0 : 235.0 * 256.0;
    const double bright =
        ToLinear(info.encoding.transfer, (code16 - black) / (white - black));
    return bright > 1.5 * reference ? bright : reference;
  }

  // The HDR white, measured when this reader decoded frame 0 (a reader that
  // starts at the beginning: the video is opened once); else frame 0 is
  // read by a reader of its own, so this one's position is kept.
  double HdrWhite() {
    if (hdr_white) return *hdr_white;
    VideoReaderOptions luma_only;
    luma_only.want_bgr = false;
    luma_only.threads = 1;
    VideoReader first(path, luma_only);
    VideoFrame frame;
    hdr_white = first.Read(&frame)
                    ? HdrWhiteOf(frame.luma)
                    : ReferenceWhiteLinear(info.encoding.transfer);
    return *hdr_white;
  }

  void Convert(VideoFrame* out) {
    out->time_s = last_good_time;
    out->index = last_good_index;
    const int w = frame->width, h = frame->height;
    if (last_good_index == 0 && !hdr_white && !info.encoding.IsSdrBt709()) {
      hdr_white = HdrWhiteOf(Luma());
    }
    if (options.want_luma) {
      out->luma = Luma();  // a view or the reused buffer: no allocation
    } else {
      out->luma.release();
    }
    if (options.want_bgr) {
      Rotate(ConvertBgr(&sws, frame->data, frame->linesize, w, h), &out->bgr);
    } else {
      out->bgr.release();
    }
  }

  // Converts a w x h picture (planes `data`) with `*context` to BGR of
  // dst_size (the picture's own size when empty), averaging areas when it
  // reduces.
  cv::Mat ConvertBgr(SwsContext** context, const uint8_t* const* data,
                     const int* linesize, int w, int h,
                     cv::Size dst_size = {}) {
    if (dst_size.empty()) dst_size = {w, h};
    const bool reduce = dst_size != cv::Size(w, h);
    if (!info.encoding.IsSdrBt709() && !to_sdr) {
      to_sdr.emplace(info.encoding, HdrWhite());
    }
    // SDR BT.709 straight to 8 bits; anything else through 16 bits to SDR.
    *context = sws_getCachedContext(
        *context, w, h, static_cast<AVPixelFormat>(frame->format),
        dst_size.width, dst_size.height,
        to_sdr ? AV_PIX_FMT_BGR48LE : AV_PIX_FMT_BGR24,
        reduce ? SWS_AREA : SWS_BILINEAR, nullptr, nullptr, nullptr);
    SetYuvToRgb(*context, frame->colorspace, frame->color_range);
    // swscale's vector code writes whole 16-pixel blocks: rows padded to
    // them (and aligned), then cut to the width.
    cv::Mat padded(dst_size.height, (dst_size.width + 15) / 16 * 16,
                   to_sdr ? CV_16UC3 : CV_8UC3);
    uint8_t* dst[] = {padded.data};
    const int dst_stride[] = {static_cast<int>(padded.step)};
    sws_scale(*context, data, linesize, 0, h, dst, dst_stride);
    if (to_sdr) return to_sdr->Convert(padded.colRange(0, dst_size.width));
    return padded.colRange(0, dst_size.width);  // owned: not a view
  }

  // Applies the rotation metadata (clockwise degrees) like ffmpeg's autorotate.
  void Rotate(const cv::Mat& in, cv::Mat* out) const {
    switch (info.rotation_deg) {
      case 90:
        cv::rotate(in, *out, cv::ROTATE_90_CLOCKWISE);
        break;
      case 180:
        cv::rotate(in, *out, cv::ROTATE_180);
        break;
      case 270:
        cv::rotate(in, *out, cv::ROTATE_90_COUNTERCLOCKWISE);
        break;
      default:
        *out = in;
    }
  }
};

VideoReader::VideoReader(const std::string& path,
                         const VideoReaderOptions& options)
    : state_(std::make_unique<State>()) {
  State& s = *state_;
  s.path = path;
  s.options = options;
  av_log_set_level(AV_LOG_QUIET);
  s.Open();
  s.ReadStreamInfo();
  s.CheckPixelFormat();
  s.ReadFrameTimes();
}

VideoReader::~VideoReader() = default;

const VideoInfo& VideoReader::info() const { return state_->info; }
const std::string& VideoReader::path() const { return state_->path; }

bool VideoReader::Read(VideoFrame* frame) {
  if (!state_->Next()) return false;
  state_->NoteReturned();
  state_->Convert(frame);
  frame->damaged = state_->FrameDamaged();
  return true;
}

bool VideoReader::Skip() {
  if (!state_->Next()) return false;
  state_->NoteReturned();
  return true;
}

const std::vector<VideoReader::DamagedFrame>& VideoReader::damaged_frames()
    const {
  return state_->damaged;
}

VideoFrame VideoReader::SeekTo(double time_s) {
  State& s = *state_;
  const VideoInfo& info = s.info;
  const double half_frame = 0.5 * info.frame_interval_s;
  if (!(time_s >= -half_frame) || time_s > info.LastFrameS() + half_frame) {
    s.Fail(
        fmt::format("cannot seek to t = {:.3f} s: the video runs from 0 to "
                    "{:.3f} s",
                    time_s, info.duration_s));
  }
  // The frame nearest the request, by the container's timestamps.
  const int64_t wanted = info.NearestFrame(time_s);
  if (info.frame_times_s.empty()) s.Fail("the video has no frames");
  const double wanted_s = info.frame_times_s[wanted];
  const int64_t target =
      s.frame_pts.empty()
          ? s.start_pts +
                static_cast<int64_t>(std::floor(wanted_s / av_q2d(s.time_base)))
          : s.frame_pts[wanted];
  // Decode forward without seeking when no key frame lies between the frame
  // on screen and the target: a seek would start from the same key frame.
  AVStream* stream = s.format->streams[s.stream];
  const int key =
      av_index_search_timestamp(stream, target, AVSEEK_FLAG_BACKWARD);
  const AVIndexEntry* key_entry =
      key >= 0 ? avformat_index_get_entry(stream, key) : nullptr;
  bool forward = !s.finished && s.last_good_pts != AV_NOPTS_VALUE &&
                 s.last_good_pts < target && key_entry != nullptr &&
                 key_entry->timestamp <= s.last_good_pts;
  int64_t seek_to = target;
  for (int attempt = 0;; ++attempt) {
    if (!forward) {
      const int err =
          av_seek_frame(s.format, s.stream, seek_to, AVSEEK_FLAG_BACKWARD);
      if (err < 0) {
        s.Fail(fmt::format("seek to t = {:.3f} s failed ({})", time_s,
                           FfmpegError(err)));
      }
      avcodec_flush_buffers(s.codec);
      s.flushing = s.finished = false;
    }
    // Decode up to the target, skipping the frames no other frame refers
    // to.
    s.discard_before_pts = target;
    bool decoded = true;
    while ((decoded = s.Next()) && s.last_good_pts < target) {
    }
    s.discard_before_pts = INT64_MIN;
    if (decoded && std::abs(s.last_good_time - wanted_s) <=
                       (s.frame_pts.empty() ? half_frame : 1e-6)) {
      break;
    }
    // Past the target: in an open GOP (HEVC's CRA key frames) the frames
    // shown just before a key frame are decoded after it from the GOP
    // before, and a decoder that starts at that key frame drops them. Start
    // from the key frame before.
    const int earlier =
        av_index_search_timestamp(stream, seek_to, AVSEEK_FLAG_BACKWARD);
    const AVIndexEntry* entry =
        earlier >= 0 ? avformat_index_get_entry(stream, earlier) : nullptr;
    if (attempt == 2 || entry == nullptr) {
      s.Fail(decoded ? fmt::format("seek to t = {:.3f} s landed on t = "
                                   "{:.3f} s",
                                   time_s, s.last_good_time)
                     : fmt::format("seek to t = {:.3f} s ran past the end",
                                   time_s));
    }
    seek_to = entry->timestamp - 1;
    forward = false;
  }
  s.last_returned_index = -1;  // the frames skipped to get here are not lost
  s.seeked = true;
  s.tainted = false;  // decoding restarted at a key frame
  s.NoteReturned();
  VideoFrame frame;
  s.Convert(&frame);
  frame.damaged = s.FrameDamaged();
  return frame;
}

namespace {

// The planar formats whose regions convert by pointing at their planes.
const AVPixFmtDescriptor* PlanarYuv(const AVFrame& frame) {
  const AVPixFmtDescriptor* desc =
      av_pix_fmt_desc_get(static_cast<AVPixelFormat>(frame.format));
  const bool planar =
      desc != nullptr && (desc->flags & AV_PIX_FMT_FLAG_PLANAR) != 0 &&
      (desc->flags & (AV_PIX_FMT_FLAG_HWACCEL | AV_PIX_FMT_FLAG_RGB)) == 0;
  return planar ? desc : nullptr;
}

// The smallest rectangle of whole chroma samples holding `r`.
cv::Rect ChromaAligned(const cv::Rect& r, const AVPixFmtDescriptor& desc,
                       const cv::Size& frame_size) {
  const int align_x = 1 << desc.log2_chroma_w,
            align_y = 1 << desc.log2_chroma_h;
  const int x0 = r.x / align_x * align_x, y0 = r.y / align_y * align_y;
  const int x1 = std::min(frame_size.width,
                          (r.br().x + align_x - 1) / align_x * align_x),
            y1 = std::min(frame_size.height,
                          (r.br().y + align_y - 1) / align_y * align_y);
  return {x0, y0, x1 - x0, y1 - y0};
}

}  // namespace

cv::Mat VideoReader::ConvertRegion(const cv::Rect& aligned,
                                   const cv::Size& dst_size) {
  State& s = *state_;
  const AVPixFmtDescriptor& desc = *PlanarYuv(*s.frame);
  // Point each plane at the region's corner.
  const uint8_t* data[4] = {};
  for (int c = 0; c < desc.nb_components; ++c) {
    const AVComponentDescriptor& comp = desc.comp[c];
    const bool chroma = c == 1 || c == 2;
    const int px = chroma ? aligned.x >> desc.log2_chroma_w : aligned.x;
    const int py = chroma ? aligned.y >> desc.log2_chroma_h : aligned.y;
    data[comp.plane] =
        s.frame->data[comp.plane] +
        static_cast<ptrdiff_t>(py) * s.frame->linesize[comp.plane] +
        static_cast<ptrdiff_t>(px) * comp.step;
  }
  return s.ConvertBgr(dst_size.empty() ? &s.region_sws : &s.reduced_sws, data,
                      s.frame->linesize, aligned.width, aligned.height,
                      dst_size);
}

bool VideoReader::RegionsConvertInPlace() const {
  return PlanarYuv(*state_->frame) != nullptr;
}

cv::Rect VideoReader::StoredRect(const cv::Rect& display) const {
  // The decoded frame is turned clockwise by the rotation for display.
  const int w = state_->frame->width, h = state_->frame->height;
  const int x0 = display.x, y0 = display.y, x1 = display.br().x,
            y1 = display.br().y;
  switch (state_->info.rotation_deg) {
    case 90:
      return {y0, h - x1, y1 - y0, x1 - x0};
    case 180:
      return {w - x1, h - y1, x1 - x0, y1 - y0};
    case 270:
      return {w - y1, x0, y1 - y0, x1 - x0};
    default:
      return display;
  }
}

cv::Mat VideoReader::BgrRegion(const cv::Rect& region) {
  State& s = *state_;
  const cv::Rect clipped =
      region & cv::Rect(0, 0, s.info.width_px, s.info.height_px);
  if (clipped.empty() || s.last_good_index < 0) return {};
  if (!RegionsConvertInPlace()) {
    // Rare path (formats without planes to point into): convert it all.
    cv::Mat full;
    s.Rotate(s.ConvertBgr(&s.sws, s.frame->data, s.frame->linesize,
                          s.frame->width, s.frame->height),
             &full);
    return full(clipped).clone();
  }
  // The region as decoded (before the display rotation), grown to whole
  // chroma samples, converted, cut to the request and turned upright.
  const cv::Rect stored = StoredRect(clipped);
  const cv::Rect aligned = ChromaAligned(stored, *PlanarYuv(*s.frame),
                                         {s.frame->width, s.frame->height});
  cv::Mat upright;
  s.Rotate(ConvertRegion(aligned, {})(stored - aligned.tl()), &upright);
  return upright.clone();
}

cv::Mat VideoReader::BgrRegionReduced(const cv::Rect& region,
                                      const cv::Size& size) {
  State& s = *state_;
  const cv::Rect clipped =
      region & cv::Rect(0, 0, s.info.width_px, s.info.height_px);
  if (clipped.empty() || size.empty() || s.last_good_index < 0) return {};
  if (RegionsConvertInPlace()) {
    const cv::Rect stored = StoredRect(clipped);
    if (ChromaAligned(stored, *PlanarYuv(*s.frame),
                      {s.frame->width, s.frame->height}) == stored) {
      // Straight from the planes, reduced, then turned upright.
      const bool quarter_turn =
          s.info.rotation_deg == 90 || s.info.rotation_deg == 270;
      cv::Mat upright;
      s.Rotate(
          ConvertRegion(
              stored, quarter_turn ? cv::Size(size.height, size.width) : size),
          &upright);
      return upright;
    }
  }
  cv::Mat reduced;
  cv::resize(BgrRegion(clipped), reduced, size, 0, 0, cv::INTER_AREA);
  return reduced;
}

}  // namespace softbench
