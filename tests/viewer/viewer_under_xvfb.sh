#!/usr/bin/env bash
# The viewer tested like a user: start it in an Xvfb display, drive it with key presses
# (xdotool), take a screenshot (F12), quit (Esc); then replay the recorded input headless
# and require (1) every frame's hash to match the window's, (2) the screenshot's emulated
# framebuffer to equal the headless frame byte for byte, and (3) the window's pixels over
# the framebuffer region to equal that frame's RGB.
#
#   viewer_under_xvfb.sh RETROGLASS PNG_COMPARE WORKDIR [DEMO WIDTH HEIGHT [SCENE]]
# DEMO defaults to pem at 640×480; tir (the programmable profile) runs at 512×512,
# impostors at 600×600 (and must record the mover stepped by = and -).
# WORKDIR (the build folder's, so never another checkout's) keeps out/pem, the quick
# precompute made by the first run and read by the later ones, and run-PID/, this run's
# recording, screenshots and replay: removed when the run passes, kept when it fails.
# Runs on one WORKDIR at the same time (two ctest runs in one build folder) take turns
# (flock): the first would be writing out/pem while the second read it.
set -euo pipefail
rg="$1"
compare="$2"
work="$3"
demo="${4:-pem}"
width="${5:-640}"
height="${6:-480}"
scene=()
[ -n "${7:-}" ] && scene=(--scene "$7")

fail() {
    echo "FAIL: $*" >&2
    [ -z "${run:-}" ] || echo "this run's files are kept in $work/$run" >&2
    exit 1
}
for tool in Xvfb xdotool; do
    command -v "$tool" >/dev/null ||
        fail "'$tool' is not installed. Install the Debian packages xvfb xdotool" \
             "(./retroglass installs them); this test does not skip."
done

mkdir -p "$work"
cd "$work"
exec 9>lock  # held until this script exits (the background processes below close it)
flock 9
run="run-$$"
rm -rf "$run" && mkdir "$run"

# ---- a display of our own: Xvfb picks a free number and writes it when it is ready ------
exec 5> "$run"/display
Xvfb -displayfd 5 -screen 0 1280x1024x24 -nolisten tcp >"$run"/xvfb.log 2>&1 9>&- &
xvfb=$!
exec 5>&-
viewer=
cleanup() {
    [ -n "$viewer" ] && kill "$viewer" 2>/dev/null || true
    kill "$xvfb" 2>/dev/null || true
}
trap cleanup EXIT
for _ in $(seq 1 200); do
    [ -s "$run"/display ] && break
    kill -0 "$xvfb" 2>/dev/null || fail "Xvfb exited: $(cat "$run"/xvfb.log)"
    sleep 0.1
done
[ -s "$run"/display ] || fail "Xvfb did not report a display"
export DISPLAY=":$(head -1 "$run"/display)"
echo "Xvfb on $DISPLAY"

# ---- the window, driven by keys ------------------------------------------------------------
# --frames bounds the run should the keys never arrive (then the checks below fail).
"$rg" view "$demo" "${scene[@]}" --record "$run"/input.txt --shots "$run"/shots --frames 600 >"$run"/view.log 2>&1 9>&- &
viewer=$!
wid=$(xdotool search --sync --onlyvisible --name "retroglass view $demo" | head -1)
[ -n "$wid" ] || fail "no viewer window appeared"
xdotool windowfocus --sync "$wid"
# Between two samples (3 passes), a sample step, off the plane of the samples; a left
# drag (orbit) and a wheel notch (dolly) over the framebuffer; a screenshot.
xdotool key --delay 50 Right Right Page_Up Right Up Up
# - and = step the demo's first continuous parameter (impostors: the moving piece).
xdotool key --delay 50 equal equal minus
xdotool mousemove --window "$wid" 320 240 mousedown 1 mousemove --window "$wid" 300 230 \
    mousemove --window "$wid" 290 236 mouseup 1 click 4
xdotool key --delay 50 F12 Escape
wait "$viewer" || { cat "$run"/view.log; fail "the viewer exited with an error"; }
viewer=
cat "$run"/view.log

grep -q " screenshot$" "$run"/input.txt || fail "no screenshot in the recording (keys not delivered?)"
grep -q " orbit " "$run"/input.txt || fail "no orbit in the recording (keys not delivered?)"
if [ "$demo" = impostors ]; then
    grep -q " param mover " "$run"/input.txt || fail "no mover step in the recording (- and = not bound?)"
fi
grep -q " dolly " "$run"/input.txt || fail "no dolly in the recording (wheel not delivered?)"
shot=$(ls "$run"/shots/"${demo}"_*.png | grep -v _window | head -1)
frame=$(basename "$shot" .png | sed "s/${demo}_//")
[ -f "$run/shots/${demo}_${frame}_window.png" ] || fail "no window screenshot"

# ---- headless replay -----------------------------------------------------------------------
"$rg" view "$demo" --replay "$run"/input.txt --headless --out "$run"/replay ||
    fail "headless replay differs from the window (frame hashes above)"
"$compare" "$shot" "$run/replay/screenshot_${frame}.png" ||
    fail "screenshot framebuffer != headless frame $frame; reproduce: $rg view $demo --replay $work/$run/input.txt --headless --out $work/$run/replay-again"
"$compare" "$run/shots/${demo}_${frame}_window.png" "$run/replay/screenshot_${frame}.png" --rgb --crop "$width" "$height" ||
    fail "window pixels over the framebuffer region != emulated framebuffer RGB"
echo "PASS: window frame $frame == headless replay, $(grep -c hash "$run"/input.txt) frame hashes equal"
cd "$work" && rm -rf "$run"
