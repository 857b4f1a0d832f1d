#!/usr/bin/env bash
# Take a screenshot of the Trundle editor: build the standalone application, run it under a
# virtual X server with the dummy audio backend (no sound card needed; its transport always
# plays, so the ball rolls and the spectrum shows sound), capture the window and write a PNG.
#
# Usage: crates/trundle/screenshot.sh [OUT.png] [WIDTHxHEIGHT]
#   OUT.png        where to write the picture (default: docs/editor.png)
#   WIDTHxHEIGHT   resize the window to this size before the capture (default: the editor's
#                  own default size), to check that the layout scales
#
# CLICK="X,Y" clicks the editor at X,Y (window pixels) before the capture: CLICK=198,383
# shows the MOTION page at the default size (docs/editor-motion.png).
#
# Debian/Ubuntu: installs what it needs with apt-get when it is missing (run as root, or
# install the packages listed below yourself). Honors CARGO_TARGET_DIR.
set -euo pipefail

cd "$(dirname "$0")/../.."
out="${1:-docs/editor.png}"
size="${2:-}"
settle_s="${SETTLE_S:-4}"

need=()
command -v Xvfb >/dev/null || need+=(xvfb)
command -v xwd >/dev/null || need+=(x11-apps)
command -v xwininfo >/dev/null || need+=(x11-utils)
command -v xdotool >/dev/null || need+=(xdotool)
command -v xwdtopnm >/dev/null || need+=(netpbm)
dpkg -s libasound2-dev >/dev/null 2>&1 || need+=(libasound2-dev)
dpkg -s libjack-jackd2-dev >/dev/null 2>&1 || need+=(libjack-jackd2-dev)
# OpenGL for egui under Xvfb (Mesa's software renderer).
dpkg -s libgl1-mesa-dri >/dev/null 2>&1 || need+=(libgl1-mesa-dri libglx-mesa0)
if ((${#need[@]})); then
    echo "installing: ${need[*]}" >&2
    export DEBIAN_FRONTEND=noninteractive
    apt-get update -qq
    apt-get install -y -qq "${need[@]}" >/dev/null
fi

cargo build -p trundle --features standalone --bin trundle-standalone
target_dir="$(cargo metadata --format-version 1 --no-deps |
    sed -n 's/.*"target_directory":"\([^"]*\)".*/\1/p')"
bin="$target_dir/debug/trundle-standalone"

# A free display number (a previous run's server may still be releasing its lock).
n="${SCREENSHOT_DISPLAY:-97}"
while [[ -e "/tmp/.X$n-lock" || -e "/tmp/.X11-unix/X$n" ]]; do n=$((n + 1)); done
display=":$n"
Xvfb "$display" -screen 0 1600x1200x24 -nolisten tcp >/dev/null 2>&1 &
xvfb_pid=$!
app_pid=""
cleanup() {
    [[ -n "$app_pid" ]] && kill "$app_pid" 2>/dev/null || true
    kill "$xvfb_pid" 2>/dev/null || true
    wait 2>/dev/null || true
}
trap cleanup EXIT
export DISPLAY="$display"
for _ in $(seq 50); do
    xwininfo -root >/dev/null 2>&1 && break
    sleep 0.1
done
if ! xwininfo -root >/dev/null 2>&1; then
    echo "Xvfb did not start on $display" >&2
    exit 1
fi

log="$(mktemp)"
"$bin" --backend dummy --sample-rate 48000 --period-size 512 >"$log" 2>&1 &
app_pid=$!

win=""
for _ in $(seq 100); do
    win="$(xdotool search --name '^Trundle$' 2>/dev/null | head -n1 || true)"
    [[ -n "$win" ]] && break
    if ! kill -0 "$app_pid" 2>/dev/null; then
        echo "the standalone exited:" >&2
        cat "$log" >&2
        exit 1
    fi
    sleep 0.2
done
if [[ -z "$win" ]]; then
    echo "no Trundle window appeared" >&2
    cat "$log" >&2
    exit 1
fi
if [[ -n "$size" ]]; then
    xdotool windowsize "$win" "${size%x*}" "${size#*x}"
fi
if [[ -n "${CLICK:-}" ]]; then
    sleep 1
    xdotool mousemove --window "$win" "${CLICK%,*}" "${CLICK#*,}" click 1
fi
# Let the ball roll and the spectrum's smoothing settle.
sleep "$settle_s"

mkdir -p "$(dirname "$out")"
xwd -silent -id "$win" | xwdtopnm 2>/dev/null | pnmtopng >"$out"
echo "wrote $out ($(xwininfo -id "$win" | sed -n 's/.*-geometry \([0-9x]*\).*/\1/p'))"
