#include "vision/tag_bitmap.h"

#include <apriltag/apriltag.h>
#include <apriltag/tag36h11.h>

#include <cstdlib>

#include "util/check.h"

namespace softbench {

TagBitmap Tag36h11Bitmap(int id) {
  apriltag_family_t* family = tag36h11_create();
  SOFTBENCH_CHECK(id >= 0 && id < static_cast<int>(family->ncodes))
      << "tag36h11 has no id " << id;
  image_u8_t* image = apriltag_to_image(family, id);
  TagBitmap bitmap;
  bitmap.total_width = family->total_width;
  bitmap.width_at_border = family->width_at_border;
  bitmap.white.resize(static_cast<size_t>(image->width) * image->height);
  for (int row = 0; row < image->height; ++row) {
    for (int col = 0; col < image->width; ++col) {
      bitmap.white[static_cast<size_t>(row) * image->width + col] =
          image->buf[row * image->stride + col] > 127;
    }
  }
  // Debian's libapriltag does not export image_u8_destroy; the image and its
  // buffer are both calloc'd by image_u8_create_stride.
  free(image->buf);
  free(image);
  tag36h11_destroy(family);
  return bitmap;
}

}  // namespace softbench
