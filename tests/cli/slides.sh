#!/usr/bin/env bash
# scripts/slides: one PNG per preset (in lecture order) and a handout page that shows
# every one of them with its title and caption.
set -euo pipefail
accelviz=$1; out=$2
repo=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
rm -rf "$out"
"$repo/scripts/slides" --accelviz "$accelviz" --out "$out" --width 480 --height 270
index="$out/index.html"
presets=("$repo"/assets/presets/*.json)
images=$(grep -c '<img src=' "$index")
if [ "$images" -ne "${#presets[@]}" ]; then
  echo "FAIL: $images slides in the page, ${#presets[@]} presets"; exit 1
fi
number=0
for preset in "${presets[@]}"; do
  number=$((number + 1))
  name=$(basename "$preset" .json)
  png="$out/$name.png"
  if [ "$(head -c 8 "$png" | od -An -tx1 | tr -d ' \n')" != "89504e470d0a1a0a" ]; then
    echo "FAIL: $png is not a PNG"; exit 1
  fi
  title=$(python3 -c 'import html, json, sys; print(html.escape(json.load(open(sys.argv[1]))["title"]))' "$preset")
  if ! grep -qF "<h2>$number. $title</h2>" "$index"; then
    echo "FAIL: slide $number ($name) is not in the page with its title: $title"; exit 1
  fi
  caption=$(python3 -c 'import html, json, sys; print(html.escape(json.load(open(sys.argv[1])).get("caption", "")))' "$preset")
  if [ -n "$caption" ] && ! grep -qF "<p class=\"caption\">$caption</p>" "$index"; then
    echo "FAIL: slide $number ($name) is not in the page with its caption: $caption"; exit 1
  fi
done
# The slides come in file-name order.
order=$(grep -o '<section id="[^"]*"' "$index" | sed 's/.*id="//; s/"//')
if [ "$order" != "$(for p in "${presets[@]}"; do basename "$p" .json; done)" ]; then
  echo "FAIL: the page's order is not the presets' file-name order"; exit 1
fi
echo "ok: ${#presets[@]} slides"
