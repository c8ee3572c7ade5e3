// Compiles and renders (to SVG, headless) every Vega-Lite chart of a softbench
// HTML report with the same libraries the page inlines; exits 1 if any chart
// fails. Usage: node report/check_report.mjs REPORT.html
import fs from 'fs';
import * as vega from 'vega';
import * as vegaLite from 'vega-lite';

const html = fs.readFileSync(process.argv[2], 'utf8');
const pattern = /vegaEmbed\('#chart(\d+)', (.*), \{actions/g;
let charts = 0;
let failures = 0;
for (const match of html.matchAll(pattern)) {
  charts++;
  try {
    const spec = JSON.parse(match[2].replaceAll('<\\/', '</'));
    const compiled = vegaLite.compile(spec).spec;
    const view = new vega.View(vega.parse(compiled), {renderer: 'none'});
    const svg = await view.toSVG();
    if (!svg.includes('<svg')) throw new Error('no SVG produced');
  } catch (error) {
    failures++;
    console.error(`chart ${match[1]}: ${error.message}`);
  }
}
console.log(`${charts} charts, ${failures} failed`);
process.exit(charts > 0 && failures === 0 ? 0 : 1);
