#include "vision/video_codecs.h"

#include <algorithm>

#include "util/join_names.h"

namespace softbench {

const std::vector<VideoCodec>& VideoCodecs() {
  static const std::vector<VideoCodec> kCodecs = {
      // The default of most Android phones and of lab cameras.
      {"h264", "libx264", {8, 10}, {"4:2:0", "4:2:2", "4:4:4"}, "", "", ""},
      // An iPhone's default (10-bit HLG in its HDR mode).
      {"hevc",
       "libx265",
       {8, 10, 12},
       {"4:2:0", "4:2:2", "4:4:4"},
       "x265-params",
       "log-level=none:pools={threads}:frame-threads=1",
       "hvc1"},
  };
  return kCodecs;
}

bool VideoCodec::Encodes(int bit_depth) const {
  return std::find(bit_depths.begin(), bit_depths.end(), bit_depth) !=
         bit_depths.end();
}

bool VideoCodec::Takes(std::string_view subsampling) const {
  return std::find(chroma.begin(), chroma.end(), subsampling) != chroma.end();
}

const VideoCodec* FindVideoCodec(std::string_view name) {
  for (const VideoCodec& codec : VideoCodecs()) {
    if (codec.name == name) return &codec;
  }
  return nullptr;
}

std::string VideoCodecNames() {
  std::vector<std::string_view> names;
  for (const VideoCodec& codec : VideoCodecs()) names.push_back(codec.name);
  return JoinNames(names);
}

}  // namespace softbench
