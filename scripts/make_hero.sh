#!/usr/bin/env bash
# Makes the README's hero animation, docs/hero.gif: a scripted volley into
# the showcase, one shot at each object, recorded frame by frame
# (`breakables play --record`) at 1280x720 and turned into a looping GIF by
# ffmpeg (its own 256-colour palette, ordered dithering, only the changed
# rectangle of each frame stored), scaled down for size. Fails if the result
# is 4 MB (4,000,000 bytes) or more.
#
# Usage: scripts/make_hero.sh
# Environment (defaults in brackets):
#   BUILD_DIR     the build directory [build]; configured and built if needed
#   HERO_WIDTH    the animation's width in pixels, its height 16:9 [800]
#   HERO_FPS      frames per second, a divisor of 60 (the game's steps) [30]
#   HERO_SECONDS  how long the run is, 1..20 s [4.5]; the last picture is then
#                 held for HERO_HOLD s [1] before the loop starts again
#   HERO_CAMERA   where the camera stands, X,Y,Z in m, looking at the
#                 showcase's target [0.5,2.1,4.1: nearer than the scene's
#                 own view, and above the shots' paths, so that no ball
#                 fills the picture as it flies past]
#   HERO_FORMAT   gif, or apng for docs/hero.png (full colour, larger) [gif]
# ffmpeg is installed with apt-get if missing (as scripts/setup.sh does).
set -euo pipefail

repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$repo"

build="${BUILD_DIR:-build}"
width="${HERO_WIDTH:-800}"
fps="${HERO_FPS:-30}"
seconds="${HERO_SECONDS:-4.5}"
hold="${HERO_HOLD:-1}"
camera="${HERO_CAMERA:-0.5,2.1,4.1}"
format="${HERO_FORMAT:-gif}"
limit=4000000

fail() {
  echo "make_hero: $*" >&2
  exit 1
}

if ! [[ "$width" =~ ^[0-9]+$ ]] || ((width < 64 || width > 1280)); then
  fail "HERO_WIDTH '$width' is not 64..1280"
fi
if ! [[ "$fps" =~ ^[0-9]+$ ]] || ((fps < 1 || fps > 60 || 60 % fps != 0)); then
  fail "HERO_FPS '$fps' is not a divisor of 60"
fi
[[ "$seconds" =~ ^[0-9]+(\.[0-9]+)?$ ]] || fail "HERO_SECONDS '$seconds' is not a number of seconds"
[[ "$hold" =~ ^[0-9]+(\.[0-9]+)?$ ]] || fail "HERO_HOLD '$hold' is not a number of seconds"
case "$format" in
gif) out="docs/hero.gif" ;;
apng) out="docs/hero.png" ;;
*) fail "HERO_FORMAT '$format' is not gif or apng" ;;
esac
frames="$(awk -v s="$seconds" 'BEGIN { printf "%d", s * 60 + 0.5 }')"
((frames >= 60 && frames <= 1200)) || fail "HERO_SECONDS '$seconds' is not 1..20"
every=$((60 / fps))
# The six shots (the wall, the pillar, the bunny, the egg, the slab, the
# tower's base) within the first two thirds, so that the last third shows
# the debris settling.
volley=$((frames * 2 / 3))
height=$(((width * 9 / 16 + 1) / 2 * 2)) # even: the encoders want it

if ! command -v ffmpeg >/dev/null 2>&1; then
  echo "make_hero: ffmpeg is missing: installing the Debian package ffmpeg (apt-get)"
  sudo=()
  if [[ "$(id -u)" -ne 0 ]]; then
    command -v sudo >/dev/null 2>&1 || fail "not root and sudo is unavailable; install ffmpeg"
    sudo=(sudo)
  fi
  "${sudo[@]}" env DEBIAN_FRONTEND=noninteractive apt-get update
  "${sudo[@]}" env DEBIAN_FRONTEND=noninteractive apt-get install -y --no-install-recommends ffmpeg
fi

if [[ ! -f "$build/CMakeCache.txt" ]]; then
  cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release
fi
cmake --build "$build" --target breakables -j2

work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
display=()
if [[ -z "${DISPLAY:-}" ]]; then
  display=(xvfb-run -a -s "-screen 0 1280x720x24") # no screen: a virtual one
fi
echo "make_hero: recording $frames frames of the showcase (one in $every: $fps fps), camera $camera"
"${display[@]}" "$build/breakables" play --scene showcase --frames "$frames" --autofire 6 --volley "$volley" \
  --hide-panel --hide-hud --width 1280 --height 720 --camera "$camera" \
  --record "$work/frames" --record-every "$every"
pictures="$(find "$work/frames" -name 'frame_*.png' | wc -l)"
((pictures > 0)) || fail "the run recorded no frames"

# Scaled with Lanczos from 1280x720: the game draws without multisampling,
# so the smaller picture is also the smoother one. The last picture is held.
scale="scale=${width}:${height}:flags=lanczos,tpad=stop_mode=clone:stop_duration=${hold}"
input=(-loglevel error -y -framerate "$fps" -i "$work/frames/frame_%05d.png")
mkdir -p docs
if [[ "$format" == gif ]]; then
  ffmpeg "${input[@]}" -vf "$scale,palettegen=max_colors=256:stats_mode=full" "$work/palette.png"
  ffmpeg "${input[@]}" -i "$work/palette.png" \
    -lavfi "${scale}[v];[v][1:v]paletteuse=dither=bayer:bayer_scale=4:diff_mode=rectangle" \
    -loop 0 "$work/hero.gif"
else
  ffmpeg "${input[@]}" -vf "$scale" -plays 0 -f apng "$work/hero.png"
fi
made="$work/$(basename "$out")"

bytes="$(stat -c %s "$made")"
duration="$(awk -v n="$pictures" -v f="$fps" -v h="$hold" 'BEGIN { printf "%.2f", n / f + h }')"
echo "make_hero: $out: $bytes bytes ($(awk -v b="$bytes" 'BEGIN { printf "%.2f", b / 1e6 }') MB)," \
  "${width}x${height}, $pictures pictures at $fps fps and ${hold} s held: ${duration} s"
# Too large: refused, and the animation already there is kept.
((bytes < limit)) ||
  fail "$out would be $bytes bytes, not under 4 MB (left as it was): lower HERO_WIDTH, HERO_FPS or HERO_SECONDS"
mv "$made" "$out"
