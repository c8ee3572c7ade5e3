#ifndef SOFTBENCH_PIPELINES_REPORTS_CALIBRATION_REPORT_H_
#define SOFTBENCH_PIPELINES_REPORTS_CALIBRATION_REPORT_H_

#include <string>
#include <vector>

#include "calibration/camera_calibration.h"
#include "pipelines/measurement/board_views.h"

namespace softbench {

// A view whose error is this many times the median's is named as one to
// drop (a blurred or misdetected board pulls the fit).
inline constexpr double kOutlierViewFactor = 2.0;

// The views to consider dropping: error over kOutlierViewFactor times the
// median view's.
std::vector<std::string> OutlierViews(const BoardViews& views,
                                      const CameraCalibration& calibration);

// How much of the image the boards covered: the fraction of the cells of an
// 8 x 6 grid over the image that some board's corner lies in (a fit from
// boards in the middle only extrapolates the distortion to the corners).
double BoardCoverage(const BoardViews& views);

// The calibration page, the counterpart of MATLAB's Camera Calibrator: the
// intrinsics with their standard errors, each view's reprojection error
// (table and chart), the views without a board, and where the boards lay
// over the image (equal axes). `board` is the one the views were searched
// for; `source` names the views' video or folder.
std::string CalibrationReportHtml(const BoardViews& views,
                                  const CameraCalibration& calibration,
                                  const BoardOptions& board,
                                  const std::string& source);

}  // namespace softbench

#endif  // SOFTBENCH_PIPELINES_REPORTS_CALIBRATION_REPORT_H_
