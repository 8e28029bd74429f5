// The browser test of the page (web/dist, built by scripts/web.sh): Debian's
// chromium, headless with WebGL2 on SwiftShader, driven by puppeteer-core.
//   node tests/web/browser_test.mjs [--screenshot FILE.png] [--json FILE.json]
//        [--dist DIR] [--chromium PATH] [--native PATH] [--frames N]
// Checks (each failure ends the test with one line saying why, exit 1):
//   - every page loads with no console error or warning (the page's or its
//     workers'), no uncaught exception, no failed request and no request that
//     leaves 127.0.0.1;
//   - ?scene=wall&autofire=3&frames=N: bonds break and the wall is in more
//     bodies than at the start;
//   - a dropped OBJ fractures (new tree hash, its fragments in #stats), and a
//     file that is no model gives a one-line error while the page runs on;
//   - the bunny into 256 pieces (seed 3000) built by the page has the native
//     tree hash (the native CLI's when build/breakables exists, else
//     tests/tree_hashes.txt), and so do the table's other fractures built by
//     the module in the page;
//   - the screenshot (after the wall's three shots) shows a scene, not a blank canvas.
// Measures and prints (reported, not checked: the machine is shared): fps
// after the three shots, the bunny's fracture in the page against the native
// CLI, and the split of the 1,024-fragment wall in the page against
// tests/web/split_native.c; --json writes these numbers.
import { existsSync, mkdirSync, writeFileSync } from 'node:fs';
import path from 'node:path';
import { launchBrowser, openPage, readStats, repo, startServer, waitForStats } from './browser.mjs';
import { frameRate, moduleBunnyFracture, moduleSplit, moduleTreeHashes, stopAnimation } from './in_page.mjs';
import {
  buildSplitNative,
  nativeBuildType,
  nativeFracture,
  nativeFractureFile,
  nativeFractureMs,
  nativeSplit,
  tableHash,
  treeHashTable,
} from './native.mjs';
import { decodePng, pictureStats } from './png.mjs';

const BUNNY_ARGS = ['--mesh', 'bunny', '--pieces', '256', '--seed', '3000'];
const SPLIT_PIECES = 1024;
const SPLIT_RUNS = 30;
const FRACTURE_RUNS = 5;
// A unit cube: 8 corners, 12 outward triangles.
const CUBE_OBJ = `# a unit cube
v 0 0 0
v 1 0 0
v 1 1 0
v 0 1 0
v 0 0 1
v 1 0 1
v 1 1 1
v 0 1 1
f 1 4 3
f 1 3 2
f 5 6 7
f 5 7 8
f 1 2 6
f 1 6 5
f 4 8 7
f 4 7 3
f 1 5 8
f 1 8 4
f 2 3 7
f 2 7 6
`;

class TestFailure extends Error {}
function check(condition, message) {
  if (!condition) throw new TestFailure(message);
}

function parseArgs(argv) {
  const opts = {
    screenshot: null,
    json: null,
    dist: path.join(repo, 'web', 'dist'),
    chromium: '/usr/bin/chromium',
    native: path.join(repo, 'build', 'breakables'),
    frames: 600,
  };
  for (let i = 0; i < argv.length; ++i) {
    const value = () => {
      if (i + 1 >= argv.length) throw new TestFailure(`${argv[i]} wants a value`);
      return argv[++i];
    };
    const a = argv[i];
    if (a === '--screenshot') opts.screenshot = path.resolve(value());
    else if (a === '--json') opts.json = path.resolve(value());
    else if (a === '--dist') opts.dist = path.resolve(value());
    else if (a === '--chromium') opts.chromium = value();
    else if (a === '--native') opts.native = path.resolve(value());
    else if (a === '--frames') {
      opts.frames = Number(value());
      // The page fires its scripted shots at frames 30, 90 and 150: the third needs time to land.
      if (!Number.isInteger(opts.frames) || opts.frames < 300) throw new TestFailure('--frames wants an integer >= 300');
    } else throw new TestFailure(`unknown option '${a}'`);
  }
  return opts;
}

const say = (line) => process.stdout.write(`browser test: ${line}\n`);
const round = (x, digits = 2) => (typeof x === 'number' && Number.isFinite(x) ? Number(x.toFixed(digits)) : null);

/// Opens `query` in a new page and waits until it is ready; `pages` collects every page for the final problem check.
async function open(ctx, query, what, timeoutMs = 120000) {
  const p = await openPage(ctx.browser, ctx.origin);
  ctx.pages.push({ what, ...p });
  await p.page.goto(`${ctx.origin}/${query}`, { waitUntil: 'load', timeout: timeoutMs });
  const stats = await waitForStats(p.page, `${what}: the page becomes ready`, (s) => s.ready === true, timeoutMs, {
    problems: p.problems,
  });
  return { ...p, stats };
}

function noProblems(ctx) {
  for (const p of ctx.pages)
    check(p.problems.length === 0, `${p.what}: ${p.problems[0]}${p.problems.length > 1 ? ` (and ${p.problems.length - 1} more)` : ''}`);
  const served = ctx.server.log.filter((l) => /^serve: \d{3} /.test(l));
  check(served.length === 0, `the server answered ${served[0]}`);
}

/// The page still animates: its frame count moves on within 10 s.
async function stillRunning(page, what) {
  const before = (await readStats(page)).frames;
  await waitForStats(page, `${what}: the page runs on`, (s) => s.frames > before, 10000, { allowError: true });
}

async function checkLoad(ctx) {
  const { page, stats } = await open(ctx, '', 'the page with no parameters');
  for (const key of ['fps', 'bodies', 'fragments', 'bonds_broken', 'physics_ms', 'break_ms', 'fracture_ms', 'tree_hash', 'frames'])
    check(key in stats, `#stats has no '${key}' (it has ${Object.keys(stats).join(', ')})`);
  check(/^[0-9a-f]{16}$/.test(stats.tree_hash), `#stats tree_hash '${stats.tree_hash}' is not 16 hex digits`);
  await stillRunning(page, 'the page with no parameters');
  // Closed, so that it takes no frames from the measured pages.
  await page.close();
  say(`loads: scene ${stats.scene}, ${stats.fragments} fragments, tree ${stats.tree_hash}`);
}

async function checkWall(ctx, opts) {
  const what = `?scene=wall&autofire=3&frames=${opts.frames}`;
  const { page, stats: start } = await open(ctx, what, what);
  const shot = await waitForStats(page, `${what}: three shots fired`, (s) => s.shots >= 3, 180000);
  // The frame rate with the debris of three shots in flight.
  const rafFps = await frameRate(page, 2000);
  const during = await readStats(page);
  const end = await waitForStats(page, `${what}: ${opts.frames} frames stepped`, (s) => s.done === true, 300000);
  check(end.frames >= opts.frames, `${what}: done after ${end.frames} frames`);
  check(end.bonds_broken > 0, `${what}: no bond broke (bonds_broken ${end.bonds_broken})`);
  check(end.bodies > start.bodies, `${what}: ${end.bodies} bodies at the end, ${start.bodies} at the start: nothing came loose`);
  ctx.numbers.wall = {
    bodies_start: start.bodies,
    bodies_end: end.bodies,
    bonds_broken: end.bonds_broken,
    fps_after_three_shots: round(during.fps, 1),
    raf_fps_after_three_shots: round(rafFps, 1),
    physics_ms: round(during.physics_ms, 3),
    break_ms: round(end.break_ms, 3),
    frames: end.frames,
    stats_after_three_shots: during,
    stats_end: end,
  };
  say(
    `wall: ${end.bonds_broken} bonds broken, bodies ${start.bodies} -> ${end.bodies}; ` +
      `after three shots ${round(during.fps, 1)} fps (#stats), ${round(rafFps, 1)} animation frames/s` +
      ` (the third shot seen at frame ${shot.frames})`,
  );
  await screenshot(ctx, page, opts);
  return page;
}

async function screenshot(ctx, page, opts) {
  const png = await page.screenshot({ type: 'png' });
  const pic = pictureStats(decodePng(png));
  // The scene's sky is its commonest colour (28% of the wall's picture); with the
  // canvas hidden, the page's background covers 91%.
  const share = `${Math.round(pic.topShare * 100)}%`;
  check(pic.colours >= 64 && pic.topShare < 0.6, `the screenshot looks blank: ${pic.colours} colours, the commonest covers ${share}`);
  if (opts.screenshot) {
    mkdirSync(path.dirname(opts.screenshot), { recursive: true });
    writeFileSync(opts.screenshot, png);
    say(`screenshot: ${opts.screenshot} (${pic.colours} colours, the commonest ${share})`);
  }
}

/// Drops on a page in real time (?scene=wall, no frame limit: its frames move on).
async function checkDrop(ctx, opts) {
  const what = '?scene=wall (drops)';
  const { page, stats: before } = await open(ctx, '?scene=wall', what);
  const drop = (name, bytes) =>
    page.evaluate(
      async (name, bytes) => {
        try {
          await window.breakablesPage.dropFile(name, new Uint8Array(bytes));
          return { ok: true };
        } catch (e) {
          return { ok: false, message: String(e && e.message ? e.message : e) };
        }
      },
      name,
      bytes,
    );
  const cube = await drop('cube.obj', [...Buffer.from(CUBE_OBJ)]);
  check(cube.ok, `dropping cube.obj: ${cube.message}`);
  const after = await waitForStats(page, 'the dropped cube', (s) => s.tree_hash !== before.tree_hash, 60000);
  check(after.fragments > 1, `the dropped cube is in ${after.fragments} fragments`);
  check(!after.error, `the dropped cube: error '${after.error}'`);
  // With no pieces, pattern or seed in the URL a dropped model takes the library's
  // defaults, as `breakables fracture --mesh FILE` does: the same tree.
  const native = nativeFractureFile(opts.native, 'cube.obj', CUBE_OBJ, []);
  if (native)
    check(after.tree_hash === native.tree_hash && after.fragments === native.pieces_made,
      `the dropped cube: tree ${after.tree_hash} of ${after.fragments} fragments, native fracture --mesh cube.obj: ${native.tree_hash} of ${native.pieces_made}`);
  say(`drop: cube.obj -> ${after.fragments} fragments, tree ${before.tree_hash} -> ${after.tree_hash}${native ? ' (= native)' : ''}`);

  const garbage = Buffer.concat([Buffer.from('this is not a model\n'), Buffer.from([0, 1, 2, 255, 254, 10, 0x76, 0x20, 0x78])]);
  const bad = await drop('bad.obj', [...garbage]);
  check(!bad.ok, 'dropping a file that is no model succeeded');
  const err = await waitForStats(page, 'the bad file: stats.error', (s) => typeof s.error === 'string' && s.error.length > 0, 30000, {
    allowError: true,
  });
  check(!/[\r\n]/.test(err.error) && err.error.length <= 300, `the bad file's error is not one line: ${JSON.stringify(err.error)}`);
  check(err.tree_hash === after.tree_hash, `the bad file replaced the scene (tree ${after.tree_hash} -> ${err.tree_hash})`);
  await stillRunning(page, 'after the bad file');
  ctx.numbers.drop = { cube_fragments: after.fragments, cube_tree_hash: after.tree_hash, bad_file_error: err.error };
  say(`drop: bad.obj -> "${err.error}"; the page runs on`);
  await page.close();
}

/// The bunny into 256 pieces: the page's tree against the native one.
async function checkBunny(ctx, opts) {
  const native = nativeFracture(opts.native, BUNNY_ARGS);
  const expected = native ? native.tree_hash : tableHash(BUNNY_ARGS);
  check(expected, `no native tree hash for ${BUNNY_ARGS.join(' ')}: no ${opts.native} and no line in tests/tree_hashes.txt`);
  const from = native ? path.relative(repo, opts.native) : 'tests/tree_hashes.txt';
  // The pattern fracture uses when given none (the library's default).
  const pattern = native ? native.pattern : 'planes';
  const what = `?scene=bunny&mesh=bunny&pieces=256&pattern=${pattern}&seed=3000`;
  const { page, stats } = await open(ctx, what, what, 180000);
  check(stats.fragments === 256, `${what}: ${stats.fragments} fragments, not 256`);
  const table = tableHash(BUNNY_ARGS);
  check(
    stats.tree_hash === expected,
    `${what}: tree_hash ${stats.tree_hash}, the native tree's is ${expected} (${from})` +
      (native && table && table !== expected ? `; tests/tree_hashes.txt has ${table} (is ${from} older than the sources?)` : ''),
  );
  say(`bunny 256: tree ${stats.tree_hash} = ${from}'s; fracture ${round(stats.fracture_ms, 1)} ms in the page`);
  ctx.numbers.bunny256 = { tree_hash: stats.tree_hash, native_from: from, page_fracture_ms: round(stats.fracture_ms, 2) };
  if (native) ctx.numbers.bunny256.native_hash_table = tableHash(BUNNY_ARGS);
  return page;
}

/// tests/tree_hashes.txt's other fractures, built by the module in the page.
async function checkTableHashes(ctx, page) {
  const jobs = [];
  const skipped = [];
  for (const row of treeHashTable()) {
    const o = {};
    for (let i = 0; i + 1 < row.args.length; i += 2) o[row.args[i]] = row.args[i + 1];
    const known = Object.keys(o).every((k) => ['--mesh', '--pattern', '--pieces', '--seed'].includes(k));
    if (!known || row.args.length % 2 || !o['--mesh']) {
      skipped.push(row.args.join(' '));
      continue;
    }
    const source = o['--mesh'] === 'bunny' ? { bunny: true } : { shape: o['--mesh'] };
    const options = { pieces: Number(o['--pieces'] || 256), seed: Number(o['--seed'] || 3000) };
    if (o['--pattern']) options.pattern = o['--pattern'];
    jobs.push({ row, source, options });
  }
  const got = await moduleTreeHashes(page, jobs.map(({ source, options }) => ({ source, options })));
  jobs.forEach(({ row }, i) =>
    check(got[i].hash === row.hash, `fracture ${row.args.join(' ')} in the page: tree_hash ${got[i].hash}, tests/tree_hashes.txt has ${row.hash}`),
  );
  say(`tree hashes: ${jobs.length} of tests/tree_hashes.txt built in the page equal${skipped.length ? `; not tried (options the page has not): ${skipped.join('; ')}` : ''}`);
}

/// Speed against the native build (printed, not checked). The page's side is
/// measured first, then the browser's pages are closed and the native side
/// runs on an idle machine (as far as this test goes).
async function measureSpeed(ctx, page, opts) {
  const bunny = await moduleBunnyFracture(page, { pieces: 256, seed: 3000 }, FRACTURE_RUNS);
  const split = await moduleSplit(page, SPLIT_PIECES, 3000, SPLIT_RUNS);
  await page.close();

  const nativeDir = path.dirname(opts.native);
  const buildType = nativeBuildType(nativeDir);
  const note =
    buildType && buildType !== 'Release' ? ` (${path.relative(repo, nativeDir)} is a ${buildType} build: not comparable)` : '';
  const n = ctx.numbers.bunny256;
  n.module_fracture_ms = round(bunny.ms, 2);
  if (existsSync(opts.native)) {
    n.native_fracture_ms = round(nativeFractureMs(opts.native, BUNNY_ARGS, FRACTURE_RUNS), 2);
    n.ratio = round(n.page_fracture_ms / n.native_fracture_ms, 2);
    n.module_ratio = round(n.module_fracture_ms / n.native_fracture_ms, 2);
    say(
      `speed: bunny 256 in ${n.page_fracture_ms} ms in the page (its first call), ${n.module_fracture_ms} ms through the module ` +
        `(median of ${FRACTURE_RUNS}); native ${n.native_fracture_ms} ms (median of ${FRACTURE_RUNS}): ${n.ratio}x and ` +
        `${n.module_ratio}x (target 2.5x)${note}`,
    );
  } else say(`speed: bunny 256 in ${n.page_fracture_ms} ms in the page; no ${opts.native} to compare with`);

  ctx.numbers.wall_split = { page: roundAll(split) };
  const built = buildSplitNative(nativeDir);
  if (built.skipped) {
    say(`speed: wall of ${split.fragments} split in ${round(split.split_ms, 3)} ms in the page; native not measured: ${built.skipped}`);
    return;
  }
  const native = nativeSplit(built.exe, SPLIT_PIECES, 3000, SPLIT_RUNS);
  const w = ctx.numbers.wall_split;
  w.native = roundAll(native);
  w.same_tree = native.tree_hash === split.tree_hash;
  w.same_result = native.clusters_created === split.clusters_created && native.bonds_broken === split.bonds_broken;
  w.split_ratio = round(split.split_ms / native.split_ms, 2);
  w.damage_split_ratio = round((split.damage_ms + split.split_ms) / (native.damage_ms + native.split_ms), 2);
  say(
    `speed: wall of ${split.fragments} fragments hit (${split.bonds_broken} bonds broken) and split into ` +
      `${split.clusters_created} clusters in ${round(split.split_ms, 3)} ms in the page, native ${round(native.split_ms, 3)} ms: ` +
      `${w.split_ratio}x (with the hit's damage ${w.damage_split_ratio}x; target 3x); same tree ${w.same_tree ? 'yes' : 'NO'}, ` +
      `same clusters and bonds ${w.same_result ? 'yes' : 'NO'}${note}`,
  );
}

function roundAll(o) {
  const out = {};
  for (const [k, v] of Object.entries(o)) out[k] = typeof v === 'number' && !Number.isInteger(v) ? round(v, 4) : v;
  return out;
}

async function main() {
  const started = Date.now();
  const opts = parseArgs(process.argv.slice(2));
  check(existsSync(path.join(opts.dist, 'index.html')), `no ${opts.dist}/index.html: build it first (scripts/web.sh --build-only)`);
  check(existsSync(opts.chromium), `no ${opts.chromium}: scripts/setup.sh --web installs chromium`);
  const ctx = { pages: [], numbers: {} };
  ctx.server = await startServer(opts.dist);
  ctx.origin = ctx.server.origin;
  const chromium = await launchBrowser(opts.chromium);
  ctx.browser = chromium.browser;
  say(`${await ctx.browser.version()} on ${ctx.origin}`);
  try {
    // Problems (console, exceptions, requests) are checked after each step, so a failure names the step.
    await checkLoad(ctx);
    noProblems(ctx);
    const wallPage = await checkWall(ctx, opts);
    await wallPage.close();
    noProblems(ctx);
    await checkDrop(ctx, opts);
    noProblems(ctx);
    const bunnyPage = await checkBunny(ctx, opts);
    // The module is measured in this page with its animation stopped: nothing draws beside it.
    await stopAnimation(bunnyPage);
    await checkTableHashes(ctx, bunnyPage);
    await measureSpeed(ctx, bunnyPage, opts);
    noProblems(ctx);
  } finally {
    await chromium.close();
    ctx.server.stop();
  }
  const seconds = (Date.now() - started) / 1000;
  if (opts.json) {
    writeFileSync(opts.json, JSON.stringify({ ok: true, seconds: round(seconds, 1), ...ctx.numbers }, null, 2) + '\n');
    say(`numbers: ${opts.json}`);
  }
  say(`passed in ${seconds.toFixed(0)} s`);
}

main().catch((e) => {
  const message = String(e && e.message ? e.message : e).split('\n')[0];
  process.stdout.write(`browser test: FAIL: ${message}\n`);
  process.exit(1);
});
