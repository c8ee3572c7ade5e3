#include "vision/video_writer.h"

#include <algorithm>
#include <cmath>

extern "C" {
#include <libavcodec/avcodec.h>
#include <libavformat/avformat.h>
#include <libavutil/display.h>
#include <libavutil/opt.h>
#include <libavutil/pixdesc.h>
#include <libswscale/swscale.h>
}

#include "util/check.h"
#include "util/input_error.h"
#include "util/join_names.h"
#include "vision/ffmpeg_util.h"
#include "vision/video_codecs.h"

namespace softbench {

std::optional<std::string> VideoWriterOptions::Problem() const {
  const VideoCodec* table_codec = FindVideoCodec(codec);
  if (table_codec == nullptr) {
    return "codec must be " + VideoCodecNames();
  }
  if (!(fps >= 1.0) || fps > 1000.0) return "fps must be in [1, 1000]";
  if (crf < 0 || crf > 51) return "crf must be between 0 and 51";
  if (!(bitrate_mbps >= 0.0 && bitrate_mbps <= 1000.0)) {
    return "bitrate must be 0 (use the CRF) or up to 1000 Mb/s";
  }
  // x264's and x265's presets: checked here, since an unknown one makes the
  // encoder print its own complaint to the terminal before failing.
  static constexpr std::string_view kPresets[] = {
      "ultrafast", "superfast", "veryfast", "faster",   "fast",
      "medium",    "slow",      "slower",   "veryslow", "placebo"};
  if (std::find(std::begin(kPresets), std::end(kPresets), preset) ==
      std::end(kPresets)) {
    return "preset '" + preset +
           "' is not one of ultrafast, superfast, veryfast, faster, fast, "
           "medium, slow, slower, veryslow, placebo";
  }
  if (threads < 1) return "threads must be >= 1";
  if (!(keyframe_interval_s > 0.0 && keyframe_interval_s <= 3600.0)) {
    return "keyframe interval must be > 0 s and at most an hour";
  }
  if (rotation_deg % 90 != 0) return "rotation must be a multiple of 90";
  if (bit_depth != 8 && bit_depth != 10 && bit_depth != 12) {
    return "bit depth must be 8, 10 or 12";
  }
  if (!table_codec->Encodes(bit_depth)) {
    std::vector<std::string_view> codecs;
    for (const VideoCodec& c : VideoCodecs()) {
      if (c.Encodes(bit_depth)) codecs.push_back(c.name);
    }
    return std::to_string(bit_depth) + " bits need " + JoinNames(codecs);
  }
  if (chroma != "4:2:0" && chroma != "4:2:2" && chroma != "4:4:4") {
    return "chroma must be 4:2:0, 4:2:2 or 4:4:4";
  }
  if (!table_codec->Takes(chroma)) {
    return codec + " does not take chroma " + chroma;
  }
  if (time_base_hz < 0) return "time base must be >= 0";
  return std::nullopt;
}

namespace {

AVPixelFormat PixelFormat(const VideoWriterOptions& o) {
  const std::string name =
      std::string(o.chroma == "4:4:4"   ? "yuv444p"
                  : o.chroma == "4:2:2" ? "yuv422p"
                                        : "yuv420p") +
      (o.bit_depth == 8 ? "" : std::to_string(o.bit_depth) + "le");
  return av_get_pix_fmt(name.c_str());
}

}  // namespace

struct VideoWriter::State {
  std::string path;
  VideoWriterOptions options;
  AVFormatContext* format = nullptr;
  AVCodecContext* codec = nullptr;
  AVStream* stream = nullptr;
  AVFrame* frame = nullptr;
  AVPacket* packet = nullptr;
  SwsContext* sws = nullptr;  // for the last input type
  int sws_input_type = -1;
  int64_t next_pts = 0;
  int64_t frame_ticks = 1;  // ticks of the time base per nominal frame
  bool open = false;

  [[noreturn]] void Fail(const std::string& what, int error) const {
    throw InputError(path + ": " + what + " (" + FfmpegError(error) + ")");
  }

  // Sends `input` (nullptr flushes) and writes every packet that comes out.
  void Encode(const AVFrame* input) {
    int err = avcodec_send_frame(codec, input);
    if (err < 0) Fail("encoding failed", err);
    for (;;) {
      err = avcodec_receive_packet(codec, packet);
      if (err == AVERROR(EAGAIN) || err == AVERROR_EOF) return;
      if (err < 0) Fail("encoding failed", err);
      // Each packet lasts one nominal frame, so the container's duration
      // counts the last frame too.
      if (packet->duration == 0) packet->duration = frame_ticks;
      av_packet_rescale_ts(packet, codec->time_base, stream->time_base);
      packet->stream_index = stream->index;
      err = av_interleaved_write_frame(format, packet);
      if (err < 0) Fail("writing failed", err);
    }
  }

  // The encoder's input from SDR BT.709 BGR: straight for 8-bit SDR, else
  // through 16 bits (and the HDR transfer).
  void ToFrame(const cv::Mat& bgr) {
    const bool direct = bgr.type() == CV_8UC3 &&
                        options.encoding.IsSdrBt709() && options.bit_depth == 8;
    cv::Mat input = bgr;
    if (!options.encoding.IsSdrBt709()) {
      input = ConvertFromSdr(bgr, options.encoding);
    } else if (!direct && bgr.depth() == CV_8U) {
      bgr.convertTo(input, CV_16U, 257.0);
    }
    if (sws_input_type != input.type()) {
      sws_freeContext(sws);
      sws = sws_getContext(
          input.cols, input.rows,
          input.depth() == CV_8U ? AV_PIX_FMT_BGR24 : AV_PIX_FMT_BGR48LE,
          input.cols, input.rows, codec->pix_fmt,
          SWS_BILINEAR | SWS_ACCURATE_RND, nullptr, nullptr, nullptr);
      SetRgbToYuv(sws, codec->colorspace, codec->color_range);
      sws_input_type = input.type();
    }
    const uint8_t* src[] = {input.data};
    const int src_stride[] = {static_cast<int>(input.step)};
    sws_scale(sws, src, src_stride, 0, input.rows, frame->data,
              frame->linesize);
  }

  // The colours' description (primaries, matrix, transfer, range) as the
  // stream and the container state it.
  void SetColorDescription() {
    const bool bt2020 = options.encoding.primaries == Primaries::kBt2020;
    codec->color_primaries = bt2020 ? AVCOL_PRI_BT2020 : AVCOL_PRI_BT709;
    codec->colorspace = bt2020 ? AVCOL_SPC_BT2020_NCL : AVCOL_SPC_BT709;
    switch (options.encoding.transfer) {
      case Transfer::kHlg:
        codec->color_trc = AVCOL_TRC_ARIB_STD_B67;
        break;
      case Transfer::kPq:
        codec->color_trc = AVCOL_TRC_SMPTE2084;
        break;
      case Transfer::kSdr:
        codec->color_trc = bt2020
                               ? (options.bit_depth > 10 ? AVCOL_TRC_BT2020_12
                                                         : AVCOL_TRC_BT2020_10)
                               : AVCOL_TRC_BT709;
        break;
    }
    codec->color_range =
        options.full_range ? AVCOL_RANGE_JPEG : AVCOL_RANGE_MPEG;
  }

  // Quality (CRF or bit rate with a phone's VBV buffer), the codec's quiet
  // parameters and its container tag (VideoCodecs()).
  void SetRateControl(const VideoCodec& table_codec) {
    av_opt_set(codec->priv_data, "preset", options.preset.c_str(), 0);
    if (options.bitrate_mbps > 0.0) {
      codec->bit_rate = static_cast<int64_t>(options.bitrate_mbps * 1e6);
      codec->rc_max_rate = codec->bit_rate * 3 / 2;
      codec->rc_buffer_size = static_cast<int>(codec->bit_rate);
    } else {
      av_opt_set(codec->priv_data, "crf", std::to_string(options.crf).c_str(),
                 0);
    }
    if (!table_codec.params_option.empty()) {
      std::string params(table_codec.params);
      const size_t at = params.find("{threads}");
      if (at != std::string::npos) {
        params.replace(at, 9, std::to_string(options.threads));
      }
      av_opt_set(codec->priv_data,
                 std::string(table_codec.params_option).c_str(), params.c_str(),
                 0);
    }
    if (table_codec.container_tag.size() == 4) {
      const std::string_view t = table_codec.container_tag;
      codec->codec_tag = MKTAG(t[0], t[1], t[2], t[3]);
    }
  }

  // The stream (with a phone's rotation matrix), the file and the header,
  // colr atom and moov first.
  void WriteHeader() {
    stream = avformat_new_stream(format, nullptr);
    avcodec_parameters_from_context(stream->codecpar, codec);
    stream->time_base = codec->time_base;
    if (options.rotation_deg % 360 != 0) {
      auto* matrix = reinterpret_cast<int32_t*>(av_stream_new_side_data(
          stream, AV_PKT_DATA_DISPLAYMATRIX, 9 * sizeof(int32_t)));
      // As phones write it: av_display_rotation_get() of this matrix is minus
      // the clockwise rotation a player applies (ffmpeg's autorotate).
      av_display_rotation_set(matrix, options.rotation_deg);
    }
    int err = avio_open(&format->pb, path.c_str(), AVIO_FLAG_WRITE);
    if (err < 0) Fail("cannot create the file", err);
    AVDictionary* muxer_options = nullptr;
    // The colour description goes into the container too (the colr atom), as
    // phones write it.
    av_dict_set(&muxer_options, "movflags", "+faststart+write_colr", 0);
    err = avformat_write_header(format, &muxer_options);
    av_dict_free(&muxer_options);
    if (err < 0) Fail("cannot write the header", err);
  }

  void AllocateFrame(int width_px, int height_px) {
    frame = av_frame_alloc();
    frame->format = codec->pix_fmt;
    frame->width = width_px;
    frame->height = height_px;
    frame->color_range = codec->color_range;
    frame->color_primaries = codec->color_primaries;
    frame->color_trc = codec->color_trc;
    frame->colorspace = codec->colorspace;
    const int err = av_frame_get_buffer(frame, 0);
    if (err < 0) Fail("out of memory", err);
    packet = av_packet_alloc();
  }

  ~State() {
    sws_freeContext(sws);
    av_frame_free(&frame);
    av_packet_free(&packet);
    avcodec_free_context(&codec);
    if (format != nullptr) {
      if (format->pb != nullptr) avio_closep(&format->pb);
      avformat_free_context(format);
    }
  }
};

VideoWriter::VideoWriter(const std::string& path, int width_px, int height_px,
                         const VideoWriterOptions& options)
    : state_(std::make_unique<State>()) {
  SOFTBENCH_CHECK(!options.Problem()) << *options.Problem();
  State& s = *state_;
  s.path = path;
  s.options = options;
  av_log_set_level(AV_LOG_QUIET);
  // The container follows the extension (.mov: QuickTime, as phones write);
  // MP4 otherwise.
  const bool mov =
      path.size() >= 4 && path.compare(path.size() - 4, 4, ".mov") == 0;
  int err = avformat_alloc_output_context2(&s.format, nullptr,
                                           mov ? "mov" : "mp4", path.c_str());
  if (err < 0) s.Fail("cannot create the container", err);
  // No creation time or library version strings: reproducible files.
  s.format->flags |= AVFMT_FLAG_BITEXACT;
  const VideoCodec& table_codec = *FindVideoCodec(options.codec);
  const std::string encoder_name(table_codec.encoder);
  const AVCodec* encoder = avcodec_find_encoder_by_name(encoder_name.c_str());
  if (encoder == nullptr) {
    throw InputError(path + ": FFmpeg has no " + encoder_name +
                     " encoder; install Debian's ffmpeg libraries");
  }
  s.codec = avcodec_alloc_context3(encoder);
  s.codec->width = width_px;
  s.codec->height = height_px;
  s.codec->pix_fmt = PixelFormat(options);
  if (options.time_base_hz > 0) {
    s.codec->time_base = {1, options.time_base_hz};
    s.frame_ticks =
        std::max<int64_t>(1, std::llround(options.time_base_hz / options.fps));
  } else {
    s.codec->time_base = av_d2q(1.0 / options.fps, 1 << 20);
  }
  s.codec->framerate = av_d2q(options.fps, 1 << 20);
  s.codec->gop_size = std::max(
      1,
      static_cast<int>(std::lround(options.fps * options.keyframe_interval_s)));
  s.codec->thread_count = options.threads;
  s.SetColorDescription();
  s.codec->flags |= AV_CODEC_FLAG_BITEXACT;
  if (s.format->oformat->flags & AVFMT_GLOBALHEADER) {
    s.codec->flags |= AV_CODEC_FLAG_GLOBAL_HEADER;
  }
  s.SetRateControl(table_codec);
  err = avcodec_open2(s.codec, encoder, nullptr);
  if (err < 0) s.Fail("cannot open " + encoder_name, err);

  s.WriteHeader();

  s.AllocateFrame(width_px, height_px);
  s.open = true;
}

VideoWriter::~VideoWriter() {
  try {
    Close();
  } catch (const InputError&) {
    // Destructors must not throw; Close() reports errors when called.
  }
}

void VideoWriter::Write(const cv::Mat& bgr, double time_s) {
  State& s = *state_;
  SOFTBENCH_CHECK(s.open && (bgr.type() == CV_8UC3 || bgr.type() == CV_16UC3) &&
                  bgr.cols == s.codec->width && bgr.rows == s.codec->height)
      << "Write takes open-writer frames of the video's size, 8 or 16 bit";
  const int err = av_frame_make_writable(s.frame);
  if (err < 0) s.Fail("out of memory", err);
  s.ToFrame(bgr);
  int64_t pts = s.next_pts;
  if (time_s >= 0.0) {
    SOFTBENCH_CHECK(s.options.time_base_hz > 0) << "frame times need a clock";
    pts = std::llround(time_s * s.options.time_base_hz);
    SOFTBENCH_CHECK(pts >= s.next_pts) << "frame times must increase";
  }
  s.frame->pts = pts;
  s.next_pts = pts + (time_s >= 0.0 ? 1 : s.frame_ticks);
  s.Encode(s.frame);
}

void VideoWriter::Close() {
  State& s = *state_;
  if (!s.open) return;
  s.open = false;
  s.Encode(nullptr);
  const int err = av_write_trailer(s.format);
  if (err < 0) s.Fail("cannot finish the file", err);
}

}  // namespace softbench
