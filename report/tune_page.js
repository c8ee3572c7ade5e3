// The tune page (softbench tune, pipelines/reports/tune_page.cc): sliders
// for each colour's HSV bounds over the picture, the mask and the dot-sized
// blobs redrawn as they move, and the plan's YAML to paste. The page defines
// COLORS, MIN_AREA, MAX_AREA and PICTURE before this script, and
// tune_core.js's toHsv, inRange and blobs.
/* global COLORS, MIN_AREA, MAX_AREA, PICTURE, toHsv, inRange, blobs */

const KEYS = ['h_lo', 'h_hi', 's_lo', 's_hi', 'v_lo', 'v_hi'];
const view = document.getElementById('view');
const context = view.getContext('2d');
const picture = new Image();
let hsv = null, pixels = null;

function bounds(color) {
  return KEYS.map(
      k => Number(document.getElementById(color.name + '-' + k).value));
}

function update() {
  if (!hsv) return;
  const w = picture.naturalWidth, h = picture.naturalHeight;
  const shown = context.createImageData(w, h);
  shown.data.set(pixels);
  const onlyMask = document.getElementById('mask-only').checked;
  if (onlyMask) shown.data.fill(0);
  for (let i = 0; i < w * h; ++i) shown.data[4 * i + 3] = 255;
  const yaml =
      ['# paste into the plan: each marker of that colour gets its hsv'];
  const marks = [];
  for (const color of COLORS) {
    const b = bounds(color);
    for (const k of KEYS) {
      document.getElementById(color.name + '-' + k + '-value').textContent =
          document.getElementById(color.name + '-' + k).value;
    }
    const mask = new Uint8Array(w * h);
    let count = 0;
    for (let i = 0; i < w * h; ++i) {
      if (!inRange(b, hsv, i)) continue;
      mask[i] = 1;
      ++count;
      shown.data[4 * i] = color.tint[0];
      shown.data[4 * i + 1] = color.tint[1];
      shown.data[4 * i + 2] = color.tint[2];
    }
    const area = Math.PI * color.radius ** 2;
    const dots = color.radius > 0 ?
        blobs(mask, w, h).filter(
            d => d.area >= MIN_AREA * area && d.area <= MAX_AREA * area) :
        [];
    for (const d of dots) marks.push({x: d.x, y: d.y, r: color.radius});
    document.getElementById('dots-' + color.name).textContent = dots.length;
    document.getElementById('pixels-' + color.name).textContent = count;
    document.getElementById('status-' + color.name).textContent =
        dots.length ?
        dots.length + ' dot-sized blob' + (dots.length > 1 ? 's' : '') :
        'absent: no dot-sized blob in this range';
    // A colour without dots in this range is written as a comment.
    yaml.push(
        (dots.length ? '  - ' : '  # no dots with: ') + '{color: ' +
        color.name + ', hsv: [' + b.join(', ') + ']}');
  }
  view.width = w;
  view.height = h;
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
      const slider = document.getElementById(name + '-' + KEYS[k]);
      if (slider) {
        slider.value = value;
        slider.dispatchEvent(new Event('input'));
      }
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
  canvas.width = w;
  canvas.height = h;
  const c = canvas.getContext('2d');
  c.drawImage(picture, 0, 0);
  pixels = c.getImageData(0, 0, w, h).data;
  hsv = toHsv(pixels);
  update();
  fromFragment();
  document.body.dataset.ready = 'yes';
};
picture.src = PICTURE;
