#include "pipelines/reports/tune_page.h"

#include <fmt/format.h>

#include <nlohmann/json.hpp>

#include "pipelines/reports/html_report.h"
#include "vision/image_data_uri.h"

namespace softbench {
namespace {

// The page's script. Hue, saturation and value are OpenCV's 8-bit ones
// (H 0-179, S and V 0-255), so bounds read here are the plan's; a range
// with h_lo > h_hi wraps through 0, as the plan's does.
constexpr const char* kScript = R"js(
const view = document.getElementById('view');
const context = view.getContext('2d');
const picture = new Image();
let hsv = null, pixels = null;

function toHsv(data) {
  const n = data.length / 4, out = new Uint8Array(3 * n);
  for (let i = 0; i < n; ++i) {
    const r = data[4 * i], g = data[4 * i + 1], b = data[4 * i + 2];
    const v = Math.max(r, g, b), diff = v - Math.min(r, g, b);
    let h = 0;
    if (diff > 0) {
      if (v === r) h = 60 * (g - b) / diff;
      else if (v === g) h = 120 + 60 * (b - r) / diff;
      else h = 240 + 60 * (r - g) / diff;
      if (h < 0) h += 360;
    }
    out[3 * i] = Math.round(h / 2) % 180;
    out[3 * i + 1] = v === 0 ? 0 : Math.round(255 * diff / v);
    out[3 * i + 2] = v;
  }
  return out;
}

function bounds(color) {
  return ['h_lo', 'h_hi', 's_lo', 's_hi', 'v_lo', 'v_hi'].map(
      k => Number(document.getElementById(color.name + '-' + k).value));
}

function inRange(b, i) {
  const h = hsv[3 * i], s = hsv[3 * i + 1], v = hsv[3 * i + 2];
  const hueIn = b[0] <= b[1] ? (h >= b[0] && h <= b[1]) : (h >= b[0] || h <= b[1]);
  return hueIn && s >= b[2] && s <= b[3] && v >= b[4] && v <= b[5];
}

// Connected components of the mask (8-connected), their areas and centroids.
function blobs(mask, w, h) {
  const label = new Int32Array(w * h).fill(-1), found = [];
  const stack = [];
  for (let start = 0; start < w * h; ++start) {
    if (!mask[start] || label[start] >= 0) continue;
    let area = 0, sx = 0, sy = 0;
    label[start] = found.length;
    stack.push(start);
    while (stack.length) {
      const p = stack.pop(), x = p % w, y = (p - x) / w;
      ++area; sx += x; sy += y;
      for (let dy = -1; dy <= 1; ++dy) {
        for (let dx = -1; dx <= 1; ++dx) {
          const nx = x + dx, ny = y + dy, q = ny * w + nx;
          if (nx < 0 || ny < 0 || nx >= w || ny >= h) continue;
          if (mask[q] && label[q] < 0) { label[q] = found.length; stack.push(q); }
        }
      }
    }
    found.push({area: area, x: sx / area, y: sy / area});
  }
  return found;
}

function update() {
  if (!hsv) return;
  const w = picture.naturalWidth, h = picture.naturalHeight;
  const shown = context.createImageData(w, h);
  shown.data.set(pixels);
  const onlyMask = document.getElementById('mask-only').checked;
  if (onlyMask) shown.data.fill(0);
  for (let i = 0; i < w * h; ++i) shown.data[4 * i + 3] = 255;
  const yaml = ['# paste into the plan: each marker of that colour gets its hsv'];
  const marks = [];
  for (const color of COLORS) {
    const b = bounds(color);
    for (const k of ['h_lo', 'h_hi', 's_lo', 's_hi', 'v_lo', 'v_hi']) {
      document.getElementById(color.name + '-' + k + '-value').textContent =
          document.getElementById(color.name + '-' + k).value;
    }
    const mask = new Uint8Array(w * h);
    let count = 0;
    for (let i = 0; i < w * h; ++i) {
      if (!inRange(b, i)) continue;
      mask[i] = 1; ++count;
      shown.data[4 * i] = color.tint[0];
      shown.data[4 * i + 1] = color.tint[1];
      shown.data[4 * i + 2] = color.tint[2];
    }
    const dots = color.radius > 0 ? blobs(mask, w, h).filter(
        d => d.area >= MIN_AREA * Math.PI * color.radius ** 2 &&
             d.area <= MAX_AREA * Math.PI * color.radius ** 2) : [];
    for (const d of dots) marks.push({x: d.x, y: d.y, r: color.radius});
    document.getElementById('dots-' + color.name).textContent = dots.length;
    document.getElementById('pixels-' + color.name).textContent = count;
    document.getElementById('status-' + color.name).textContent =
        dots.length ? dots.length + ' dot-sized blob' + (dots.length > 1 ? 's' : '')
                    : 'absent: no dot-sized blob in this range';
    // A colour without dots in this range is written as a comment.
    yaml.push((dots.length ? '  - ' : '  # no dots with: ') + '{color: ' +
              color.name + ', hsv: [' + b.join(', ') + ']}');
  }
  view.width = w; view.height = h;
  context.putImageData(shown, 0, 0);
  context.strokeStyle = '#00ff00';
  context.lineWidth = Math.max(2, w / 600);
  for (const m of marks) {
    context.beginPath();
    context.arc(m.x + 0.5, m.y + 0.5, m.r + 6, 0, 2 * Math.PI);
    context.stroke();
  }
  document.getElementById('yaml').textContent = yaml.join('\n') + '\n';
}

// #red=0,10,100,255,50,255&green=...: move those sliders.
function fromFragment() {
  for (const part of location.hash.slice(1).split('&')) {
    const [name, values] = part.split('=');
    if (!values || !COLORS.some(c => c.name === name)) continue;
    values.split(',').forEach((value, k) => {
      const slider = document.getElementById(
          name + '-' + ['h_lo', 'h_hi', 's_lo', 's_hi', 'v_lo', 'v_hi'][k]);
      if (slider) { slider.value = value; slider.dispatchEvent(new Event('input')); }
    });
  }
}

for (const input of document.querySelectorAll('input')) {
  input.addEventListener('input', update);
}
window.addEventListener('hashchange', fromFragment);
picture.onload = () => {
  const w = picture.naturalWidth, h = picture.naturalHeight;
  const canvas = document.createElement('canvas');
  canvas.width = w; canvas.height = h;
  const c = canvas.getContext('2d');
  c.drawImage(picture, 0, 0);
  pixels = c.getImageData(0, 0, w, h).data;
  hsv = toHsv(pixels);
  update();
  fromFragment();
  document.body.dataset.ready = 'yes';
};
picture.src = PICTURE;
)js";

constexpr const char* kStyle = R"css(
body { font-family: system-ui, sans-serif; margin: 1em; color: #222; }
h1 { font-size: 1.4em; overflow-wrap: anywhere; }
.layout { display: flex; flex-wrap: wrap; gap: 1em; align-items: flex-start; }
.controls { flex: 1 1 22em; min-width: 0; max-width: 30em; }
fieldset { margin: 0 0 1em 0; }
label { display: grid; grid-template-columns: 6em 1fr 2.5em; gap: 0.4em;
        align-items: center; font-size: 0.9em; }
.status { font-size: 0.9em; margin: 0.3em 0; }
canvas { max-width: 100%; height: auto; border: 1px solid #ccc; }
.picture { flex: 1 1 30em; min-width: 0; }
pre { background: #f5f5f5; padding: 0.6em; overflow-x: auto; }
)css";

}  // namespace

std::string TunePageHtml(const cv::Mat& bgr, const std::string& source,
                         double time_s, const std::vector<TunedColor>& colors,
                         const SegmentationOptions& segmentation) {
  nlohmann::json described = nlohmann::json::array();
  std::string controls;
  const char* labels[] = {"hue low",         "hue high",  "saturation low",
                          "saturation high", "value low", "value high"};
  const char* keys[] = {"h_lo", "h_hi", "s_lo", "s_hi", "v_lo", "v_hi"};
  for (const TunedColor& color : colors) {
    // The mask's tint: magenta over any colour, easy to tell from the dots.
    described.push_back({{"name", color.name},
                         {"radius", color.found ? color.dot_radius_px : 0.0},
                         {"tint", {255, 0, 255}}});
    controls += fmt::format("<fieldset><legend>{}</legend>\n", color.name);
    for (int k = 0; k < 6; ++k) {
      controls += fmt::format(
          "<label>{0}<input type=\"range\" id=\"{1}-{2}\" min=\"0\" "
          "max=\"{3}\" value=\"{4}\"><span id=\"{1}-{2}-value\">{4}</span>"
          "</label>\n",
          labels[k], color.name, keys[k], k < 2 ? 179 : 255, color.bounds[k]);
    }
    controls += fmt::format(
        "<p class=\"status\"><span id=\"status-{0}\"></span> (<span "
        "id=\"dots-{0}\"></span> dots, <span id=\"pixels-{0}\"></span> "
        "pixels in range){1}</p></fieldset>\n",
        color.name,
        color.found
            ? ""
            : "; tune found none in its range: " + HtmlEscape(color.why_not));
  }
  return fmt::format(
      "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\n"
      "<meta name=\"viewport\" content=\"width=device-width, "
      "initial-scale=1\">\n<title>softbench tune: {0}</title>\n"
      "<style>{1}</style></head>\n<body>\n<h1>Colour thresholds: {0} at t = "
      "{2:.3f} s</h1>\n<p>Move the sliders until each colour's dots, and "
      "nothing else, are magenta; a green ring marks each blob of a dot's "
      "size. Then paste the YAML into the plan.</p>\n"
      "<div class=\"layout\"><div class=\"controls\">\n{3}"
      "<label><span>mask only</span><input type=\"checkbox\" "
      "id=\"mask-only\"><span></span></label>\n"
      "<pre id=\"yaml\"></pre></div>\n"
      "<div class=\"picture\"><canvas id=\"view\"></canvas></div></div>\n"
      "<script>const COLORS = {4}; const MIN_AREA = {5}; const MAX_AREA = "
      "{6}; const PICTURE = '{7}';</script>\n<script>{8}</script>\n"
      "</body></html>\n",
      HtmlEscape(source), kStyle, time_s, controls, described.dump(),
      segmentation.min_area_fraction, segmentation.max_area_fraction,
      PngDataUri(bgr), kScript);
}

}  // namespace softbench
