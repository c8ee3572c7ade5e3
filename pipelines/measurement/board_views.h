#ifndef SOFTBENCH_PIPELINES_MEASUREMENT_BOARD_VIEWS_H_
#define SOFTBENCH_PIPELINES_MEASUREMENT_BOARD_VIEWS_H_

#include <opencv2/core.hpp>
#include <optional>
#include <string>
#include <vector>

#include "calibration/camera_calibration.h"

namespace softbench {

// Where a checkerboard was seen, for CalibrateCamera: the video or the
// images read with vision/, the corners found with calibration/.
struct BoardViewsOptions {
  BoardOptions board;    // the board's inner corners and square size
  double every_s = 0.5;  // video: one view per this many seconds
  bool progress =
      true;  // report progress (util/progress.h) while reading a video
  // The first this many views also have their board's own corners counted
  // (CountBoardCorners), so a --board that does not match the print is
  // refused with the count the print has.
  int counted_views = 5;

  // The first bad field, named, and what it must be.
  std::optional<std::string> Problem() const;
};

struct BoardViews {
  std::vector<std::vector<cv::Point2f>> corners;  // per view with a board
  std::vector<std::string> names;   // of those views: a file, or a time
  std::vector<std::string> missed;  // the views without the whole board
  cv::Size size;                    // every view's image size
  int looked_at = 0;                // views looked at, with a board or not
  // Inner corners the first views' boards have, whatever --board says.
  std::vector<cv::Size> counted;
};

// The board the views show: the inner-corner count found in more than half
// of the counted views (and in two at least), either way round; nullopt when
// the views do not agree.
std::optional<cv::Size> PrintedBoardSize(const BoardViews& views);

// Throws InputError when a view cannot be read or differs in size.
BoardViews BoardViewsFromVideo(const std::string& video_path,
                               const BoardViewsOptions& options);
// Every PNG or JPEG image in `directory`, in name order.
BoardViews BoardViewsFromImages(const std::string& directory,
                                const BoardViewsOptions& options);

}  // namespace softbench

#endif  // SOFTBENCH_PIPELINES_MEASUREMENT_BOARD_VIEWS_H_
