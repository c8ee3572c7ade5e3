#ifndef SOFTBENCH_VISION_TAG_BITMAP_H_
#define SOFTBENCH_VISION_TAG_BITMAP_H_

#include <cstddef>
#include <vector>

namespace softbench {

// The printed pattern of one tag36h11 tag, from libapriltag's own bitmap:
// what the renderer paints and `softbench targets` prints, so both draw
// exactly the tag the detector decodes.
struct TagBitmap {
  int total_width = 0;      // cells across, with the white quiet zone
  int width_at_border = 0;  // cells across the black border (size_mm's span)
  // total_width x total_width cells, row-major from the printed top-left;
  // true where the paper stays white.
  std::vector<bool> white;

  bool IsWhite(int row, int col) const {
    return white[static_cast<size_t>(row) * total_width + col];
  }
};

// The pattern of tag36h11 `id`; a programmer error outside the family's ids
// (plans and flags check them first).
TagBitmap Tag36h11Bitmap(int id);

}  // namespace softbench

#endif  // SOFTBENCH_VISION_TAG_BITMAP_H_
