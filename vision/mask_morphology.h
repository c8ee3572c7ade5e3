#ifndef SOFTBENCH_VISION_MASK_MORPHOLOGY_H_
#define SOFTBENCH_VISION_MASK_MORPHOLOGY_H_

#include <opencv2/core.hpp>

namespace softbench {

// Opening then closing of a 0/255 mask (CV_8UC1; any non-zero counts as
// set) by OpenCV's elliptical structuring element of side 2 radius + 1:
// the same pixels as cv::morphologyEx(MORPH_OPEN) then (MORPH_CLOSE) with
// cv::getStructuringElement(MORPH_ELLIPSE), borders included. The masks
// of tracked dots are a few dozen pixels wide, where OpenCV's four filter
// passes cost about 10 µs each in set-up alone, as much as the colour
// conversion; here the rows are packed 64 pixels to a word and each pass
// is a few shifts and ANDs per word.
void OpenThenClose(int radius, cv::Mat* mask);

}  // namespace softbench

#endif  // SOFTBENCH_VISION_MASK_MORPHOLOGY_H_
