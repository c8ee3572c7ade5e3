#!/usr/bin/env bash
# Phone footage made outside softbench's renderer, to check the measurement
# on what it did not make itself: a still SDR render of a delta (four test
# points, test b slipping 0.1 mm) is shaken by FFmpeg's perspective filter
# (drift 0.5/-0.3 px, tremor 0.08 px RMS, knocks of about 2 px with a roll
# of 0.03-0.05 degrees at 2.0 s, 7.5 s and 14.0 s; 7.5 s is inside b's
# actuated window), converted by zimg (zscale) to HLG BT.2020 10-bit and
# encoded by x265 at 10 Mb/s, as an iPhone records. Then `validate` measures
# it, and each test's displacement is scored against the render's truth.
#   scripts/independent_footage.sh OUT_DIR
# Needs the FFmpeg program (scripts/bootstrap.sh --bench). Prints each
# test's error and the worst; docs/measurement.md quotes them.
set -euo pipefail
command -v ffmpeg >/dev/null || { echo "needs ffmpeg: scripts/bootstrap.sh --bench" >&2; exit 2; }
source "$(dirname "$0")/footage_setup.sh" "$@"

cp "$root/scripts/delta_four_points.plan.yaml" plan.yaml
"$softbench" render --plan plan.yaml --out still_sdr.mp4 --truth truth.csv \
  --plan-out rendered.plan.yaml --resolution 1080p --crf 8 --seed 21 --quiet

# The camera's motion at input frame `in` (30 fps, 585 frames): the content
# moves by (DX, DY) px and turns by R rad about the centre.
dx='(0.5*in/585+0.08*(sin(in*2.1)+sin(in*3.7+1))+2*gte(in\,60)-1.5*gte(in\,225)+1.2*gte(in\,420))'
dy='(-0.3*in/585+0.08*(sin(in*2.9+2)+sin(in*1.3+0.5))+0.5*gte(in\,60)+1.2*gte(in\,225)-1.6*gte(in\,420))'
r='(0.0009*gte(in\,60)-0.0007*gte(in\,225)+0.0005*gte(in\,420))'
shake="perspective=x0=-$dx+$r*(H/2):y0=-$dy-$r*(W/2)"
shake+=":x1=W-$dx+$r*(H/2):y1=-$dy+$r*(W/2)"
shake+=":x2=-$dx-$r*(H/2):y2=H-$dy-$r*(W/2)"
shake+=":x3=W-$dx-$r*(H/2):y3=H-$dy+$r*(W/2):interpolation=cubic:eval=frame"
to_hlg="zscale=rangein=limited:primariesin=bt709:transferin=bt709:matrixin=bt709"
to_hlg+=":transfer=linear:npl=203,format=gbrpf32le"
to_hlg+=",zscale=primaries=bt2020:transfer=arib-std-b67:matrix=bt2020nc"
to_hlg+=":range=limited:npl=203,format=yuv420p10le"
ffmpeg -hide_banner -loglevel error -y -i still_sdr.mp4 -vf "$shake,$to_hlg" \
  -c:v libx265 -preset fast \
  -x265-params "bitrate=10000:vbv-maxrate=12000:vbv-bufsize=20000:log-level=error" \
  -color_primaries bt2020 -color_trc arib-std-b67 -colorspace bt2020nc \
  -color_range tv phone_hlg.mp4

"$softbench" validate --plan rendered.plan.yaml phone_hlg.mp4 --out report --quiet

# Each test's measured displacement against the truth's median over the
# same windows.
"$root/scripts/score_against_truth.py" truth.csv report phone_hlg.mp4
