#include "vision/video_reader.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <mutex>
#include <opencv2/core.hpp>
#include <opencv2/core/hal/intrin.hpp>
#include <opencv2/imgproc.hpp>
#include <optional>
#include <unordered_set>

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
#include "vision/video_reader_state.h"

namespace softbench {
namespace {

// The readers' counts of their decoders' errors: FFmpeg's log callback is
// global and a decoder's threads log through copies of the reader's codec
// context, which share its `opaque` (the reader's count), so a logged
// error is a reader's only when `opaque` is one of these.
std::mutex decoding_readers_mutex;
std::unordered_set<const void*> decoding_readers;

// With frame threads a decoder's error flags on the frame it concealed
// race with that frame's output and are sometimes missing (seen on a
// sample with 40 flipped bits: a damaged key frame flagged in 2 runs of
// 4), while its log of the error is not: every error-level message from a
// reader's decoder is counted on the reader.
void CountDecodeErrors(void* object, int level, const char* /*format*/,
                       va_list /*args*/) {
  if (level > AV_LOG_ERROR || object == nullptr) return;
  if (*static_cast<const AVClass* const*>(object) != avcodec_get_class()) {
    return;
  }
  void* count = static_cast<const AVCodecContext*>(object)->opaque;
  const std::lock_guard<std::mutex> lock(decoding_readers_mutex);
  if (decoding_readers.contains(count)) {
    ++*static_cast<std::atomic<int64_t>*>(count);
  }
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

VideoReader::State::~State() {
  for (auto& [key, context] : sws_contexts) sws_freeContext(context);
  av_frame_free(&frame);
  av_packet_free(&packet);
  avcodec_free_context(&codec);
  avformat_close_input(&format);
  const std::lock_guard<std::mutex> lock(decoding_readers_mutex);
  decoding_readers.erase(&decode_errors);
}

void VideoReader::State::CountDecoderErrors() {
  static std::once_flag installed;
  std::call_once(installed, [] { av_log_set_callback(CountDecodeErrors); });
  codec->opaque = &decode_errors;
  const std::lock_guard<std::mutex> lock(decoding_readers_mutex);
  decoding_readers.insert(&decode_errors);
}

void VideoReader::State::Fail(const std::string& what) const {
  throw InputError(path + ": " + what);
}

void VideoReader::State::FailBroken(const std::string& detail) const {
  const std::string where = last_good_index < 0
                                ? "before the first frame"
                                : fmt::format("after frame {} (t = {:.3f} s)",
                                              last_good_index, last_good_time);
  Fail(
      fmt::format("the video data is truncated or corrupt {} of the {} "
                  "frames the container lists ({}); re-copy or re-export "
                  "the file",
                  where, info.frame_count, detail));
}

bool VideoReader::State::DecodeNext() {
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

void VideoReader::State::NoteReturned() {
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
  // An error logged since the last frame returned lies in a frame decoded
  // meanwhile, which is returned within as many frames as the decoder
  // holds (its threads, and its reordering delay for B pictures): all of
  // them are suspect, and a key frame among them does not clear the taint.
  const int64_t errors = decode_errors.load();
  if (errors != errors_noted) {
    errors_noted = errors;
    suspect_frames = codec->thread_count + codec->has_b_frames + 2;
  }
  if (frame->key_frame && suspect_frames == 0) tainted = false;
  tainted = tainted || lost || suspect_frames > 0 ||
            frame->decode_error_flags != 0 ||
            (frame->flags & AV_FRAME_FLAG_CORRUPT) != 0;
  if (suspect_frames > 0) --suspect_frames;
  if (tainted) damaged.push_back({last_good_index, last_good_time, false});
  last_returned_index = last_good_index;
}

double VideoReader::State::FrameTime() const {
  const int64_t pts = frame->best_effort_timestamp != AV_NOPTS_VALUE
                          ? frame->best_effort_timestamp
                          : frame->pts;
  return (pts - start_pts) * av_q2d(time_base);
}

bool VideoReader::State::Next() {
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

int64_t VideoReader::State::IndexOf(int64_t pts, double time_s) const {
  const auto it = std::lower_bound(frame_pts.begin(), frame_pts.end(), pts);
  if (it != frame_pts.end() && *it == pts) return it - frame_pts.begin();
  return std::llround(time_s * info.fps);  // no timestamps to go by
}

void VideoReader::State::CheckFormat() const {
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

void VideoReader::State::Rewind() {
  av_seek_frame(format, stream, start_pts, AVSEEK_FLAG_BACKWARD);
  avcodec_flush_buffers(codec);
  ForgetSuspects();
  flushing = finished = false;
  last_good_index = -1;
  last_good_time = 0.0;
  last_good_pts = AV_NOPTS_VALUE;
}

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
  frame->intra = state_->FrameIntra();
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
      s.ForgetSuspects();
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
  frame.intra = s.FrameIntra();
  return frame;
}

}  // namespace softbench
