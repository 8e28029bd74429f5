#!/usr/bin/env bash
# Fetches the source of Debian's GLU (the package whose tessellator the
# authoring library closes cuts with) into web/.deps/, for the WebAssembly
# build: the same C code as the native build's libGLU, so the page's trees are
# byte for byte the native ones. The source comes from the Debian archive this
# machine already installs from (its own apt sources, read as deb-src, with a
# private package index: the system's apt state is not touched).
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
deps="$PWD/web/.deps"
want="glu-9.0.2"
if [[ -f "$deps/$want/src/libtess/tess.c" ]]; then
  exit 0
fi
mkdir -p "$deps/apt/lists/partial" "$deps/apt/cache/archives/partial"
sources="$deps/apt/sources"
: >"$sources.list"
rm -f "$sources".d-*.sources
# deb822 files (Types: deb) and one-line lists (deb URI ...), turned into deb-src.
n=0
for f in /etc/apt/sources.list.d/*.sources; do
  [[ -f "$f" ]] || continue
  sed -e 's/^Types:.*/Types: deb-src/' "$f" >"$sources.d-$n.sources"
  n=$((n + 1))
done
for f in /etc/apt/sources.list /etc/apt/sources.list.d/*.list; do
  [[ -f "$f" ]] || continue
  sed -n -e 's/^deb \(.*\)/deb-src \1/p' "$f" >>"$sources.list"
done
mkdir -p "$deps/apt/sources.d"
rm -f "$deps/apt/sources.d/"*
for f in "$sources".d-*.sources; do
  [[ -f "$f" ]] && mv "$f" "$deps/apt/sources.d/"
done
apt_opts=(-o "Dir::Etc::SourceList=$sources.list" -o "Dir::Etc::SourceParts=$deps/apt/sources.d"
  -o "Dir::State::Lists=$deps/apt/lists" -o "Dir::Cache=$deps/apt/cache" -o "APT::Sandbox::User=root"
  -o "Debug::NoLocking=1")
echo "web_glu: reading the Debian source index (private to web/.deps)"
apt-get "${apt_opts[@]}" update -qq
cd "$deps"
echo "web_glu: fetching the source of libglu"
apt-get "${apt_opts[@]}" source --download-only libglu >/dev/null 2>"$deps/apt/source.log" || true
orig="$(ls "$deps"/libglu_9.0.2.orig.tar.* 2>/dev/null | head -n 1 || true)"
if [[ -z "$orig" ]]; then
  echo "web_glu: could not fetch libglu's source (see $deps/apt/source.log)" >&2
  exit 1
fi
tar -xf "$orig" -C "$deps"
if [[ ! -f "$deps/$want/src/libtess/tess.c" ]]; then
  echo "web_glu: $orig holds no $want/src/libtess" >&2
  exit 1
fi
echo "web_glu: $want in web/.deps"
