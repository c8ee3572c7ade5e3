#ifndef SOFTBENCH_VISION_TAG_FINDER_H_
#define SOFTBENCH_VISION_TAG_FINDER_H_

#include <opencv2/core.hpp>
#include <optional>
#include <set>
#include <string>

#include "vision/tag_detector.h"

namespace softbench {

struct TagFinderOptions {
  // Reads the tag: in the region around it, or in the whole frame.
  TagDetectorOptions detector{};
  // The first whole-frame search looks at an image decimated by a whole
  // factor to about this many pixels on its longer side; a tag under ~8 px
  // across there (50 px in a 4K frame) is then sought at `detector`'s own
  // decimation, as is any tag when that is as coarse. libapriltag's quad search
  // over a rendered 4K frame at quad_decimate 2 takes 99 ms; at 640 px, with
  // the tag then read in its region, 23 ms (BM_FindTagInFirstFrame).
  int search_side_px = 640;
  // The region read after the tag is found: its box grown by this fraction
  // of its side on every side (room for the camera's drift and knocks).
  double region_margin = 0.5;

  std::optional<std::string> Problem() const;
};

// Finds one tag in the frames of a video that holds it still or nearly: the
// first frame that shows it is searched whole, every later one only in the
// region around where it was first read, ten times faster. The whole-frame
// search looks first in a coarse image, then reads the tag in its region as
// every later frame is, so each frame's corners come from the same
// full-resolution fit (TagDetector); a tag too small for the coarse search
// is looked for at the detector's own decimation.
class TagFinder {
 public:
  TagFinder(int id, const TagFinderOptions& options);

  // Tag `id` in `luma` (8 or 16 bits, vision/luma.h), corners in the
  // frame's pixels, or nullopt. Other tags read are added to other_ids().
  std::optional<TagDetection> Find(const cv::Mat& luma);

  // Ids of the other tag36h11 tags read so far (for naming what was seen
  // when the wanted one is absent).
  const std::set<int>& other_ids() const { return other_ids_; }

 private:
  // The tag read by reader_ in `region` of `luma` (corners moved into the
  // frame's pixels).
  std::optional<TagDetection> ReadIn(const cv::Mat& luma,
                                     const cv::Rect& region);
  cv::Rect RegionAround(const TagDetection& tag, const cv::Size& size) const;

  int id_;
  TagFinderOptions options_;
  TagDetector reader_;
  std::optional<TagDetector> searcher_;  // made at the first frame's size
  cv::Rect region_;                      // empty until the tag is read
  std::set<int> other_ids_;
};

}  // namespace softbench

#endif  // SOFTBENCH_VISION_TAG_FINDER_H_
