// The browser side of the browser test: the page's static server (web/tools/
// serve.mjs, on a free port), Debian's chromium through puppeteer-core, and
// pages that record every problem a user would not see but should not have:
// console errors and warnings (the page's and its workers'), uncaught
// exceptions, failed or refused requests, and requests leaving 127.0.0.1.
import { spawn } from 'node:child_process';
import { mkdtempSync, rmSync } from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import { createRequire } from 'node:module';
import { fileURLToPath } from 'node:url';

const here = path.dirname(fileURLToPath(import.meta.url));
export const repo = path.resolve(here, '..', '..');
// puppeteer-core is a package of web/ (web/package.json), not of tests/.
const requireFromWeb = createRequire(path.join(repo, 'web', 'package.json'));

// Headless chromium with WebGL2 on SwiftShader, and none of its background
// traffic (component updates, sync, field trials): this network is closed and
// the page must not need it.
const CHROMIUM_ARGS = [
  '--headless=new',
  '--no-sandbox',
  '--disable-gpu-sandbox',
  '--use-angle=swiftshader',
  '--enable-unsafe-swiftshader',
  '--disable-background-networking',
  '--disable-component-update',
  '--disable-sync',
  '--no-first-run',
  '--disable-quic',
  // A page in a headless window must not be throttled as if hidden: fps is measured.
  '--disable-background-timer-throttling',
  '--disable-renderer-backgrounding',
  '--disable-backgrounding-occluded-windows',
];

/// Starts serve.mjs on a free port of 127.0.0.1; resolves once it listens.
/// Every line it logs (a 404, a refused path) is kept in `log`.
export function startServer(dist) {
  const child = spawn(process.execPath, [path.join(repo, 'web', 'tools', 'serve.mjs'), '--root', dist, '--port', '0'], {
    stdio: ['ignore', 'pipe', 'pipe'],
  });
  const log = [];
  child.stderr.setEncoding('utf8');
  child.stderr.on('data', (d) => log.push(...d.split('\n').filter(Boolean)));
  return new Promise((resolve, reject) => {
    let out = '';
    const timer = setTimeout(() => reject(new Error('the server did not start within 10 s')), 10000);
    child.stdout.setEncoding('utf8');
    child.stdout.on('data', (d) => {
      out += d;
      const m = out.match(/http:\/\/127\.0\.0\.1:(\d+)\//);
      if (!m) return;
      clearTimeout(timer);
      resolve({
        origin: `http://127.0.0.1:${m[1]}`,
        log,
        stop: () => child.kill('SIGTERM'),
      });
    });
    child.once('exit', (code) => {
      clearTimeout(timer);
      reject(new Error(`the server exited (${code}): ${log.join(' ') || out.trim()}`));
    });
  });
}

/// chromium with a fresh profile (removed by close()).
export async function launchBrowser(executablePath) {
  const puppeteer = requireFromWeb('puppeteer-core');
  const profile = mkdtempSync(path.join(os.tmpdir(), 'breakables-chromium-'));
  const browser = await puppeteer.launch({
    executablePath,
    headless: true,
    userDataDir: profile,
    args: [...CHROMIUM_ARGS, `--user-data-dir=${profile}`],
    protocolTimeout: 300000,
  });
  return {
    browser,
    close: async () => {
      await browser.close().catch(() => {});
      rmSync(profile, { recursive: true, force: true });
    },
  };
}

/// A page whose problems are recorded in `problems` (one line each).
export async function openPage(browser, origin, { width = 960, height = 600 } = {}) {
  const page = await browser.newPage();
  await page.setViewport({ width, height });
  const problems = [];
  const local = (u) => u.startsWith(origin + '/') || u.startsWith('data:') || u.startsWith('blob:');
  const where = (msg) => {
    const loc = msg.location && msg.location();
    return loc && loc.url ? ` (${loc.url.replace(origin, '')}:${loc.lineNumber ?? '?'})` : '';
  };
  const onConsole = (who) => (msg) => {
    const type = msg.type();
    if (type === 'error' || type === 'warn' || type === 'warning' || type === 'assert')
      problems.push(`${who} console ${type}: ${msg.text()}${where(msg)}`);
  };
  page.on('console', onConsole('page'));
  page.on('pageerror', (e) => problems.push(`page uncaught exception: ${String(e.message || e).split('\n')[0]}`));
  page.on('error', (e) => problems.push(`page crashed: ${e.message}`));
  page.on('workercreated', (w) => {
    w.on('console', onConsole(`worker ${w.url().replace(origin, '')}`));
    w.on('error', (e) => problems.push(`worker uncaught exception: ${String(e.message || e).split('\n')[0]}`));
  });
  page.on('request', (r) => {
    if (!local(r.url())) problems.push(`request outside 127.0.0.1: ${r.url()}`);
  });
  page.on('requestfailed', (r) => {
    const reason = r.failure() ? r.failure().errorText : 'failed';
    problems.push(`request failed: ${r.url().replace(origin, '')} (${reason})`);
  });
  page.on('response', (r) => {
    if (r.status() >= 400) problems.push(`request failed: ${r.url().replace(origin, '')} (HTTP ${r.status()})`);
  });
  return { page, problems };
}

/// The page's #stats JSON, or null while it holds none.
export async function readStats(page) {
  const text = await page.$eval('#stats', (el) => el.textContent).catch(() => null);
  if (!text) return null;
  try {
    return JSON.parse(text);
  } catch {
    return null;
  }
}

/// Polls #stats until `test(stats)` holds; throws after timeoutMs with the last
/// stats seen, or at once when the page reports an error (unless allowError)
/// or a problem is recorded in `problems` (a page that cannot load says why
/// at once instead of timing out).
export async function waitForStats(page, what, test, timeoutMs, { allowError = false, problems = null } = {}) {
  const start = Date.now();
  let last = null;
  while (Date.now() - start < timeoutMs) {
    if (problems && problems.length) throw new Error(`${what}: ${problems[0]}`);
    last = await readStats(page);
    if (last && last.error && !allowError) throw new Error(`${what}: the page reports an error: ${last.error}`);
    if (last && test(last)) return last;
    await new Promise((r) => setTimeout(r, 100));
  }
  throw new Error(`${what}: not within ${timeoutMs / 1000} s (last stats: ${JSON.stringify(last)})`);
}
