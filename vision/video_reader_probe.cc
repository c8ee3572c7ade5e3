// VideoReader's probe: the file opened, its stream described and its pixel
// format checked before any frame is measured; every frame's time.
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
#include "util/parallel_tasks.h"
#include "vision/ffmpeg_util.h"
#include "vision/video_reader_state.h"

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

void VideoReader::State::Open() {
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
  stream = av_find_best_stream(format, AVMEDIA_TYPE_VIDEO, -1, -1, nullptr, 0);
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
  codec->thread_count = options.threads > 0 ? options.threads : CoreCount();
  codec->thread_type = FF_THREAD_FRAME | FF_THREAD_SLICE;
  CountDecoderErrors();
  err = avcodec_open2(codec, decoder, nullptr);
  if (err < 0) Fail("cannot open the decoder (" + FfmpegError(err) + ")");
  packet = av_packet_alloc();
  frame = av_frame_alloc();
  time_base = st->time_base;
  start_pts = st->start_time != AV_NOPTS_VALUE ? st->start_time : 0;
}

void VideoReader::State::ReadStreamInfo() {
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
  const bool quarter_turn = info.rotation_deg == 90 || info.rotation_deg == 270;
  info.width_px = quarter_turn ? st->codecpar->height : st->codecpar->width;
  info.height_px = quarter_turn ? st->codecpar->width : st->codecpar->height;
}

void VideoReader::State::CheckPixelFormat() {
  AVStream* st = format->streams[stream];
  // The pixel format is checked here, so an unreadable video is refused by
  // name before any measurement starts.
  desc = av_pix_fmt_desc_get(static_cast<AVPixelFormat>(st->codecpar->format));
  if (desc == nullptr) {
    // FFmpeg decodes frames to learn the pixel format: none known means no
    // frame decoded, because the media data is missing or damaged.
    const bool has_data = av_read_frame(format, packet) >= 0;
    av_packet_unref(packet);
    Fail(has_data ? fmt::format("none of its first frames decodes (the video "
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
    info.luma_code_bits = desc->comp[0].depth + desc->comp[0].shift;
  }
  info.encoding = EncodingOf(*st->codecpar);
}

void VideoReader::State::ReadFrameTimes() {
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
                     intervals.begin() + intervals.size() / 2, intervals.end());
    info.frame_interval_s = intervals[intervals.size() / 2];
  }
}

void VideoReader::State::ScanFrameTimes() {
  std::vector<int64_t> key_pts;
  for (;;) {
    if (av_read_frame(format, packet) < 0) break;
    if (packet->stream_index == stream &&
        (packet->flags & AV_PKT_FLAG_DISCARD) == 0) {
      if (packet->pts == AV_NOPTS_VALUE) {
        frame_pts.clear();  // no timestamps: frames are k / fps
        key_pts.clear();
        av_packet_unref(packet);
        break;
      }
      frame_pts.push_back(packet->pts);
      if (packet->flags & AV_PKT_FLAG_KEY) key_pts.push_back(packet->pts);
    }
    av_packet_unref(packet);
  }
  std::sort(frame_pts.begin(), frame_pts.end());
  frame_pts.erase(std::unique(frame_pts.begin(), frame_pts.end()),
                  frame_pts.end());
  for (const int64_t pts : frame_pts) {
    info.frame_times_s.push_back((pts - start_pts) * av_q2d(time_base));
  }
  std::sort(key_pts.begin(), key_pts.end());
  for (const int64_t pts : key_pts) {
    info.key_frame_times_s.push_back((pts - start_pts) * av_q2d(time_base));
  }
  Rewind();
}

}  // namespace softbench
