#include "vision/mask_morphology.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cstdint>
#include <cstring>
#include <opencv2/imgproc.hpp>
#include <vector>

#include "util/check.h"

namespace softbench {
namespace {

// Eight pixels are moved to and from a word with byte i as pixel i.
static_assert(std::endian::native == std::endian::little);

constexpr uint64_t kOnes = ~uint64_t{0};

// Eight pixels from eight bits: byte i of kPixelsOf[bits] is 255 where bit
// i is set.
constexpr std::array<uint64_t, 256> kPixelsOf = [] {
  std::array<uint64_t, 256> pixels{};
  for (int bits = 0; bits < 256; ++bits) {
    for (int i = 0; i < 8; ++i) {
      if (((bits >> i) & 1) != 0) pixels[bits] |= uint64_t{0xff} << (8 * i);
    }
  }
  return pixels;
}();

// A mask's rows as bits, 64 pixels to a word (pixel x in bit x % 64 of
// word x / 64). The bits past the width are kept set: an erosion counts
// everything outside the image as set (cv::morphologyEx's default border
// for it), and a dilation, run as the erosion of the complement, as clear.
class BitRows {
 public:
  BitRows(int rows, int cols)
      : rows_(rows),
        cols_(cols),
        words_((cols + 63) / 64),
        bits_(static_cast<size_t>(rows) * words_) {}

  int rows() const { return rows_; }
  int words() const { return words_; }
  uint64_t* Row(int y) {
    return bits_.data() + static_cast<size_t>(y) * words_;
  }
  const uint64_t* Row(int y) const {
    return bits_.data() + static_cast<size_t>(y) * words_;
  }

  void Pack(const cv::Mat& mask) {
    for (int y = 0; y < rows_; ++y) {
      const uint8_t* p = mask.ptr<uint8_t>(y);
      uint64_t* row = Row(y);
      for (int w = 0; w < words_; ++w) row[w] = 0;
      int x = 0;
      // Eight pixels at a time: each byte's "non-zero" folded into its
      // lowest bit, and a multiply that gathers the eight bits, in order,
      // into the top byte (every partial product lands on a bit of its own,
      // so none carries).
      for (; x + 8 <= cols_; x += 8) {
        uint64_t eight = 0;
        std::memcpy(&eight, p + x, 8);
        eight |= eight >> 4;
        eight |= eight >> 2;
        eight |= eight >> 1;
        eight &= 0x0101010101010101;
        const uint64_t byte = (eight * 0x0102040810204080) >> 56;
        row[x / 64] |= byte << (x % 64);
      }
      for (; x < cols_; ++x) row[x / 64] |= uint64_t{p[x] != 0} << (x % 64);
    }
    Pad();
  }

  void Unpack(cv::Mat* mask) const {
    for (int y = 0; y < rows_; ++y) {
      uint8_t* p = mask->ptr<uint8_t>(y);
      const uint64_t* row = Row(y);
      int x = 0;
      for (; x + 8 <= cols_; x += 8) {
        const uint64_t eight = kPixelsOf[(row[x / 64] >> (x % 64)) & 0xff];
        std::memcpy(p + x, &eight, 8);
      }
      for (; x < cols_; ++x) {
        p[x] = ((row[x / 64] >> (x % 64)) & 1) != 0 ? 255 : 0;
      }
    }
  }

  void Invert() {
    for (uint64_t& word : bits_) word = ~word;
    Pad();
  }

  // The bits past the width in a row's last word.
  uint64_t padding() const {
    return cols_ % 64 == 0 ? 0 : kOnes << (cols_ % 64);
  }

  // Sets the bits past the width.
  void Pad() {
    for (int y = 0; y < rows_; ++y) Row(y)[words_ - 1] |= padding();
  }

 private:
  int rows_, cols_, words_;
  std::vector<uint64_t> bits_;
};

// Erodes a row along itself by one pixel each side, in place: pixel x
// becomes pixels x - 1, x and x + 1 ANDed, beyond the ends set. Erosion by
// a run of half width w is this w times (runs add under dilation, and a
// set pixel beyond an end stands in exactly for what it hides, which an
// inner pixel's own AND already holds). `padding`: the bits past the width
// in the last word, set again.
void ErodeAlongByOne(uint64_t padding, int words, uint64_t* row) {
  uint64_t before = kOnes;  // the word before, as it was
  for (int i = 0; i < words; ++i) {
    const uint64_t word = row[i];
    const uint64_t after = i + 1 < words ? row[i + 1] : kOnes;
    const uint64_t right = (word >> 1) | (after << 63);  // pixel x + 1
    const uint64_t left = (word << 1) | (before >> 63);  // pixel x - 1
    row[i] = word & right & left;
    before = word;
  }
  row[words - 1] |= padding;
}

// Erosion by the element whose row dy (-r to r) is the centred run of
// half width half_widths[dy + r]: each row eroded along itself by every
// half width, then the rows ANDed. `across` is scratch.
void Erode(const std::vector<int>& half_widths, BitRows* bits,
           std::vector<uint64_t>* across) {
  const int r = static_cast<int>(half_widths.size()) / 2;
  const int widest = *std::max_element(half_widths.begin(), half_widths.end());
  const int rows = bits->rows(), words = bits->words();
  const size_t plane = static_cast<size_t>(rows) * words;
  // (*across)[w * plane + y * words + i]: row y eroded along by half width w.
  across->resize((widest + 1) * plane);
  const uint64_t padding = bits->padding();
  for (int y = 0; y < rows; ++y) {
    const uint64_t* row = bits->Row(y);
    uint64_t* eroded = across->data() + y * words;
    // Word by word: a row is a word or two, too short for memcpy's call.
    for (int i = 0; i < words; ++i) eroded[i] = row[i];
    for (int w = 1; w <= widest; ++w) {
      for (int i = 0; i < words; ++i) eroded[plane + i] = eroded[i];
      eroded += plane;
      ErodeAlongByOne(padding, words, eroded);
    }
  }
  for (int y = 0; y < rows; ++y) {
    uint64_t* out = bits->Row(y);
    // Rows beyond the image are set: they leave the AND as it is.
    const int dy_first = std::max(-r, -y), dy_last = std::min(r, rows - 1 - y);
    for (int i = 0; i < words; ++i) {
      uint64_t word = kOnes;
      for (int dy = dy_first; dy <= dy_last; ++dy) {
        word &= (*across)[half_widths[dy + r] * plane + (y + dy) * words + i];
      }
      out[i] = word;
    }
  }
}

// The half width of each row of OpenCV's elliptical element (each row is
// one run centred on the middle column).
std::vector<int> EllipseRows(int radius) {
  const cv::Mat element = cv::getStructuringElement(
      cv::MORPH_ELLIPSE, {2 * radius + 1, 2 * radius + 1});
  std::vector<int> half_widths;
  for (int y = 0; y < element.rows; ++y) {
    const uint8_t* row = element.ptr<uint8_t>(y);
    const int first =
        static_cast<int>(std::find_if(row, row + element.cols,
                                      [](uint8_t v) { return v != 0; }) -
                         row);
    const int set = static_cast<int>(std::count_if(
        row, row + element.cols, [](uint8_t v) { return v != 0; }));
    SOFTBENCH_CHECK(set > 0 && first + set - 1 == 2 * radius - first)
        << "OpenCV's elliptical element row " << y << " is not one centred run";
    half_widths.push_back(radius - first);
  }
  return half_widths;
}

}  // namespace

void OpenThenClose(int radius, cv::Mat* mask) {
  SOFTBENCH_CHECK(radius >= 1 && mask->type() == CV_8UC1)
      << "OpenThenClose needs a radius >= 1 and a CV_8UC1 mask";
  if (mask->empty()) return;
  const std::vector<int> half_widths = EllipseRows(radius);
  BitRows bits(mask->rows, mask->cols);
  bits.Pack(*mask);
  // Opening (erode, dilate) then closing (dilate, erode), each dilation the
  // erosion of the complement: the two dilations share one complement.
  std::vector<uint64_t> across;
  Erode(half_widths, &bits, &across);
  bits.Invert();
  Erode(half_widths, &bits, &across);
  Erode(half_widths, &bits, &across);
  bits.Invert();
  Erode(half_widths, &bits, &across);
  bits.Unpack(mask);
}

}  // namespace softbench
