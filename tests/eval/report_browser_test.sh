#!/usr/bin/env bash
# Renders a real `slamkit report` in headless Chromium and checks that its plots are drawn.
#
# usage: report_browser_test.sh SLAMKIT_BINARY SOURCE_DIR WORK_DIR
# The runs come from `slamkit eval` on the KITTI 00 reference files (and two optimizer
# summaries in the documented schema). Exit 77 = skipped (no Chromium, Python 3 or dataset),
# except under CI=true, where a missing prerequisite fails the test.
set -euo pipefail

slamkit=$1
source_dir=$2
work=$3

skip() {
  if [[ "${CI:-}" == "true" ]]; then
    echo "FAIL (CI=true): $1" >&2
    exit 1
  fi
  echo "SKIPPED: $1" >&2
  exit 77
}

chromium=""
for candidate in "${CHROMIUM:-}" chromium chromium-browser google-chrome; do
  if [[ -n "$candidate" ]] && command -v "$candidate" > /dev/null 2>&1; then
    chromium=$(command -v "$candidate")
    break
  fi
done
[[ -n "$chromium" ]] || skip "no Chromium found (install Debian's chromium or set CHROMIUM)"
command -v python3 > /dev/null 2>&1 || skip "python3 not found"

data=${SLAMKIT_DATA:-../shared/datasets}
[[ "$data" = /* ]] || data="$source_dir/$data"
ref="$data/vio/eval_reference/KITTI_00_gt.txt"
est="$data/vio/eval_reference/KITTI_00_ORB.txt"
[[ -f "$ref" && -f "$est" ]] || skip "dataset not found: $ref (set SLAMKIT_DATA)"

rm -rf "$work"
mkdir -p "$work"
cd "$work"

"$slamkit" eval ate "$est" "$ref" --align se3 --label "ORB-SLAM (SE3)" --json ate_se3.json > ate_se3.txt
"$slamkit" eval ate "$est" "$ref" --align sim3 --label "ORB-SLAM (Sim3)" --json ate_sim3.json > /dev/null
"$slamkit" eval rpe "$est" "$ref" --delta 10 --delta-unit m --label "ORB-SLAM" --json rpe_10m.json > /dev/null
"$slamkit" report ate_se3.json ate_sim3.json rpe_10m.json \
  "$source_dir/tests/eval/data/optimize_example.json" "$source_dir/tests/eval/data/optimize_example_gn.json" \
  --title "KITTI 00: ORB-SLAM vs ground truth" -o report.html
grep -q "rmse	1.303450" ate_se3.txt || { echo "FAIL: unexpected APE summary"; cat ate_se3.txt; exit 1; }

profile=$(mktemp -d)
trap 'rm -rf "$profile"' EXIT
flags=(--headless --no-sandbox --disable-gpu --disable-quic --no-first-run --disable-background-networking
       --disable-component-update --disable-sync --hide-scrollbars --user-data-dir="$profile")
timeout 180 "$chromium" "${flags[@]}" --screenshot="$work/report.png" --window-size=1280,2000 \
  "file://$work/report.html" > chromium_screenshot.log 2>&1 || { cat chromium_screenshot.log; exit 1; }
timeout 180 "$chromium" "${flags[@]}" --dump-dom "file://$work/report.html" > dom.html 2> chromium_dom.log \
  || { cat chromium_dom.log; exit 1; }
[[ -s report.png ]] || { echo "FAIL: no screenshot written"; cat chromium_screenshot.log; exit 1; }

# 5 eval runs' worth of figures: APE 5 + 2 along-path, RPE 5 + 1, optimization 2 = 15 <svg>.
python3 "$source_dir/tests/eval/check_report_render.py" report.png dom.html 15 20
echo "report rendered: $work/report.png"
