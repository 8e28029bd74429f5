// What a page's modules import, found without a bundler: the import map of
// index.html, the import/export statements of a module (a text scan: the
// page's files and the npm packages it uses are plain ES modules), and how a
// browser resolves a specifier against the map. Used by assemble.mjs to copy
// exactly the vendor files the page reaches.

// A specifier a browser would fetch from another host (or a data:/blob: URL).
const ABSOLUTE = /^([a-z][a-z0-9+.-]*:|\/\/)/i;

/// The "imports" of the page's <script type="importmap">, or {} when it has none.
export function parseImportMap(html) {
  const m = html.match(/<script\s+type=["']importmap["'][^>]*>([\s\S]*?)<\/script>/i);
  if (!m) return {};
  let map;
  try {
    map = JSON.parse(m[1]);
  } catch (e) {
    throw new Error(`its import map is not JSON (${e.message})`);
  }
  if (map.scopes) throw new Error('its import map has scopes, which assemble.mjs does not follow');
  return map.imports || {};
}

/// The path (from the site's root, '/...') a specifier imported by the module
/// at path `from` names, or null when neither a path nor the import map
/// resolves it. Throws on a URL of another host: the page must work offline.
export function resolveSpecifier(spec, from, importMap) {
  if (ABSOLUTE.test(spec)) throw new Error(`'${spec}' (imported by ${from}) is not a file of the page`);
  const base = 'http://page.invalid';
  if (spec.startsWith('/') || spec.startsWith('./') || spec.startsWith('../'))
    return new URL(spec, base + from).pathname;
  let target = null;
  if (Object.hasOwn(importMap, spec)) target = importMap[spec];
  else {
    // The longest prefix key ending in '/' wins, as in the browser.
    let best = '';
    for (const key of Object.keys(importMap))
      if (key.endsWith('/') && spec.startsWith(key) && key.length > best.length) best = key;
    if (best) target = importMap[best] + spec.slice(best.length);
  }
  if (target === null) return null;
  if (ABSOLUTE.test(target)) throw new Error(`the import map sends '${spec}' to ${target}, not a file of the page`);
  // Import map addresses are relative to the document (index.html at the root).
  return new URL(target, base + '/index.html').pathname;
}

/// The specifiers a module's text imports. Static imports and re-exports are
/// `strict` (the module cannot load without them); dynamic import('...') and
/// new URL('...', import.meta.url) (workers, wasm) are `optional`: they may
/// sit in code a browser never runs (emscripten's node branch imports node's
/// modules), so a missing one is left to the browser test.
export function scanModule(text) {
  const strict = [];
  const optional = [];
  // A statement starts a line or follows ; or } (minified code). `from` lists
  // hold names, braces, commas, stars and `as`, never quotes.
  const stat = /(?:^|[;\n}])\s*(?:import|export)\s*(?:[\w$*{}\s,]+?\s*from\s*)?["']([^"'\n]+)["']/g;
  for (const m of text.matchAll(stat)) strict.push(m[1]);
  for (const m of text.matchAll(/\bimport\s*\(\s*["']([^"'\n]+)["']\s*\)/g)) optional.push(m[1]);
  for (const m of text.matchAll(/\bnew\s+URL\s*\(\s*["']([^"'\n]+)["']\s*,\s*import\.meta\.url\s*\)/g))
    optional.push(m[1].startsWith('.') || m[1].startsWith('/') ? m[1] : './' + m[1]);
  return { strict, optional };
}

/// What index.html loads: script src= and stylesheet/module-preload href=
/// (document URLs, made './'-relative), and what its inline module scripts import.
export function scanHtml(html) {
  const strict = [];
  const optional = [];
  const asPath = (u) => (ABSOLUTE.test(u) || u.startsWith('/') || u.startsWith('.') ? u : './' + u);
  for (const m of html.matchAll(/<script\b[^>]*\bsrc=["']([^"']+)["']/gi)) strict.push(asPath(m[1]));
  for (const m of html.matchAll(/<link\b[^>]*>/gi)) {
    const rel = (m[0].match(/\brel=["']([^"']+)["']/i) || [])[1] || '';
    const href = (m[0].match(/\bhref=["']([^"']+)["']/i) || [])[1];
    // data: URLs (an empty icon, so the browser asks for no favicon.ico) load nothing.
    if (href && !href.startsWith('data:') && /stylesheet|modulepreload|icon|preload/i.test(rel)) strict.push(asPath(href));
  }
  for (const m of html.matchAll(/<script\b([^>]*)>([\s\S]*?)<\/script>/gi)) {
    if (!/type=["']module["']/i.test(m[1]) || /\bsrc=/i.test(m[1])) continue;
    const inner = scanModule(m[2]);
    strict.push(...inner.strict);
    optional.push(...inner.optional);
  }
  return { strict, optional };
}
