// The native build's side of the browser test: the tree hashes every build
// must give (tests/tree_hashes.txt, or the native CLI itself when it is
// built), and its times for the speed comparison (the CLI's fracture --json
// `ms`, and tests/web/split_native.c built against the same build's libraries).
import { execFileSync } from 'node:child_process';
import { existsSync, mkdtempSync, readFileSync, rmSync, statSync, writeFileSync } from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import { repo } from './browser.mjs';

/// The lines of tests/tree_hashes.txt: {hash, args: ['--mesh', 'bunny', ...]}.
export function treeHashTable() {
  const file = path.join(repo, 'tests', 'tree_hashes.txt');
  return readFileSync(file, 'utf8')
    .split('\n')
    .map((l) => l.trim())
    .filter((l) => l && !l.startsWith('#'))
    .map((l) => {
      const [hash, ...args] = l.split(/\s+/);
      return { hash, args };
    });
}

/// The table's hash for exactly these fracture arguments, or null.
export function tableHash(args) {
  const key = args.join(' ');
  const row = treeHashTable().find((r) => r.args.join(' ') === key);
  return row ? row.hash : null;
}

/// The build type ('Release', 'Debug', ...) of the native build in dir, or null when it has none.
export function nativeBuildType(nativeDir) {
  try {
    const cache = readFileSync(path.join(nativeDir, 'CMakeCache.txt'), 'utf8');
    const m = cache.match(/^CMAKE_BUILD_TYPE:STRING=(.*)$/m);
    return m ? m[1] || 'none' : 'none';
  } catch {
    return null;
  }
}

/// `breakables fracture ARGS --json` of the native CLI, parsed; null when it is not built.
export function nativeFracture(exe, args) {
  if (!existsSync(exe)) return null;
  const out = execFileSync(exe, ['fracture', ...args, '--json'], { encoding: 'utf8', timeout: 120000 });
  return JSON.parse(out);
}

/// `breakables fracture --mesh FILE ARGS --json` of a model given as text (written to a temporary folder).
export function nativeFractureFile(exe, name, text, args) {
  if (!existsSync(exe)) return null;
  const dir = mkdtempSync(path.join(os.tmpdir(), 'breakables-web-test-'));
  try {
    const file = path.join(dir, name);
    writeFileSync(file, text);
    return nativeFracture(exe, ['--mesh', file, ...args]);
  } finally {
    rmSync(dir, { recursive: true, force: true });
  }
}

/// The median of `runs` runs of the native fracture's own time (`ms`).
export function nativeFractureMs(exe, args, runs) {
  const times = [];
  for (let i = 0; i < runs; ++i) times.push(nativeFracture(exe, args).ms);
  return median(times);
}

export function median(values) {
  const v = [...values].sort((a, b) => a - b);
  const n = v.length;
  return n % 2 ? v[(n - 1) / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

const newer = (a, b) => statSync(a).mtimeMs > statSync(b).mtimeMs;

/// Builds tests/web/split_native.c against the static libraries of the native
/// build in nativeDir (into nativeDir/web_split_native, again when the source
/// or a library is newer). Returns {exe} or {skipped: reason}.
export function buildSplitNative(nativeDir) {
  const libs = ['libbreakables-runtime.a', 'libbreakables-authoring.a'].map((l) => path.join(nativeDir, l));
  const missing = libs.find((l) => !existsSync(l));
  if (missing) return { skipped: `no ${path.relative(repo, missing)} (build the native libraries)` };
  const source = path.join(repo, 'tests', 'web', 'split_native.c');
  const exe = path.join(nativeDir, 'web_split_native');
  if (existsSync(exe) && !newer(source, exe) && !libs.some((l) => newer(l, exe))) return { exe };
  // What breakables-authoring.pc gives as its private dependencies: GLU, assimp, meshoptimizer, threads.
  let extra;
  try {
    extra = execFileSync('pkg-config', ['--libs', 'glu', 'assimp'], { encoding: 'utf8' }).trim().split(/\s+/);
  } catch {
    return { skipped: 'pkg-config finds no glu or assimp' };
  }
  const args = ['-O2', '-std=c11', '-D_POSIX_C_SOURCE=200809L', '-I', path.join(repo, 'include'), source, ...libs];
  try {
    execFileSync('cc', [...args, ...extra, '-lmeshoptimizer', '-lm', '-pthread', '-o', exe], {
      encoding: 'utf8',
      stdio: ['ignore', 'pipe', 'pipe'],
    });
  } catch (e) {
    return { skipped: `split_native.c does not build: ${String(e.stderr || e.message).split('\n')[0]}` };
  }
  return { exe };
}

/// The native split measurement (see split_native.c), parsed.
export function nativeSplit(exe, pieces, seed, runs) {
  const out = execFileSync(exe, [String(pieces), String(seed), String(runs)], { encoding: 'utf8', timeout: 300000 });
  return JSON.parse(out);
}
