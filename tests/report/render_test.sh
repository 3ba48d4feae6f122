#!/usr/bin/env bash
# Report.RendersInHeadlessChromium: runs the tiny tier (tests/report/tiny.yaml)
# through `tissuebench suite`, opens DIR/report/index.html in headless Chromium
# and checks that every image loaded (the page records loaded/total images on
# <body data-images>) and that the console stayed silent; checks summary.md;
# keeps a screenshot (OUT/screenshot.png) for a person to look at. Two negative
# controls - the same page with a missing image, and with a console error -
# must each be caught, so each check can fail.
# Usage: render_test.sh TISSUEBENCH SOURCE_ROOT OUT_DIR
set -euo pipefail
tb="$1" root="$2" out="$3"
rm -rf "$out"
mkdir -p "$out"
"$tb" suite --tier "$root/tests/report/tiny.yaml" --out "$out/suite" --quiet > "$out/suite.log" 2>&1 ||
  { cat "$out/suite.log"; echo "FAIL: the suite did not run"; exit 1; }

chrome() {
  timeout 120 chromium --headless --no-sandbox --disable-gpu --disable-background-networking \
    --user-data-dir="$out/profile" "$@"
}

# check_page FILE: 0 when every image loaded and the console printed nothing.
check_page() {
  local page="$1" dom="$out/dom.html" log="$out/console.log"
  chrome --enable-logging=stderr --v=0 --virtual-time-budget=10000 --dump-dom "file://$page" > "$dom" 2> "$log" || true
  local images
  images=$(grep -o 'data-images="[^"]*"' "$dom" | head -n 1 | sed 's/data-images="\(.*\)"/\1/')
  local loaded="${images%/*}" total="${images#*/}"
  if [[ -z "$images" || "$images" == "pending" || "$loaded" != "$total" || "$total" == "0" ]]; then
    echo "images loaded: '${images}' in $page"
    return 1
  fi
  if grep -q "CONSOLE" "$log"; then
    echo "console output in $page:"
    grep "CONSOLE" "$log"
    return 1
  fi
  echo "ok: $images images loaded, console silent ($page)"
}

report="$out/suite/report/index.html"
[[ -f "$report" ]] || { echo "FAIL: no $report"; exit 1; }
check_page "$report" || { echo "FAIL: the report does not render cleanly"; exit 1; }
grep -q "^| tiny_uniaxial |" "$out/suite/report/summary.md" || { echo "FAIL: summary.md lacks the accuracy table"; exit 1; }
grep -q "git " "$out/suite/report/summary.md" || { echo "FAIL: summary.md lacks the provenance"; exit 1; }
chrome --window-size=1200,4200 --screenshot="$out/screenshot.png" "file://$report" > /dev/null 2>&1 || true
[[ -s "$out/screenshot.png" ]] || { echo "FAIL: no screenshot"; exit 1; }
echo "screenshot: $out/screenshot.png"

# Negative controls, one fault per page so each check is shown to fail on its
# own: a missing image, and a console error on a page whose images all load.
sed -e 's|</body>|<img src="missing.png" alt="missing"></body>|' "$report" > "$out/suite/report/broken_image.html"
sed -e 's|</body>|<script>console.error("deliberate")</script></body>|' "$report" > "$out/suite/report/console_error.html"
for control in broken_image console_error; do
  if check_page "$out/suite/report/$control.html" > "$out/control_$control.log"; then
    cat "$out/control_$control.log"
    echo "FAIL: the check passed the negative control $control.html"
    exit 1
  fi
  echo "ok: the negative control $control was caught: $(head -n 1 "$out/control_$control.log")"
done
