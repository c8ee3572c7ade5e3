#ifndef SOFTBENCH_VISION_VIDEO_CODECS_H_
#define SOFTBENCH_VISION_VIDEO_CODECS_H_

#include <string>
#include <string_view>
#include <vector>

namespace softbench {

// A video codec softbench writes (`render --codec`): the one table that the
// writer's options check, the encoder's choice and the help text read. A new
// codec is one row here (docs/architecture.md, "Adding a video codec").
struct VideoCodec {
  std::string_view name;                 // as --codec names it: "h264"
  std::string_view encoder;              // FFmpeg's encoder: "libx264"
  std::vector<int> bit_depths;           // bits per sample it encodes
  std::vector<std::string_view> chroma;  // subsamplings: "4:2:0", ...
  // The encoder's private option that takes "key=value:..." parameters, and
  // the ones that keep it quiet and its threads to VideoWriterOptions::threads
  // ("{threads}" is replaced); empty for none.
  std::string_view params_option;
  std::string_view params;
  // The sample-entry tag written into MP4/MOV (4 characters; empty: the
  // muxer's default). HEVC as "hvc1" plays on Apple's players.
  std::string_view container_tag;

  bool Encodes(int bit_depth) const;
  bool Takes(std::string_view subsampling) const;
};

const std::vector<VideoCodec>& VideoCodecs();
// The codec named `name`, or nullptr.
const VideoCodec* FindVideoCodec(std::string_view name);
// "h264 or hevc", for help texts and messages.
std::string VideoCodecNames();

}  // namespace softbench

#endif  // SOFTBENCH_VISION_VIDEO_CODECS_H_
