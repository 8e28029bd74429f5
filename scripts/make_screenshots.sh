#!/usr/bin/env bash
# Remakes the README's pictures of the game: one per scene after its
# scripted shots, the glass bunny breaking, dust close up, the HUD, the
# panel, the editor. Every picture is a scripted run (the same frames each
# time), 1280x720 under xvfb-run, so a change to the look shows up as a
# change to these files. Usage: scripts/make_screenshots.sh [BUILD_DIR]
# (default build/, a Release build of `breakables`).
set -euo pipefail

repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${1:-$repo/build}"
exe="$build/breakables"
out="$repo/docs/screenshots"
if [[ ! -x "$exe" ]]; then
  echo "make_screenshots: no $exe; build first (cmake -S . -B build -DCMAKE_BUILD_TYPE=Release && cmake --build build)" >&2
  exit 2
fi
command -v xvfb-run >/dev/null || { echo "make_screenshots: xvfb-run is missing (apt-get install xvfb)" >&2; exit 2; }
mkdir -p "$out"

shot() { # NAME ARGS...: one scripted run into docs/screenshots/NAME.png
  local name="$1"
  shift
  echo "== $name: breakables $*"
  xvfb-run -a -s "-screen 0 1280x720x24" "$exe" "$@" --width 1280 --height 720 --screenshot "$out/$name.png"
}

# Every scene after its scripted shots (the HUD hidden: it is pictured once, below).
shot scene_showcase play --scene showcase --frames 480 --autofire 20 --volley 360 --hide-panel --hide-hud
shot scene_wall play --scene wall --frames 82 --autofire 3 --hide-panel --hide-hud
shot scene_pillar play --scene pillar --frames 120 --autofire 3 --hide-panel --hide-hud
shot scene_slab play --scene slab --frames 120 --autofire 3 --hide-panel --hide-hud
shot scene_eggshell play --scene eggshell --frames 90 --autofire 2 --hide-panel --hide-hud
shot scene_bunny play --scene bunny --frames 90 --autofire 2 --hide-panel --hide-hud
shot scene_torus play --scene torus --frames 90 --autofire 2 --hide-panel --hide-hud
shot scene_tower play --scene tower --frames 160 --autofire 3 --volley 120 --hide-panel --hide-hud
# The bridge and the balcony as they are: their own shots bring them down.
shot scene_bridge play --scene bridge --frames 175 --autofire 3 --volley 120 --hide-panel --hide-hud
shot scene_balcony play --scene balcony --frames 160 --autofire 3 --volley 120 --hide-panel --hide-hud
# The glass bunny a few frames after the shot, its shards in the air; dust
# close up a moment after a hit on the slab; the HUD as a player first sees it.
shot glass_breaking play --scene bunny --frames 36 --autofire 1 --hide-panel --hide-hud
shot dust_close play --scene slab --frames 60 --autofire 2 --hide-panel --hide-hud
shot hud play --scene wall --frames 40 --hide-panel
# The top of the README.
shot wall_break play --scene wall --frames 82 --autofire 3 --hide-panel --hide-hud
shot panel play --scene showcase --frames 300 --autofire 8 --volley 200 --hide-hud
# Structures under stress (README section of that name).
shot stress_tower_falling play --scene tower --frames 160 --autofire 3 --volley 120 --hide-panel --hide-hud
shot stress_bridge_breaking play --scene bridge --frames 175 --autofire 3 --volley 120 --hide-panel --hide-hud
shot stress_bridge_weight play --scene bridge --drop 20000 --frames 132 --hide-panel --hide-hud
shot stress_overlay play --scene bridge --frames 40 --overlay stress --hide-panel --hide-hud
echo "make_screenshots: wrote $(ls "$out" | wc -l) pictures in $out"
