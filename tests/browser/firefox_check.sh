#!/usr/bin/env bash
# A manual check (not in CTest: the setup does not install Firefox): the
# viewer page plays in Firefox from a local file. Firefox runs in a real window
# on a virtual X display (Xvfb; its headless mode gives no WebGL without a
# GPU); two screenshots of the display 1.5 s apart must differ.
#   apt-get install firefox-esr xvfb x11-apps imagemagick
#   tests/browser/firefox_check.sh PAGE.html OUT_DIR
set -euo pipefail
page=$(realpath "$1") out=$2
mkdir -p "$out"
profile=$(mktemp -d)
printf 'user_pref("webgl.force-enabled", true);\nuser_pref("browser.shell.checkDefaultBrowser", false);\n' > "$profile/user.js"
display=:$((70 + RANDOM % 20))
Xvfb "$display" -screen 0 1000x800x24 >/dev/null 2>&1 &
xvfb=$!
trap 'kill $xvfb ${ff:-} 2>/dev/null; rm -rf "$profile"' EXIT
sleep 2
DISPLAY=$display firefox-esr --no-remote --profile "$profile" --new-window "file://$page" >/dev/null 2>&1 &
ff=$!
sleep 25
DISPLAY=$display xwd -root -silent | convert xwd:- "$out/firefox_a.png"
sleep 1.5
DISPLAY=$display xwd -root -silent | convert xwd:- "$out/firefox_b.png"
changed=$(compare -metric AE "$out/firefox_a.png" "$out/firefox_b.png" null: 2>&1 || true)
echo "firefox: $(firefox-esr --version 2>/dev/null); pixels changed in 1.5 s: $changed (screenshots in $out)"
[ "${changed%%.*}" -gt 1000 ]
