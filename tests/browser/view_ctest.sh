#!/usr/bin/env bash
# CTest: a one-second hamstrings run, its viewer page written by
# `tissuebench view`, and that page played in headless Chromium (view_test.mjs).
#   view_ctest.sh TISSUEBENCH SOURCE_DIR WORK_DIR
set -euo pipefail
bin=$1 src=$2 work=$3
rm -rf "$work" && mkdir -p "$work"
"$bin" leg "$src/msd/data/scenes/hamstrings.yaml" --duration 1 --obj-every 0 --quiet --out "$work/run" > "$work/leg.log"
"$bin" view "$work/run" --out "$work/view.html"
node "$src/tests/browser/view_test.mjs" --page "$work/view.html" --shots "$work/shots"
