#ifndef SOFTBENCH_VISION_PHOTO_READER_H_
#define SOFTBENCH_VISION_PHOTO_READER_H_

#include <opencv2/core.hpp>
#include <string>

namespace softbench {

// True when `path` names a photo by its extension (.png, .jpg, .jpeg, .heic,
// .heif, any case) rather than a video.
bool IsPhotoPath(const std::string& path);

// A photo of the bench as 8-bit BGR, upright as it was taken: PNG and JPEG
// through FFmpeg (EXIF orientation applied), HEIC and HEIF, an iPhone's
// default, through libheif (its rotation and mirroring applied). Throws
// InputError naming the file when it cannot be read.
cv::Mat ReadPhoto(const std::string& path);

}  // namespace softbench

#endif  // SOFTBENCH_VISION_PHOTO_READER_H_
