// Runs tune_core.js on the cases a C++ test wrote with OpenCV's answers
// (tests/pipelines/reports/tune_page_test.cc) and says where they differ.
// Usage: node check_tune_core.js CASES.json; exits 1 on any difference.
'use strict';
const fs = require('fs');
const path = require('path');
const {toHsv, inRange, blobs} = require(path.join(__dirname, 'tune_core.js'));

const cases = JSON.parse(fs.readFileSync(process.argv[2], 'utf8'));
const problems = [];

// HSV: every pixel's three values.
const hsv = toHsv(Uint8Array.from(cases.rgba));
hsv.forEach((value, k) => {
  if (value !== cases.hsv[k] && problems.length < 10) {
    const pixel = Math.floor(k / 3);
    problems.push(`pixel ${pixel} rgba ` +
        `${cases.rgba.slice(4 * pixel, 4 * pixel + 3)}: hsv[${k % 3}] ` +
        `${value}, OpenCV ${cases.hsv[k]}`);
  }
});
// Masks: each range over the same pixels.
for (const range of cases.ranges) {
  range.mask.forEach((expected, i) => {
    if (Number(inRange(range.bounds, hsv, i)) !== expected &&
        problems.length < 20) {
      problems.push(`range [${range.bounds}] pixel ${i}: ${!expected}, ` +
          `OpenCV ${Boolean(expected)}`);
    }
  });
}
// Blobs: areas and centroids of each mask's components, in any order.
const key = b => `${b.area}@${b.x.toFixed(6)},${b.y.toFixed(6)}`;
for (const shapes of cases.blobs) {
  const ours = blobs(Uint8Array.from(shapes.mask), shapes.width,
      shapes.height).map(key).sort();
  const theirs = shapes.expected.map(key).sort();
  if (ours.join(' ') !== theirs.join(' ')) {
    problems.push(`blobs: ${ours.join(' ')}; OpenCV ${theirs.join(' ')}`);
  }
}
for (const problem of problems) console.log(problem);
console.log(problems.length ? 'tune_core.js differs from OpenCV' :
  'tune_core.js agrees with OpenCV');
process.exit(problems.length ? 1 : 0);
