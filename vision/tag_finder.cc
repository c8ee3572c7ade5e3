#include "vision/tag_finder.h"

#include <algorithm>
#include <numbers>

#include "util/check.h"
#include "vision/frame_source.h"

namespace softbench {

std::optional<std::string> TagFinderOptions::Problem() const {
  if (auto problem = detector.Problem()) return problem;
  if (search_side_px < 64) return "search_side_px must be >= 64";
  if (!(region_margin >= 0.1)) return "region_margin must be >= 0.1";
  return std::nullopt;
}

TagFinder::TagFinder(int id, const TagFinderOptions& options)
    : id_(id), options_(options), reader_(options.detector) {
  SOFTBENCH_CHECK(!options.Problem()) << *options.Problem();
}

std::optional<TagDetection> TagFinder::Find(const cv::Mat& luma) {
  if (!region_.empty()) return ReadIn(luma, region_);
  // A whole factor: libapriltag decimates by the integer part of any other
  // than 1.5 but scales the quads back by the factor as given.
  const int factor = std::max(luma.cols, luma.rows) / options_.search_side_px;
  const auto decimate = static_cast<float>(factor);
  if (decimate > options_.detector.quad_decimate) {
    if (!searcher_) {
      TagDetectorOptions coarse = options_.detector;
      coarse.quad_decimate = decimate;
      searcher_.emplace(coarse);
    }
    for (const TagDetection& seen : searcher_->Detect(luma)) {
      if (seen.id != id_) continue;
      if (auto tag = ReadIn(luma, RegionAround(seen, luma.size()))) {
        region_ = RegionAround(*tag, luma.size());
        return tag;
      }
    }
  }
  auto tag = ReadIn(luma, cv::Rect(cv::Point(0, 0), luma.size()));
  if (tag) region_ = RegionAround(*tag, luma.size());
  return tag;
}

std::optional<TagDetection> TagFinder::ReadIn(const cv::Mat& luma,
                                              const cv::Rect& region) {
  std::optional<TagDetection> wanted;
  const Eigen::Vector2d offset(region.x, region.y);
  for (TagDetection tag : reader_.Detect(luma(region))) {
    for (int c = 0; c < 4; ++c) {
      tag.corners[c] += offset;
      tag.coarse_corners[c] += offset;
    }
    if (tag.id != id_) {
      other_ids_.insert(tag.id);
    } else if (!wanted) {
      wanted = tag;
    }
  }
  return wanted;
}

cv::Rect TagFinder::RegionAround(const TagDetection& tag,
                                 const cv::Size& size) const {
  const double side_px =
      (tag.corners[0] - tag.corners[2]).norm() / std::numbers::sqrt2;
  return BoxAround({tag.corners.begin(), tag.corners.end()},
                   options_.region_margin * side_px, size);
}

}  // namespace softbench
