#!/usr/bin/env node
// Serves the acuity web page on 127.0.0.1 only:  node web/serve.mjs [--port 8080] [--content DIR] [--wasm DIR]
//   /            web/index.html, main.js, acuity.js
//   /three/      web/node_modules/three (npm, pinned in web/package-lock.json)
//   /wasm/       acuity.mjs + acuity.wasm (default build/web)
//   /content/    the scene and its profiles (default build/demo: `acuity demo` writes field.glb and profiles/)
// Read-only, GET/HEAD, regular files inside those folders only. Prints the URL, then serves until stopped.
import fs from 'node:fs';
import http from 'node:http';
import path from 'node:path';
import { fileURLToPath } from 'node:url';

const here = path.dirname(fileURLToPath(import.meta.url));
const repo = path.dirname(here);
const args = process.argv.slice(2);
function option(name, fallback) {
  const i = args.indexOf(name);
  if (i < 0) return fallback;
  if (i + 1 >= args.length) { console.error(`serve.mjs: ${name} needs a value`); process.exit(2); }
  return args[i + 1];
}
for (let i = 0; i < args.length; i += 2)
  if (!['--port', '--content', '--wasm'].includes(args[i])) {
    console.error('usage: node web/serve.mjs [--port N (0: any free)] [--content DIR] [--wasm DIR]');
    process.exit(2);
  }
const port = Number(option('--port', '8080'));
const roots = {
  '/three/': path.join(here, 'node_modules', 'three'),
  '/wasm/': path.resolve(option('--wasm', path.join(repo, 'build', 'web'))),
  '/content/': path.resolve(option('--content', path.join(repo, 'build', 'demo'))),
};
const pageFiles = new Set(['index.html', 'main.js', 'acuity.js', 'lod_scene.js']);
const types = { '.html': 'text/html; charset=utf-8', '.js': 'text/javascript', '.mjs': 'text/javascript',
                '.wasm': 'application/wasm', '.json': 'application/json', '.glb': 'model/gltf-binary',
                '.gltf': 'model/gltf+json', '.png': 'image/png' };

for (const [prefix, dir] of Object.entries(roots))
  if (!fs.existsSync(dir)) console.warn(`serve.mjs: ${dir} does not exist yet; ${prefix} answers 404 until it does`);

// The file a URL path names, or null: inside its root after resolving '..' and symbolic links.
function resolve(urlPath) {
  let p;
  try { p = decodeURIComponent(urlPath); } catch { return null; }
  if (p.includes('\0')) return null;
  if (p === '/') p = '/index.html';
  let root = null, rest = null;
  for (const [prefix, dir] of Object.entries(roots))
    if (p.startsWith(prefix)) { root = dir; rest = p.slice(prefix.length); }
  if (root === null) {
    if (!pageFiles.has(p.slice(1))) return null;
    root = here;
    rest = p.slice(1);
  }
  try {
    const realRoot = fs.realpathSync(root);
    const file = fs.realpathSync(path.resolve(realRoot, rest));
    if (!file.startsWith(realRoot + path.sep) || !fs.statSync(file).isFile()) return null;
    return file;
  } catch {
    return null;
  }
}

const server = http.createServer((req, res) => {
  const url = new URL(req.url, 'http://127.0.0.1');
  if (req.method !== 'GET' && req.method !== 'HEAD') {
    res.writeHead(405, { Allow: 'GET, HEAD' }).end();
    return;
  }
  const file = resolve(url.pathname);
  if (!file) {
    res.writeHead(404, { 'Content-Type': 'text/plain' }).end(`not found: ${url.pathname}\n`);
    return;
  }
  res.writeHead(200, { 'Content-Type': types[path.extname(file)] || 'application/octet-stream', 'Cache-Control': 'no-store' });
  if (req.method === 'HEAD') { res.end(); return; }
  fs.createReadStream(file).on('error', () => res.destroy()).pipe(res);
});
server.on('error', e => { console.error(`serve.mjs: ${e.message}`); process.exit(1); });
server.listen(port, '127.0.0.1', () => {
  console.log(`acuity web page: http://127.0.0.1:${server.address().port}/`);
  console.log(`  content ${roots['/content/']}, module ${roots['/wasm/']}`);
});
