#!/usr/bin/env bash
# Checks a `kiln report cs184` page in a real browser and screenshots it: headless Chromium (Debian
# package `chromium`, not in tools/setup.sh: only this check needs it) loads the page, a script
# counts the images that failed to load, and the page is captured as a PNG.
#   tools/cs184_report_screenshot.sh DIR/index.html OUT.png [WIDTH HEIGHT]
# Exit 0: the page loaded and every image in it decoded; 1: some did not (listed); 2: usage.
set -euo pipefail
if [ $# -lt 2 ]; then
  echo "usage: $0 PAGE.html OUT.png [WIDTH HEIGHT]" >&2
  exit 2
fi
page=$(realpath "$1")
out=$2
width=${3:-1400}
height=${4:-4000}
browser=$(command -v chromium || command -v chromium-browser || true)
if [ -z "$browser" ]; then
  echo "$0: needs Chromium: apt-get install chromium" >&2
  exit 2
fi
flags=(--headless --no-sandbox --disable-gpu --hide-scrollbars --allow-file-access-from-files
  --virtual-time-budget=20000 --run-all-compositor-stages-before-draw)

# A copy of the page beside it (same folder: the images' relative paths hold) with a script that
# writes into the DOM how many images there are and which did not decode.
check="$(dirname "$page")/.kiln-check-$$.html"
trap 'rm -f "$check"' EXIT
sed 's|</body>|<script>addEventListener("load",()=>{const bad=[...document.images].filter(i=>!i.complete\|\|i.naturalWidth===0).map(i=>i.getAttribute("src"));const p=document.createElement("pre");p.id="kiln-check";p.textContent="IMAGES "+document.images.length+" BROKEN "+bad.length+" "+bad.join(" ");document.body.appendChild(p);});</script></body>|' \
  "$page" >"$check"
dom=$("$browser" "${flags[@]}" --dump-dom "file://$check" 2>/dev/null)
result=$(grep -o 'IMAGES [0-9]* BROKEN [0-9]*[^<]*' <<<"$dom" || true)
if [ -z "$result" ]; then
  echo "$0: $page: the page did not load (no check result in the DOM)" >&2
  exit 1
fi
echo "$page: $result"
"$browser" "${flags[@]}" --window-size="$width,$height" --screenshot="$(realpath -m "$out")" \
  "file://$page" 2>/dev/null
[ -s "$out" ] || { echo "$0: no screenshot written to $out" >&2; exit 1; }
echo "screenshot: $out"
read -r _ images _ broken _ <<<"$result"
[ "$images" -gt 0 ] && [ "$broken" -eq 0 ]
