#include "vision/head_tracker.h"

#include <fmt/format.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <utility>

namespace softbench {

std::optional<std::string> HeadTrackerOptions::Problem() const {
  if (auto problem = centre.Problem()) return problem;
  if (!(relocate_radius_factor >= 0.0)) {
    return "relocate_radius_factor must be >= 0";
  }
  if (!(search_radius_factor >= 1.2)) {
    return "search_radius_factor must be >= 1.2 (the region must hold a dot)";
  }
  if (!(layout_tolerance_mm > 0.0)) return "layout_tolerance_mm must be > 0";
  return search.Problem();
}

namespace {

constexpr double kNan = std::numeric_limits<double>::quiet_NaN();

// Rotation taking the centred points `from` onto the centred points `to`
// (2-D Procrustes), and the RMS residual after it and the translation.
double RigidFit(const std::vector<Eigen::Vector2d>& from,
                const std::vector<Eigen::Vector2d>& to, double* rms) {
  Eigen::Vector2d mean_from = Eigen::Vector2d::Zero(),
                  mean_to = Eigen::Vector2d::Zero();
  for (size_t i = 0; i < from.size(); ++i) {
    mean_from += from[i];
    mean_to += to[i];
  }
  mean_from /= from.size();
  mean_to /= to.size();
  double dot = 0.0, cross = 0.0;
  for (size_t i = 0; i < from.size(); ++i) {
    const Eigen::Vector2d a = from[i] - mean_from, b = to[i] - mean_to;
    dot += a.dot(b);
    cross += a.x() * b.y() - a.y() * b.x();
  }
  const double angle = std::atan2(cross, dot);
  if (rms != nullptr) {
    const Eigen::Matrix2d r = Eigen::Rotation2Dd(angle).toRotationMatrix();
    double sum = 0.0;
    for (size_t i = 0; i < from.size(); ++i) {
      sum += (r * (from[i] - mean_from) - (to[i] - mean_to)).squaredNorm();
    }
    *rms = std::sqrt(sum / from.size());
  }
  return angle;
}

}  // namespace

HeadTracker::HeadTracker(PlaneMapping mapping, std::vector<HeadMarkers> heads,
                         const HeadTrackerOptions& options)
    : mapping_(std::move(mapping)),
      heads_(std::move(heads)),
      options_(options) {
  const CameraIntrinsics& k = mapping_.intrinsics();
  const double mm_per_px = mapping_.MmPerPixelAt(
      Eigen::Vector2d(k.width_px / 2.0, k.height_px / 2.0));
  for (const HeadMarkers& head : heads_) {
    radius_px_.push_back(head.dot_diameter_mm / 2.0 / mm_per_px);
    first_offsets_mm_.push_back(head.layout_mm);
  }
  last_pixels_.resize(heads_.size());
  first_dots_mm_.resize(heads_.size());
}

void HeadTracker::ForgetPositions() { relocate_ = true; }

bool HeadTracker::Relocate(const FrameSource& frame, int head,
                           HeadObservation* out) {
  const cv::Rect region = BoxAround(
      last_pixels_[head], options_.relocate_radius_factor * radius_px_[head],
      frame.luma().size());
  if (region.empty()) return false;
  HeadObservation found = *out;
  // Rejections are counted by full-image searches only.
  if (!Detect(frame, region, head, &found) ||
      found.dots_found < heads_[head].dots) {
    return false;
  }
  found.rejected_blobs = 0;
  *out = found;
  return true;
}

std::vector<HeadObservation> HeadTracker::Measure(const FrameSource& frame) {
  std::vector<HeadObservation> result(heads_.size());
  claimed_.clear();
  for (size_t h = 0; h < heads_.size(); ++h) {
    HeadObservation& obs = result[h];
    obs.dots.assign(heads_[h].dots, DotObservation{});
    const bool known =
        !options_.full_frame_every_frame && !last_pixels_[h].empty();
    bool found = false;
    if (known && relocate_) {
      found = Relocate(frame, static_cast<int>(h), &obs);
    } else if (known) {
      TrackRegions(frame, static_cast<int>(h), &obs);
      found = obs.dots_found == heads_[h].dots;
    }
    if (!found) {
      HeadObservation detected = obs;
      detected.dots.assign(heads_[h].dots, DotObservation{});
      detected.dots_found = 0;
      if (Detect(frame, cv::Rect(cv::Point(0, 0), frame.luma().size()),
                 static_cast<int>(h), &detected)) {
        obs = detected;
      } else if (obs.dots_found == 0) {
        obs.note = detected.note;
        obs.rejected_blobs = detected.rejected_blobs;
      } else {
        obs.note += (obs.note.empty() ? "" : "; ") + detected.note;
      }
      obs.full_frame = true;
    }
    Finish(static_cast<int>(h), &obs);
  }
  relocate_ = false;
  return result;
}

void HeadTracker::TrackRegions(const FrameSource& frame, int head,
                               HeadObservation* out) {
  const HeadMarkers& markers = heads_[head];
  SegmentationOptions segmentation = options_.segmentation;
  segmentation.dot_radius_px = radius_px_[head];
  const int half = static_cast<int>(
      std::ceil(options_.search_radius_factor * radius_px_[head]));
  for (int i = 0; i < markers.dots; ++i) {
    const Eigen::Vector2d last = last_pixels_[head][i];
    const cv::Rect region(static_cast<int>(std::lround(last.x())) - half,
                          static_cast<int>(std::lround(last.y())) - half,
                          2 * half + 1, 2 * half + 1);
    const cv::Mat bgr = frame.BgrRegion(region);
    if (bgr.empty()) continue;
    const cv::Rect clipped =
        region & cv::Rect(0, 0, frame.luma().cols, frame.luma().rows);
    cv::Mat mask = ColorMask(bgr, markers.color);
    CleanMask(segmentation, &mask);
    // Usually the region holds the dot alone; otherwise label it and take
    // the blob nearest the last position. Rejections are not counted here:
    // a region may clip a neighbouring dot, which is no distractor.
    std::optional<Blob> nearest = SingleBlob(mask, segmentation, clipped.tl());
    if (!nearest) {
      for (const Blob& blob :
           FindBlobs(mask, segmentation, clipped.tl()).accepted) {
        if (!nearest || (blob.centroid - last).squaredNorm() <
                            (nearest->centroid - last).squaredNorm()) {
          nearest = blob;
        }
      }
    }
    if (!nearest) continue;
    // A blob cut by the region's edge is a different shape: let the full
    // image decide.
    if (nearest->box.x <= clipped.x || nearest->box.y <= clipped.y ||
        nearest->box.br().x >= clipped.br().x ||
        nearest->box.br().y >= clipped.br().y) {
      continue;
    }
    // A dot that barely moved converges in fewer steps from its last
    // centre than from the mask's.
    const bool still = (nearest->centroid - last).norm() < 1.0;
    Refine(frame, head, i, nearest->centroid, still ? last : nearest->centroid,
           out);
  }
}

bool HeadTracker::Refine(const FrameSource& frame, int head, int dot,
                         const Eigen::Vector2d& blob_centroid,
                         const Eigen::Vector2d& start, HeadObservation* out) {
  DotCentreOptions centre_options = options_.centre;
  centre_options.luma_encoding = frame.luma_encoding();
  const DotCentre centre =
      LocateDotCentre(frame.luma(), start, radius_px_[head], centre_options);
  if (!centre.found) {
    out->note = fmt::format("dot {}: {}", dot + 1, centre.why_not);
    return false;
  }
  DotObservation& d = out->dots[dot];
  d.found = true;
  d.pixel = centre.centre;
  d.sigma_px = centre.sigma_px;
  d.binary_pixel = blob_centroid;
  ++out->dots_found;
  return true;
}

bool HeadTracker::Detect(const FrameSource& frame, const cv::Rect& region,
                         int head, HeadObservation* out) {
  const HeadMarkers& markers = heads_[head];
  SegmentationOptions segmentation = options_.segmentation;
  segmentation.dot_radius_px = radius_px_[head];
  const BlobSummary blobs =
      SearchDots(frame, region, markers.color, segmentation, options_.search);
  // Candidates: accepted blobs not taken by an earlier head this frame,
  // the roundest first, at most 12 (the search below is combinatorial).
  std::vector<Blob> candidates;
  for (const Blob& blob : blobs.accepted) {
    const bool taken = std::any_of(
        claimed_.begin(), claimed_.end(), [&](const Eigen::Vector2d& c) {
          return (c - blob.centroid).norm() < radius_px_[head];
        });
    if (!taken) candidates.push_back(blob);
  }
  std::sort(candidates.begin(), candidates.end(),
            [](const Blob& a, const Blob& b) {
              return a.circularity > b.circularity;
            });
  if (candidates.size() > 12) candidates.resize(12);
  out->rejected_blobs = blobs.TotalRejected();
  const int k = markers.dots;
  const int n = static_cast<int>(candidates.size());
  const std::string seen = fmt::format(
      "{} {} dot-like blob{} ({} more rejected by size or shape) at t = "
      "{:.3f} s",
      n, markers.color_name, n == 1 ? "" : "s", blobs.TotalRejected(),
      frame.time_s());
  if (n < k) {
    out->note = fmt::format(
        "head '{}': found {}, the plan says {} dots; check the colour "
        "range (softbench tune) and the dot size",
        markers.name, seen, k);
    return false;
  }
  std::vector<Eigen::Vector2d> candidate_mm;
  for (const Blob& blob : candidates) {
    candidate_mm.push_back(mapping_.ToPlane(blob.centroid));
  }
  // Every k-subset in every order, fitted rigidly to the layout; among fits
  // within 0.1 mm of the best, the one turned least (the layout's own
  // symmetry gives several equally good orders).
  struct Fit {
    double rms, angle;
    std::vector<int> order;
  };
  std::vector<Fit> fits;
  std::vector<bool> select(n, false);
  std::fill(select.begin(), select.begin() + k, true);
  do {
    std::vector<int> order;
    for (int i = 0; i < n; ++i) {
      if (select[i]) order.push_back(i);
    }
    do {
      std::vector<Eigen::Vector2d> points;
      for (int i : order) points.push_back(candidate_mm[i]);
      double rms = 0.0;
      const double angle = RigidFit(markers.layout_mm, points, &rms);
      fits.push_back({rms, angle, order});
    } while (std::next_permutation(order.begin(), order.end()));
  } while (std::prev_permutation(select.begin(), select.end()));
  double best_rms = std::numeric_limits<double>::infinity();
  for (const Fit& fit : fits) best_rms = std::min(best_rms, fit.rms);
  const Fit* chosen = nullptr;
  for (const Fit& fit : fits) {
    if (fit.rms <= best_rms + 0.1 &&
        (chosen == nullptr || std::abs(fit.angle) < std::abs(chosen->angle))) {
      chosen = &fit;
    }
  }
  if (best_rms > options_.layout_tolerance_mm) {
    out->note = fmt::format(
        "head '{}': found {}, but no {} of them match the plan's dot layout "
        "(best misfit {:.2f} mm > {:.2f} mm); check layout_mm and the scale",
        markers.name, seen, k, best_rms, options_.layout_tolerance_mm);
    return false;
  }
  for (int i = 0; i < k; ++i) {
    const Eigen::Vector2d& centroid = candidates[chosen->order[i]].centroid;
    Refine(frame, head, i, centroid, centroid, out);
  }
  out->rejected_blobs += n - k;
  return out->dots_found > 0;
}

void HeadTracker::Finish(int head, HeadObservation* out) {
  const HeadMarkers& markers = heads_[head];
  ToPlane(head, mapping_, out);
  for (const DotObservation& d : out->dots) {
    if (d.found) claimed_.push_back(d.pixel);
  }
  if (out->complete && first_dots_mm_[head].empty()) {
    Eigen::Vector2d mean = Eigen::Vector2d::Zero();
    for (const DotObservation& d : out->dots) mean += d.plane_mm;
    mean /= markers.dots;
    for (int i = 0; i < markers.dots; ++i) {
      first_dots_mm_[head].push_back(out->dots[i].plane_mm);
      first_offsets_mm_[head][i] = out->dots[i].plane_mm - mean;
    }
  }
  Locate(head, mapping_, out);
  if (out->dots_found == 0) return;
  if (last_pixels_[head].empty()) {
    last_pixels_[head].assign(markers.dots, out->pixel);
  }
  for (int i = 0; i < markers.dots; ++i) {
    if (out->dots[i].found) last_pixels_[head][i] = out->dots[i].pixel;
  }
  if (!out->complete && out->note.empty()) {
    out->note =
        fmt::format("{} of {} dots found", out->dots_found, markers.dots);
  }
}

void HeadTracker::Remap(int head, const PlaneMapping& mapping,
                        HeadObservation* observation) const {
  ToPlane(head, mapping, observation);
  Locate(head, mapping, observation);
}

void HeadTracker::ToPlane(int head, const PlaneMapping& mapping,
                          HeadObservation* out) const {
  for (int i = 0; i < heads_[head].dots; ++i) {
    DotObservation& d = out->dots[i];
    if (!d.found) continue;
    d.plane_mm = mapping.ToPlane(d.pixel);
    d.binary_plane_mm = mapping.ToPlane(d.binary_pixel);
  }
  out->complete = out->dots_found == heads_[head].dots;
}

void HeadTracker::Locate(int head, const PlaneMapping& mapping,
                         HeadObservation* out) const {
  const HeadMarkers& markers = heads_[head];
  std::vector<Eigen::Vector2d> found_mm, first_mm;
  std::vector<int> found;
  double variance_px = 0.0;
  for (int i = 0; i < markers.dots; ++i) {
    if (!out->dots[i].found) continue;
    found.push_back(i);
    variance_px += out->dots[i].sigma_px * out->dots[i].sigma_px;
  }
  out->position_mm = out->binary_position_mm = out->pixel =
      Eigen::Vector2d(kNan, kNan);
  if (found.empty()) return;
  // Rotation from the dots found, against their first positions.
  if (!first_dots_mm_[head].empty() && found.size() >= 2) {
    for (int i : found) {
      found_mm.push_back(out->dots[i].plane_mm);
      first_mm.push_back(first_dots_mm_[head][i]);
    }
    out->rotation_rad = RigidFit(first_mm, found_mm, nullptr);
  }
  // Head centre: each found dot minus its (turned) offset, averaged; with
  // every dot found this is exactly the centre of the dots.
  const Eigen::Matrix2d turn =
      Eigen::Rotation2Dd(out->rotation_rad).toRotationMatrix();
  Eigen::Vector2d position = Eigen::Vector2d::Zero(),
                  binary = Eigen::Vector2d::Zero();
  for (int i : found) {
    const Eigen::Vector2d offset = turn * first_offsets_mm_[head][i];
    position += out->dots[i].plane_mm - offset;
    binary += out->dots[i].binary_plane_mm - offset;
  }
  out->position_mm = position / found.size();
  out->binary_position_mm = binary / found.size();
  out->pixel = mapping.ToPixel(out->position_mm);
  const double mm_per_px = mapping.MmPerPixelAt(out->pixel);
  out->sigma_mm = mm_per_px * std::sqrt(variance_px) / found.size();
}

}  // namespace softbench
