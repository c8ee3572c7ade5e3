#include "vision/video_reader.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

extern "C" {
#include <libavcodec/avcodec.h>
#include <libavformat/avformat.h>
#include <libavutil/display.h>
#include <libavutil/imgutils.h>
#include <libavutil/pixdesc.h>
#include <libswscale/swscale.h>
}

#include "util/input_error.h"
#include "vision/ffmpeg_util.h"

namespace softbench {

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
  int64_t frames_returned = 0;   // since open or the last seek
  int64_t last_good_index = -1;  // for truncation messages
  double last_good_time = 0.0;
  int64_t last_good_pts = AV_NOPTS_VALUE;
  // While seeking: packets presented before this are decoded only when
  // other frames refer to them (non-reference frames are skipped, exactly).
  int64_t discard_before_pts = INT64_MIN;
  bool flushing = false;
  bool finished = false;

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
    last_good_index = std::llround(last_good_time * info.fps);
    ++frames_returned;
    return true;
  }

  void Convert(VideoFrame* out) {
    out->time_s = last_good_time;
    out->index = last_good_index;
    const int w = frame->width, h = frame->height;
    if (options.want_luma) {
      const cv::Mat plane(h, w, CV_8UC1, frame->data[0], frame->linesize[0]);
      if (info.rotation_deg == 0) {
        out->luma = plane;  // a view: no copy on the hot path
      } else {
        Rotate(plane, &out->luma);
      }
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
    *context = sws_getCachedContext(
        *context, w, h, static_cast<AVPixelFormat>(frame->format),
        dst_size.width, dst_size.height, AV_PIX_FMT_BGR24,
        reduce ? SWS_AREA : SWS_BILINEAR, nullptr, nullptr, nullptr);
    SetColorspace(*context, frame->colorspace, frame->color_range);
    // swscale's vector code writes whole 16-pixel blocks: rows padded to
    // them (and aligned), then cut to the width.
    cv::Mat padded(dst_size.height, (dst_size.width + 15) / 16 * 16, CV_8UC3);
    uint8_t* dst[] = {padded.data};
    const int dst_stride[] = {static_cast<int>(padded.step)};
    sws_scale(*context, data, linesize, 0, h, dst, dst_stride);
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
  int err = avformat_open_input(&s.format, path.c_str(), nullptr, nullptr);
  if (err < 0) {
    s.Fail("cannot open the video (" + FfmpegError(err) +
           "); check the path, or re-copy the file if it is truncated");
  }
  err = avformat_find_stream_info(s.format, nullptr);
  if (err < 0)
    s.Fail("cannot read stream information (" + FfmpegError(err) + ")");
  s.stream =
      av_find_best_stream(s.format, AVMEDIA_TYPE_VIDEO, -1, -1, nullptr, 0);
  if (s.stream < 0) s.Fail("no video stream in the file");
  AVStream* stream = s.format->streams[s.stream];
  const AVCodec* decoder = avcodec_find_decoder(stream->codecpar->codec_id);
  if (decoder == nullptr) {
    s.Fail(std::string("no decoder for codec '") +
           avcodec_get_name(stream->codecpar->codec_id) + "'");
  }
  s.codec = avcodec_alloc_context3(decoder);
  avcodec_parameters_to_context(s.codec, stream->codecpar);
  s.codec->thread_count = options.threads;
  s.codec->thread_type = FF_THREAD_FRAME | FF_THREAD_SLICE;
  err = avcodec_open2(s.codec, decoder, nullptr);
  if (err < 0) s.Fail("cannot open the decoder (" + FfmpegError(err) + ")");
  s.packet = av_packet_alloc();
  s.frame = av_frame_alloc();
  s.time_base = stream->time_base;
  s.start_pts = stream->start_time != AV_NOPTS_VALUE ? stream->start_time : 0;

  VideoInfo& info = s.info;
  info.codec = avcodec_get_name(stream->codecpar->codec_id);
  const AVRational rate = stream->avg_frame_rate.num > 0
                              ? stream->avg_frame_rate
                              : stream->r_frame_rate;
  info.fps = av_q2d(rate);
  if (!(info.fps > 0.0)) s.Fail("the video has no frame rate");
  info.frame_count = stream->nb_frames;
  info.duration_s = stream->duration != AV_NOPTS_VALUE
                        ? stream->duration * av_q2d(stream->time_base)
                        : info.frame_count / info.fps;
  if (info.frame_count <= 0) {
    info.frame_count = std::llround(info.duration_s * info.fps);
  }
  if (const uint8_t* matrix =
          av_stream_get_side_data(stream, AV_PKT_DATA_DISPLAYMATRIX, nullptr)) {
    // Counter-clockwise degrees in the matrix; frames turn the other way.
    const double ccw =
        av_display_rotation_get(reinterpret_cast<const int32_t*>(matrix));
    if (std::isfinite(ccw)) {
      info.rotation_deg =
          ((-static_cast<int>(std::lround(ccw)) % 360) + 360) % 360;
    }
  }
  const bool quarter_turn = info.rotation_deg == 90 || info.rotation_deg == 270;
  info.width_px =
      quarter_turn ? stream->codecpar->height : stream->codecpar->width;
  info.height_px =
      quarter_turn ? stream->codecpar->width : stream->codecpar->height;
}

VideoReader::~VideoReader() = default;

const VideoInfo& VideoReader::info() const { return state_->info; }
const std::string& VideoReader::path() const { return state_->path; }

bool VideoReader::Read(VideoFrame* frame) {
  if (!state_->Next()) return false;
  state_->Convert(frame);
  return true;
}

bool VideoReader::Skip() { return state_->Next(); }

VideoFrame VideoReader::SeekTo(double time_s) {
  State& s = *state_;
  const double half_frame = 0.5 / s.info.fps;
  if (!(time_s >= -half_frame) || time_s > s.info.duration_s - half_frame) {
    s.Fail(
        fmt::format("cannot seek to t = {:.3f} s: the video runs from 0 to "
                    "{:.3f} s",
                    time_s, s.info.duration_s));
  }
  const int64_t target =
      s.start_pts +
      static_cast<int64_t>(std::floor(time_s / av_q2d(s.time_base)));
  // Decode forward without seeking when no key frame lies between the frame
  // on screen and the target: a seek would start from the same key frame.
  AVStream* stream = s.format->streams[s.stream];
  const int key =
      av_index_search_timestamp(stream, target, AVSEEK_FLAG_BACKWARD);
  const AVIndexEntry* key_entry =
      key >= 0 ? avformat_index_get_entry(stream, key) : nullptr;
  const bool forward = !s.finished && s.last_good_pts != AV_NOPTS_VALUE &&
                       s.last_good_time < time_s - half_frame &&
                       key_entry != nullptr &&
                       key_entry->timestamp <= s.last_good_pts;
  if (!forward) {
    const int err =
        av_seek_frame(s.format, s.stream, target, AVSEEK_FLAG_BACKWARD);
    if (err < 0) {
      s.Fail(fmt::format("seek to t = {:.3f} s failed ({})", time_s,
                         FfmpegError(err)));
    }
    avcodec_flush_buffers(s.codec);
    s.flushing = s.finished = false;
  }
  // Decode up to the frame on screen at `time_s`, skipping the frames no
  // other frame refers to.
  s.discard_before_pts =
      s.start_pts + static_cast<int64_t>(std::floor((time_s - half_frame) /
                                                    av_q2d(s.time_base)));
  for (;;) {
    if (!s.Next()) {
      s.discard_before_pts = INT64_MIN;
      s.Fail(fmt::format("seek to t = {:.3f} s ran past the end", time_s));
    }
    if (s.last_good_time >= time_s - half_frame) break;
  }
  s.discard_before_pts = INT64_MIN;
  if (std::abs(s.last_good_time - time_s) > half_frame) {
    s.Fail(fmt::format("seek to t = {:.3f} s landed on t = {:.3f} s", time_s,
                       s.last_good_time));
  }
  VideoFrame frame;
  s.Convert(&frame);
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
  return state_->info.rotation_deg == 0 && PlanarYuv(*state_->frame);
}

cv::Mat VideoReader::BgrRegion(const cv::Rect& region) {
  State& s = *state_;
  const cv::Rect clipped =
      region & cv::Rect(0, 0, s.info.width_px, s.info.height_px);
  if (clipped.empty() || s.last_good_index < 0) return {};
  if (!RegionsConvertInPlace()) {
    // Rare path (phone portrait video, packed formats): convert it all.
    cv::Mat full;
    s.Rotate(s.ConvertBgr(&s.sws, s.frame->data, s.frame->linesize,
                          s.frame->width, s.frame->height),
             &full);
    return full(clipped).clone();
  }
  // Grow the region to whole chroma samples, convert, and cut the request
  // out of it.
  const cv::Rect aligned = ChromaAligned(clipped, *PlanarYuv(*s.frame),
                                         {s.frame->width, s.frame->height});
  return ConvertRegion(aligned, {})(clipped - aligned.tl()).clone();
}

cv::Mat VideoReader::BgrRegionReduced(const cv::Rect& region,
                                      const cv::Size& size) {
  State& s = *state_;
  const cv::Rect clipped =
      region & cv::Rect(0, 0, s.info.width_px, s.info.height_px);
  if (clipped.empty() || size.empty() || s.last_good_index < 0) return {};
  if (RegionsConvertInPlace() &&
      ChromaAligned(clipped, *PlanarYuv(*s.frame),
                    {s.frame->width, s.frame->height}) == clipped) {
    return ConvertRegion(clipped, size);  // straight from the planes
  }
  cv::Mat reduced;
  cv::resize(BgrRegion(clipped), reduced, size, 0, 0, cv::INTER_AREA);
  return reduced;
}

}  // namespace softbench
