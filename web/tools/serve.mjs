// A small static file server for the built page (web/dist): 127.0.0.1 only,
// GET and HEAD, the MIME types a browser insists on (application/wasm for
// WebAssembly.instantiateStreaming, text/javascript for modules), and no path
// that leaves the served folder.
//   node web/tools/serve.mjs [--root DIR] [--port P] [--quiet]
// --port 0 picks a free port. Prints "serving DIR at http://127.0.0.1:P/" once
// listening (the browser test reads that line to learn the port).
import { createServer } from 'node:http';
import { createReadStream, promises as fs } from 'node:fs';
import path from 'node:path';
import { fileURLToPath } from 'node:url';

const here = path.dirname(fileURLToPath(import.meta.url));

const MIME = {
  '.html': 'text/html; charset=utf-8',
  '.css': 'text/css; charset=utf-8',
  '.js': 'text/javascript; charset=utf-8',
  '.mjs': 'text/javascript; charset=utf-8',
  '.json': 'application/json; charset=utf-8',
  '.map': 'application/json; charset=utf-8',
  '.wasm': 'application/wasm',
  '.obj': 'text/plain; charset=utf-8',
  '.glb': 'model/gltf-binary',
  '.gltf': 'model/gltf+json',
  '.mtree': 'application/octet-stream',
  '.png': 'image/png',
  '.jpg': 'image/jpeg',
  '.svg': 'image/svg+xml',
  '.ico': 'image/x-icon',
  '.txt': 'text/plain; charset=utf-8',
};

function usage(message) {
  process.stderr.write(`serve: ${message}\nusage: node web/tools/serve.mjs [--root DIR] [--port P] [--quiet]\n`);
  process.exit(2);
}

function parseArgs(argv) {
  const opts = { root: path.resolve(here, '..', 'dist'), port: 8080, quiet: false };
  for (let i = 0; i < argv.length; ++i) {
    const a = argv[i];
    if (a === '--root' && i + 1 < argv.length) opts.root = path.resolve(argv[++i]);
    else if (a === '--port' && i + 1 < argv.length) {
      const p = argv[++i];
      if (!/^\d+$/.test(p) || Number(p) > 65535) usage(`--port wants 0..65535, not '${p}'`);
      opts.port = Number(p);
    } else if (a === '--quiet') opts.quiet = true;
    else usage(`unknown option '${a}'`);
  }
  return opts;
}

// Maps a request path onto a file under root, or null when it would leave root
// (after decoding: %2e%2e and backslashes included) or names something odd.
export function resolveUnder(root, urlPath) {
  let decoded;
  try {
    decoded = decodeURIComponent(urlPath);
  } catch {
    return null;
  }
  if (decoded.includes('\0') || decoded.includes('\\')) return null;
  const full = path.resolve(root, '.' + path.posix.normalize('/' + decoded));
  const rel = path.relative(root, full);
  if (rel.startsWith('..') || path.isAbsolute(rel)) return null;
  return full;
}

async function fileFor(root, urlPath) {
  let full = resolveUnder(root, urlPath);
  if (!full) return { status: 403 };
  let st;
  try {
    st = await fs.stat(full);
    if (st.isDirectory()) {
      full = path.join(full, 'index.html');
      st = await fs.stat(full);
    }
  } catch {
    return { status: 404 };
  }
  if (!st.isFile()) return { status: 404 };
  // A symlink inside dist pointing outside it is refused as well.
  const real = await fs.realpath(full);
  const realRoot = await fs.realpath(root);
  const rel = path.relative(realRoot, real);
  if (rel.startsWith('..') || path.isAbsolute(rel)) return { status: 403 };
  return { status: 200, full, size: st.size, mtime: st.mtime };
}

export function startServer({ root, port, quiet }) {
  const server = createServer(async (req, res) => {
    const send = (status, text) => {
      res.writeHead(status, { 'Content-Type': 'text/plain; charset=utf-8' });
      res.end(req.method === 'HEAD' ? undefined : `${status} ${text}\n`);
    };
    if (req.method !== 'GET' && req.method !== 'HEAD') {
      res.setHeader('Allow', 'GET, HEAD');
      return send(405, 'method not allowed');
    }
    const urlPath = (req.url || '/').split('?')[0].split('#')[0];
    const found = await fileFor(root, urlPath);
    if (!quiet && found.status !== 200) process.stderr.write(`serve: ${found.status} ${req.url}\n`);
    if (found.status === 403) return send(403, 'forbidden');
    if (found.status !== 200) return send(404, 'not found');
    // The browser may keep a file but must ask again each time (no-cache with an
    // ETag): a rebuilt page is never mixed with an old one, and an unchanged
    // .wasm stays in the cache, where chromium keeps its optimised machine code
    // for the next visit.
    const etag = `"${found.size.toString(16)}-${Math.floor(found.mtime.getTime()).toString(16)}"`;
    const headers = { 'Cache-Control': 'no-cache', ETag: etag, 'X-Content-Type-Options': 'nosniff' };
    if (req.headers['if-none-match'] === etag) {
      res.writeHead(304, headers);
      return res.end();
    }
    res.writeHead(200, {
      ...headers,
      'Content-Type': MIME[path.extname(found.full).toLowerCase()] || 'application/octet-stream',
      'Content-Length': found.size,
    });
    if (req.method === 'HEAD') return res.end();
    createReadStream(found.full).pipe(res);
  });
  return new Promise((resolve, reject) => {
    server.once('error', reject);
    server.listen(port, '127.0.0.1', () => resolve(server));
  });
}

async function main() {
  const opts = parseArgs(process.argv.slice(2));
  try {
    const st = await fs.stat(path.join(opts.root, 'index.html'));
    if (!st.isFile()) throw new Error();
  } catch {
    process.stderr.write(`serve: no index.html in ${opts.root} (build it first: scripts/web.sh --build-only)\n`);
    process.exit(1);
  }
  let server;
  try {
    server = await startServer(opts);
  } catch (e) {
    process.stderr.write(`serve: cannot listen on 127.0.0.1:${opts.port}: ${e.code || e.message}\n`);
    process.exit(1);
  }
  const { port } = server.address();
  process.stdout.write(`serving ${opts.root} at http://127.0.0.1:${port}/\n`);
  // A browser keeps its connections open: close them too, or close() waits for them.
  const stop = () => {
    server.close(() => process.exit(0));
    server.closeAllConnections();
  };
  process.on('SIGINT', stop);
  process.on('SIGTERM', stop);
}

if (process.argv[1] && path.resolve(process.argv[1]) === fileURLToPath(import.meta.url)) main();
