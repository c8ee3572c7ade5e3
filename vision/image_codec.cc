#include "vision/image_codec.h"

#include <fmt/format.h>

#include <cstdlib>
#include <cstring>
#include <fstream>
#include <functional>
#include <memory>
#include <opencv2/imgproc.hpp>

extern "C" {
#include <libavcodec/avcodec.h>
#include <libavformat/avformat.h>
#include <libavutil/pixdesc.h>
#include <libswscale/swscale.h>
}

#include "util/check.h"
#include "vision/ffmpeg_util.h"

namespace softbench {
namespace {

// Beyond any camera's photo (268 megapixels): refused before it is decoded.
constexpr int64_t kMaxPixels = int64_t{1} << 28;

struct FfmpegDeleter {
  void operator()(AVFormatContext* c) const { avformat_close_input(&c); }
  void operator()(AVCodecContext* c) const { avcodec_free_context(&c); }
  void operator()(AVFrame* f) const { av_frame_free(&f); }
  void operator()(AVPacket* p) const { av_packet_free(&p); }
  void operator()(SwsContext* s) const { sws_freeContext(s); }
};
template <typename T>
using FfmpegPtr = std::unique_ptr<T, FfmpegDeleter>;

// Neither RGB nor a palette: YUV with colour, or gray (one or two
// components, with alpha).
bool IsLumaChroma(const AVPixFmtDescriptor& desc) {
  return (desc.flags & (AV_PIX_FMT_FLAG_RGB | AV_PIX_FMT_FLAG_PAL)) == 0;
}

// `frame` converted by swscale to `to` (BGR24 or GRAY8). swscale's vector
// code writes whole 16-pixel blocks: rows padded to them, then cut.
cv::Mat Convert(const AVFrame& frame, AVPixelFormat to) {
  const AVPixFmtDescriptor* desc =
      av_pix_fmt_desc_get(static_cast<AVPixelFormat>(frame.format));
  const FfmpegPtr<SwsContext> sws(sws_getContext(
      frame.width, frame.height, static_cast<AVPixelFormat>(frame.format),
      frame.width, frame.height, to,
      SWS_BILINEAR | SWS_FULL_CHR_H_INT | SWS_ACCURATE_RND, nullptr, nullptr,
      nullptr));
  SOFTBENCH_CHECK(sws != nullptr) << "swscale refused " << desc->name;
  if (IsLumaChroma(*desc) && desc->nb_components >= 3)
    SetYuvToRgb(sws.get(), frame.colorspace, frame.color_range);
  const bool bgr = to == AV_PIX_FMT_BGR24;
  cv::Mat padded(frame.height, (frame.width + 15) / 16 * 16,
                 bgr ? CV_8UC3 : CV_8UC1);
  uint8_t* dst[] = {padded.data};
  const int dst_stride[] = {static_cast<int>(padded.step)};
  sws_scale(sws.get(), frame.data, frame.linesize, 0, frame.height, dst,
            dst_stride);
  return padded.colRange(0, frame.width).clone();
}

// The frame as 8-bit `color`: gray sources (one channel, with or without
// alpha) through gray, so their levels are not taken for video range.
cv::Mat ToColor(const AVFrame& frame, ImageColor color) {
  const AVPixFmtDescriptor* desc =
      av_pix_fmt_desc_get(static_cast<AVPixelFormat>(frame.format));
  if (IsLumaChroma(*desc) && desc->nb_components <= 2) {
    cv::Mat gray = Convert(frame, AV_PIX_FMT_GRAY8);
    if (color == ImageColor::kBgr) cv::cvtColor(gray, gray, cv::COLOR_GRAY2BGR);
    return gray;
  }
  cv::Mat image = Convert(frame, AV_PIX_FMT_BGR24);
  // The picture's own colours to gray, weighed as OpenCV's imread does.
  if (color == ImageColor::kGray)
    cv::cvtColor(image, image, cv::COLOR_BGR2GRAY);
  return image;
}

// EXIF's orientation (1-8, the frame's "Orientation" tag, which FFmpeg's
// JPEG decoder exports) undone, as OpenCV's imread undoes it.
cv::Mat Upright(const AVFrame& frame, cv::Mat image) {
  const AVDictionaryEntry* tag =
      av_dict_get(frame.metadata, "Orientation", nullptr, 0);
  const int orientation = tag != nullptr ? std::atoi(tag->value) : 1;
  if (orientation >= 5 && orientation <= 8) cv::transpose(image, image);
  switch (orientation) {
    case 2:
    case 6:
      cv::flip(image, image, 1);
      break;
    case 3:
    case 7:
      cv::flip(image, image, -1);
      break;
    case 4:
    case 8:
      cv::flip(image, image, 0);
      break;
    default:
      break;
  }
  return image;
}

// The file's kind by its first bytes (a PNG's or a JPEG's signature), not
// by its name; nullptr for anything else.
const AVInputFormat* ImageFormat(const std::string& path) {
  std::ifstream file(path, std::ios::binary);
  char head[8] = {};
  file.read(head, sizeof(head));
  if (std::memcmp(head, "\x89PNG\r\n\x1a\n", 8) == 0) {
    return av_find_input_format("png_pipe");
  }
  if (std::memcmp(head, "\xFF\xD8\xFF", 3) == 0) {
    return av_find_input_format("jpeg_pipe");
  }
  return nullptr;
}

// The file's picture; a why_not otherwise.
ImageRead Decode(const std::string& path, ImageColor color) {
  const AVInputFormat* kind = ImageFormat(path);
  if (kind == nullptr) return {{}, "not a PNG or JPEG image"};
  AVFormatContext* raw_format = nullptr;
  if (avformat_open_input(&raw_format, path.c_str(), kind, nullptr) < 0) {
    return {{}, "cannot be opened as an image"};
  }
  const FfmpegPtr<AVFormatContext> format(raw_format);
  if (avformat_find_stream_info(format.get(), nullptr) < 0) {
    return {{}, "not a PNG or JPEG image"};
  }
  const int stream =
      av_find_best_stream(format.get(), AVMEDIA_TYPE_VIDEO, -1, -1, nullptr, 0);
  if (stream < 0) return {{}, "not a PNG or JPEG image"};
  const AVCodecParameters& par = *format->streams[stream]->codecpar;
  if (static_cast<int64_t>(par.width) * par.height > kMaxPixels) {
    return {{},
            fmt::format("declares a {}x{} picture, larger than any camera's",
                        par.width, par.height)};
  }
  const AVCodec* codec = avcodec_find_decoder(par.codec_id);
  const FfmpegPtr<AVCodecContext> decoder(avcodec_alloc_context3(codec));
  SOFTBENCH_CHECK(codec != nullptr && decoder != nullptr)
      << "FFmpeg has no PNG or JPEG decoder";
  decoder->thread_count = 1;
  if (avcodec_parameters_to_context(decoder.get(), &par) < 0 ||
      avcodec_open2(decoder.get(), codec, nullptr) < 0) {
    return {{}, "the image's header is damaged"};
  }
  const FfmpegPtr<AVPacket> packet(av_packet_alloc());
  const FfmpegPtr<AVFrame> frame(av_frame_alloc());
  int received = AVERROR(EAGAIN);
  while (received == AVERROR(EAGAIN) &&
         av_read_frame(format.get(), packet.get()) >= 0) {
    if (packet->stream_index == stream) {
      avcodec_send_packet(decoder.get(), packet.get());
      received = avcodec_receive_frame(decoder.get(), frame.get());
    }
    av_packet_unref(packet.get());
  }
  if (received == AVERROR(EAGAIN)) {
    avcodec_send_packet(decoder.get(), nullptr);
    received = avcodec_receive_frame(decoder.get(), frame.get());
  }
  if (received < 0 || frame->width <= 0 || frame->height <= 0) {
    return {{}, "the image's data is damaged (" + FfmpegError(received) + ")"};
  }
  // A JPEG's YUV is full-range BT.601 whatever its header says.
  if (par.codec_id == AV_CODEC_ID_MJPEG) {
    frame->colorspace = AVCOL_SPC_BT470BG;
    frame->color_range = AVCOL_RANGE_JPEG;
  }
  return {Upright(*frame, ToColor(*frame, color)), ""};
}

// `frame` encoded by `codec_id`'s encoder, its options set by `setup`.
std::vector<uint8_t> Encode(AVCodecID codec_id, const AVFrame& frame,
                            const std::function<void(AVCodecContext*)>& setup) {
  const AVCodec* codec = avcodec_find_encoder(codec_id);
  SOFTBENCH_CHECK(codec != nullptr) << "FFmpeg has no encoder " << codec_id;
  const FfmpegPtr<AVCodecContext> encoder(avcodec_alloc_context3(codec));
  encoder->width = frame.width;
  encoder->height = frame.height;
  encoder->pix_fmt = static_cast<AVPixelFormat>(frame.format);
  encoder->time_base = {1, 1};
  encoder->thread_count = 1;
  setup(encoder.get());
  const int opened = avcodec_open2(encoder.get(), codec, nullptr);
  SOFTBENCH_CHECK(opened >= 0)
      << "the image encoder would not open: " << FfmpegError(opened);
  SOFTBENCH_CHECK(avcodec_send_frame(encoder.get(), &frame) >= 0 &&
                  avcodec_send_frame(encoder.get(), nullptr) >= 0)
      << "the image encoder refused the picture";
  std::vector<uint8_t> bytes;
  const FfmpegPtr<AVPacket> packet(av_packet_alloc());
  while (avcodec_receive_packet(encoder.get(), packet.get()) >= 0) {
    bytes.insert(bytes.end(), packet->data, packet->data + packet->size);
    av_packet_unref(packet.get());
  }
  SOFTBENCH_CHECK(!bytes.empty()) << "the image encoder wrote nothing";
  return bytes;
}

// A frame of `format` and `image`'s size, its buffers FFmpeg's own.
FfmpegPtr<AVFrame> FrameFor(const cv::Mat& image, AVPixelFormat format) {
  FfmpegPtr<AVFrame> frame(av_frame_alloc());
  frame->width = image.cols;
  frame->height = image.rows;
  frame->format = format;
  SOFTBENCH_CHECK(av_frame_get_buffer(frame.get(), 0) >= 0)
      << "out of memory for a " << image.cols << "x" << image.rows
      << " picture";
  return frame;
}

}  // namespace

ImageRead ReadImageFile(const std::string& path, ImageColor color) {
  av_log_set_level(AV_LOG_QUIET);  // the why_not says what went wrong
  return Decode(path, color);
}

std::vector<uint8_t> EncodePng(const cv::Mat& image) {
  SOFTBENCH_CHECK(image.type() == CV_8UC3 || image.type() == CV_8UC1)
      << "EncodePng takes 8-bit BGR or gray";
  av_log_set_level(AV_LOG_QUIET);
  const bool bgr = image.channels() == 3;
  const FfmpegPtr<AVFrame> frame =
      FrameFor(image, bgr ? AV_PIX_FMT_RGB24 : AV_PIX_FMT_GRAY8);
  cv::Mat into(image.rows, image.cols, image.type(), frame->data[0],
               static_cast<size_t>(frame->linesize[0]));
  if (bgr) {
    cv::cvtColor(image, into, cv::COLOR_BGR2RGB);  // into the frame's rows
  } else {
    image.copyTo(into);
  }
  return Encode(AV_CODEC_ID_PNG, *frame, [](AVCodecContext*) {});
}

std::vector<uint8_t> EncodeJpeg(const cv::Mat& bgr, int qscale) {
  SOFTBENCH_CHECK(bgr.type() == CV_8UC3 && qscale >= 1 && qscale <= 31)
      << "EncodeJpeg takes 8-bit BGR and a qscale of 1-31";
  av_log_set_level(AV_LOG_QUIET);  // swscale's notes are no user's concern
  // Chroma averaged over each 2x2 block (SWS_AREA), as libjpeg does. At
  // an odd size the same picture's JPEG differed from run to run (samples
  // past its edge that nothing wrote reached it): the picture is converted
  // at an even size, its edge repeated, so every sample is written, and
  // the frame is then cut back to its own size.
  cv::Mat even;
  cv::copyMakeBorder(bgr, even, 0, bgr.rows % 2, 0, bgr.cols % 2,
                     cv::BORDER_REPLICATE);
  const FfmpegPtr<AVFrame> frame = FrameFor(even, AV_PIX_FMT_YUVJ420P);
  const FfmpegPtr<SwsContext> sws(
      sws_getContext(even.cols, even.rows, AV_PIX_FMT_BGR24, even.cols,
                     even.rows, AV_PIX_FMT_YUVJ420P,
                     SWS_AREA | SWS_ACCURATE_RND, nullptr, nullptr, nullptr));
  SOFTBENCH_CHECK(sws != nullptr) << "swscale refused BGR to YUV 4:2:0";
  SetRgbToYuv(sws.get(), AVCOL_SPC_BT470BG, AVCOL_RANGE_JPEG);
  const uint8_t* src[] = {even.data};
  const int src_stride[] = {static_cast<int>(even.step)};
  sws_scale(sws.get(), src, src_stride, 0, even.rows, frame->data,
            frame->linesize);
  frame->width = bgr.cols;
  frame->height = bgr.rows;
  frame->quality = FF_QP2LAMBDA * qscale;
  return Encode(AV_CODEC_ID_MJPEG, *frame, [&](AVCodecContext* encoder) {
    encoder->flags |= AV_CODEC_FLAG_QSCALE;
    encoder->global_quality = FF_QP2LAMBDA * qscale;
    encoder->qmin = 1;  // FFmpeg's floor is 2 unless lowered
    encoder->color_range = AVCOL_RANGE_JPEG;
    encoder->colorspace = AVCOL_SPC_BT470BG;
  });
}

}  // namespace softbench
