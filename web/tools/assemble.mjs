// Assembles the page into web/dist/ (what scripts/web.sh serves): the page's
// own files, the WebAssembly build, the bunny, and from node_modules only the
// files the page's modules reach. Which vendor files those are is read from
// the page itself: the import map in index.html and the import statements of
// every module, followed transitively, so the page and its worker work offline
// and nothing a module imports can be missing from dist (that fails here, at
// build time, instead of as a failed request in the browser).
//   node web/tools/assemble.mjs [--wasm-dir DIR] [--out DIR]
// DIR defaults: build-web (emscripten's output), web/dist.
import { promises as fs } from 'node:fs';
import path from 'node:path';
import { fileURLToPath } from 'node:url';
import { parseImportMap, resolveSpecifier, scanHtml, scanModule } from './module_graph.mjs';

const here = path.dirname(fileURLToPath(import.meta.url));
const web = path.resolve(here, '..');
const repo = path.resolve(web, '..');
const nodeModules = path.join(web, 'node_modules');

// The page's own files, copied as they are (web/<name> -> dist/<name>).
const PAGE_ENTRIES = ['index.html', 'css', 'js'];
// The wrapper imports '../wasm/breakables_web.mjs' (see web/js/breakables.js).
const WASM_FILES = ['breakables_web.mjs', 'breakables_web.wasm'];
// Where the page's vendor URLs come from in node_modules (the longest prefix
// wins): the import map of index.html names files under /vendor/.
const VENDOR_MAP = [
  { url: '/vendor/addons/', from: 'three/examples/jsm/', pkg: 'three' },
  { url: '/vendor/rapier/', from: '@dimforge/rapier3d-compat/dist/', pkg: '@dimforge/rapier3d-compat' },
  { url: '/vendor/', from: 'three/build/', pkg: 'three' },
];
function vendorEntry(url) {
  return VENDOR_MAP.find((v) => url.startsWith(v.url)) || null;
}

function fail(message) {
  process.stderr.write(`assemble: ${message}\n`);
  process.exit(1);
}

function parseArgs(argv) {
  const opts = { wasmDir: path.join(repo, 'build-web'), out: path.join(web, 'dist') };
  for (let i = 0; i < argv.length; ++i) {
    if (argv[i] === '--wasm-dir' && i + 1 < argv.length) opts.wasmDir = path.resolve(argv[++i]);
    else if (argv[i] === '--out' && i + 1 < argv.length) opts.out = path.resolve(argv[++i]);
    else fail(`unknown option '${argv[i]}' (use --wasm-dir DIR, --out DIR)`);
  }
  return opts;
}

async function exists(p) {
  try {
    await fs.access(p);
    return true;
  } catch {
    return false;
  }
}

async function copyFile(from, to) {
  await fs.mkdir(path.dirname(to), { recursive: true });
  await fs.copyFile(from, to);
}

// Every file under dir (recursively), as paths relative to it.
async function listFiles(dir, prefix = '') {
  const out = [];
  for (const e of await fs.readdir(path.join(dir, prefix), { withFileTypes: true })) {
    const rel = path.join(prefix, e.name);
    if (e.isDirectory()) out.push(...(await listFiles(dir, rel)));
    else if (e.isFile()) out.push(rel);
  }
  return out;
}

async function copyPage(out) {
  for (const entry of PAGE_ENTRIES) {
    const from = path.join(web, entry);
    if (!(await exists(from))) {
      if (entry === 'index.html') fail(`no ${path.relative(repo, from)}: the page is missing`);
      continue;
    }
    const st = await fs.stat(from);
    const files = st.isDirectory() ? (await listFiles(from)).map((f) => path.join(entry, f)) : [entry];
    for (const f of files) await copyFile(path.join(web, f), path.join(out, f));
  }
}

async function copyWasm(out, wasmDir) {
  for (const f of WASM_FILES) {
    const from = path.join(wasmDir, f);
    if (!(await exists(from))) fail(`no ${from}: build the WebAssembly module first (scripts/web.sh)`);
    await copyFile(from, path.join(out, 'wasm', f));
  }
}

async function copyAssets(out) {
  const bunny = path.join(repo, 'assets', 'meshes', 'bunny.obj');
  if (!(await exists(bunny))) fail(`no ${bunny}`);
  await copyFile(bunny, path.join(out, 'assets', 'bunny.obj'));
}

// Follows the module graph from index.html and the page's modules. A path
// under dist/vendor/ is copied from node_modules; any other must already be in
// dist. A static import that cannot be found fails the build; a dynamic one
// (see module_graph.mjs) is followed only when its file exists. Returns the
// vendor files copied (their packages' names).
async function followModules(out) {
  const html = await fs.readFile(path.join(out, 'index.html'), 'utf8');
  let importMap;
  try {
    importMap = parseImportMap(html);
  } catch (e) {
    fail(`index.html: ${e.message}`);
  }
  const seen = new Set();
  const vendored = [];
  const pending = [];
  const localPath = (url) => path.join(out, ...url.split('/').filter(Boolean));
  const vendorSource = (v, url) => path.join(nodeModules, ...(v.from + url.slice(v.url.length)).split('/'));
  const visit = async (spec, from, strict) => {
    let url;
    try {
      url = resolveSpecifier(spec, from, importMap);
    } catch (e) {
      fail(e.message);
    }
    if (!url) {
      if (strict) fail(`${from} imports '${spec}', which neither the import map nor a path resolves`);
      return;
    }
    if (seen.has(url)) return;
    const v = vendorEntry(url);
    const source = v ? vendorSource(v, url) : localPath(url);
    if (!(await exists(source))) {
      if (!strict) return;
      if (v) fail(`${from} imports ${url}, but web/node_modules has no ${path.relative(nodeModules, source)}`);
      fail(`${from} imports ${url}, which is not in dist`);
    }
    seen.add(url);
    if (v) {
      await copyFile(source, localPath(url));
      vendored.push(v.pkg);
    }
    if (/\.m?js$/.test(url)) pending.push(url);
  };
  const fromHtml = scanHtml(html);
  for (const spec of fromHtml.strict) await visit(spec, '/index.html', true);
  for (const spec of fromHtml.optional) await visit(spec, '/index.html', false);
  // Every module of the page is a root too: workers and modules loaded by name at run time.
  for (const f of await listFiles(out))
    if (/\.m?js$/.test(f)) await visit('/' + f.split(path.sep).join('/'), '/index.html', true);
  while (pending.length) {
    const file = pending.pop();
    const found = scanModule(await fs.readFile(localPath(file), 'utf8'));
    for (const spec of found.strict) await visit(spec, file, true);
    for (const spec of found.optional) await visit(spec, file, false);
  }
  return vendored;
}

// The licence of each package vendored (three: MIT, Rapier: Apache-2.0), as
// vendor/licenses/<package>/LICENSE: what the page redistributes carries its terms.
async function copyLicences(out, packages) {
  for (const pkg of new Set(packages)) {
    const dir = path.join(nodeModules, ...pkg.split('/'));
    for (const name of await fs.readdir(dir))
      if (/^(licen[cs]e|copying)(\.\w+)?$/i.test(name))
        await copyFile(path.join(dir, name), path.join(out, 'vendor', 'licenses', ...pkg.split('/'), name));
  }
}

async function main() {
  const opts = parseArgs(process.argv.slice(2));
  if (!(await exists(nodeModules))) fail('no web/node_modules: run scripts/setup.sh --web (npm ci --prefix web)');
  await fs.rm(opts.out, { recursive: true, force: true });
  await fs.mkdir(opts.out, { recursive: true });
  await copyPage(opts.out);
  await copyWasm(opts.out, opts.wasmDir);
  await copyAssets(opts.out);
  const vendored = await followModules(opts.out);
  await copyLicences(opts.out, vendored);
  const files = await listFiles(opts.out);
  let bytes = 0;
  for (const f of files) bytes += (await fs.stat(path.join(opts.out, f))).size;
  process.stdout.write(
    `assemble: ${path.relative(process.cwd(), opts.out) || '.'}: ${files.length} files ` +
      `(${vendored.length} from node_modules), ${(bytes / 1048576).toFixed(1)} MiB\n`,
  );
}

main().catch((e) => fail(e.message));
