// What the tune page computes the way softbench's C++ does, so the sliders
// show the mask `validate` will use. Kept free of the page (no DOM) so that
// tests/pipelines/reports/tune_page_test.cc runs it under Node.js against
// OpenCV on the same cases (report/check_tune_core.js).

// OpenCV's 8-bit RGB to HSV (cv::cvtColor COLOR_BGR2HSV), bit for bit: its
// fixed-point tables with 12 fractional bits. Hue 0-179 (degrees / 2),
// saturation and value 0-255. `rgba` is canvas ImageData (4 bytes a pixel).
const HSV_SHIFT = 12;
const HSV_ROUND = 1 << (HSV_SHIFT - 1);
const SDIV = new Int32Array(256);
const HDIV = new Int32Array(256);
for (let i = 1; i < 256; ++i) {
  SDIV[i] = Math.round((255 << HSV_SHIFT) / i);
  HDIV[i] = Math.round((180 << HSV_SHIFT) / (6 * i));
}

function toHsv(rgba) {
  const n = rgba.length / 4;
  const out = new Uint8Array(3 * n);
  for (let i = 0; i < n; ++i) {
    const r = rgba[4 * i], g = rgba[4 * i + 1], b = rgba[4 * i + 2];
    const v = Math.max(r, g, b);
    const diff = v - Math.min(r, g, b);
    let h;
    if (v === r) h = g - b;
    else if (v === g) h = b - r + 2 * diff;
    else h = r - g + 4 * diff;
    h = (h * HDIV[diff] + HSV_ROUND) >> HSV_SHIFT;
    if (h < 0) h += 180;
    out[3 * i] = h;
    out[3 * i + 1] = (diff * SDIV[v] + HSV_ROUND) >> HSV_SHIFT;
    out[3 * i + 2] = v;
  }
  return out;
}

// Whether pixel i of `hsv` lies in bounds b = [h_lo, h_hi, s_lo, s_hi, v_lo,
// v_hi]; a hue range with h_lo > h_hi wraps through 0, as the plan's does
// (vision/color_segmentation.h, HsvRange).
function inRange(b, hsv, i) {
  const h = hsv[3 * i], s = hsv[3 * i + 1], v = hsv[3 * i + 2];
  const hueIn = b[0] <= b[1] ? h >= b[0] && h <= b[1] : h >= b[0] || h <= b[1];
  return hueIn && s >= b[2] && s <= b[3] && v >= b[4] && v <= b[5];
}

// The 8-connected components of a w x h mask (non-zero bytes), with their
// areas and centroids, as cv::connectedComponentsWithStats gives them, in
// the raster order of each component's first pixel.
function blobs(mask, w, h) {
  const label = new Int32Array(w * h).fill(-1);
  const found = [];
  const stack = [];
  for (let start = 0; start < w * h; ++start) {
    if (!mask[start] || label[start] >= 0) continue;
    let area = 0, sx = 0, sy = 0;
    label[start] = found.length;
    stack.push(start);
    while (stack.length) {
      const p = stack.pop(), x = p % w, y = (p - x) / w;
      ++area;
      sx += x;
      sy += y;
      for (let dy = -1; dy <= 1; ++dy) {
        for (let dx = -1; dx <= 1; ++dx) {
          const nx = x + dx, ny = y + dy, q = ny * w + nx;
          if (nx < 0 || ny < 0 || nx >= w || ny >= h) continue;
          if (mask[q] && label[q] < 0) {
            label[q] = found.length;
            stack.push(q);
          }
        }
      }
    }
    found.push({area: area, x: sx / area, y: sy / area});
  }
  return found;
}

if (typeof module !== 'undefined') module.exports = {toHsv, inRange, blobs};
