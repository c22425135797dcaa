#!/usr/bin/env bash
# `retroglass replay T --out X.png --raw X.rgba` writes the framebuffer's bytes as they are
# (issue 23, item 2): the raw file's SHA-256 is the one replay prints, and the PNG read back
# with unassociated alpha holds every byte of it — pixels with alpha 0, 255 and in between
# (OpenImageIO once divided colour by alpha where 0 < alpha < 255).
#   replay_image_check.sh RETROGLASS PNG_COMPARE TRACE WORKDIR
set -euo pipefail
rg="$1" compare="$2" trace="$3" work="$4"
mkdir -p "$work"
line=$("$rg" replay "$trace" --out "$work/frame.png" --raw "$work/frame.rgba" | tail -1)
hash=${line%% *}
size=$(echo "$line" | sed -E 's/.*, ([0-9]+)x([0-9]+).*/\1 \2/')
raw=$(sha256sum "$work/frame.rgba" | cut -d' ' -f1)
[ "$raw" = "$hash" ] || { echo "FAIL: --raw bytes hash $raw, replay printed $hash"; exit 1; }
out=$("$compare" "$work/frame.png" --raw "$work/frame.rgba" $size) || { echo "$out"; echo "FAIL: the PNG does not hold the framebuffer's bytes"; exit 1; }
echo "$out"
echo "$out" | grep -Eq "between: [1-9]" || { echo "FAIL: the trace has no pixel of partial alpha to check"; exit 1; }
rm -rf "$work"
echo "PASS"
