#!/usr/bin/env bash
# Regenerates assets/meshes/bunny.obj from the npm package "bunny" 1.0.1
# (the Stanford bunny, Stanford Computer Graphics Laboratory).
# Positions are written unchanged; the program rescales meshes at load time.
# Triangles are written with outward (counter-clockwise seen from outside)
# winding: if the package's triangles enclose a negative signed volume,
# every triangle is flipped.
set -euo pipefail

repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
out="$repo/assets/meshes/bunny.obj"
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT

npm install --no-save --no-audit --no-fund --silent --prefix "$tmp" bunny@1.0.1
mkdir -p "$(dirname "$out")"

NODE_PATH="$tmp/node_modules" OUT="$out" node -e '
const fs = require("fs");
const bunny = require("bunny");
const P = bunny.positions, C = bunny.cells;
let vol = 0;
for (const [a, b, c] of C) {
  const [p, q, r] = [P[a], P[b], P[c]];
  vol += (p[0] * (q[1] * r[2] - q[2] * r[1]) -
          p[1] * (q[0] * r[2] - q[2] * r[0]) +
          p[2] * (q[0] * r[1] - q[1] * r[0])) / 6;
}
const flip = vol < 0;
const lines = [
  "# Stanford bunny (Stanford Computer Graphics Laboratory, Stanford 3D Scanning Repository).",
  "# Source: npm package bunny 1.0.1; positions unchanged (the program rescales on load).",
  "# Written by scripts/make_bunny.sh" + (flip ? "; triangles flipped to outward winding." : "."),
  `# ${P.length} vertices, ${C.length} triangles`,
];
for (const p of P) lines.push(`v ${p[0]} ${p[1]} ${p[2]}`);
for (const [a, b, c] of C)
  lines.push(flip ? `f ${a + 1} ${c + 1} ${b + 1}` : `f ${a + 1} ${b + 1} ${c + 1}`);
fs.writeFileSync(process.env.OUT, lines.join("\n") + "\n");
console.log(`wrote ${process.env.OUT}: ${P.length} vertices, ${C.length} triangles, ` +
            `source signed volume ${vol}${flip ? " (flipped)" : ""}`);
'
