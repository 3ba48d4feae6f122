#!/usr/bin/env bash
# Report.RendersInHeadlessChromium: runs the tiny tier (tests/report/tiny.yaml)
# through `tissuebench suite`, opens DIR/report/index.html in headless Chromium
# and checks that every image loaded (the page records loaded/total images on
# <body data-images>) and that the console stayed silent; checks summary.md;
# keeps a screenshot (OUT/screenshot.png) for a person to look at. A negative
# control - the same page with a missing image and a console error - must be
# caught, so the check itself can fail.
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

# Negative control: a broken image and a console error must both be caught.
sed -e 's|</body>|<img src="missing.png" alt="missing"><script>console.error("deliberate")</script></body>|' \
  "$report" > "$out/suite/report/broken.html"
if check_page "$out/suite/report/broken.html" > "$out/control.log"; then
  cat "$out/control.log"
  echo "FAIL: the check passed a page with a missing image and a console error"
  exit 1
fi
echo "ok: the negative control was caught"
