// The page in Debian's headless Chromium (playwright-core, no browser download), served by
// web/serve.mjs on 127.0.0.1: it runs a scripted walk through the demo field with no console error,
// the levels it chose equal the native library's on the very inputs it recorded, THREE.LOD shows them,
// the canvas is not blank and, coloured by level, shows those levels' colours. Bad content (a missing
// scene, a profile failing validation, a file that is not glTF, a glTF that is not lodgen's) shows a
// message on the page and in the console, and nothing throws uncaught. An object with a cluster
// hierarchy is drawn as acuity's cut under a triangle budget (checked in node and against the native
// library), which follows the gaze.
import assert from 'node:assert/strict';
import { spawn } from 'node:child_process';
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import { fileURLToPath } from 'node:url';
import { chromium } from 'playwright-core';
import { PNG } from 'pngjs';

import { FLAG } from '../acuity.js';
import { env, firstDifference, loadWasm, runNative } from './scene.mjs';

const here = path.dirname(fileURLToPath(import.meta.url));
const fieldDir = env('ACUITY_FIELD_DIR');
const work = path.join(env('ACUITY_WEB_WORK'), 'page');
fs.mkdirSync(work, { recursive: true });
const FRAMES = 90;
const PALETTE = [0x2060ff, 0x20d0e0, 0x30c040, 0xf0e020, 0xff8020, 0xe02020, 0xc040c0, 0xffffff];

// Bad content beside the good: a truncated profile set, a glTF without MSFT_lod.
const badProfiles = path.join(fieldDir, 'bad-profiles');
fs.mkdirSync(badProfiles, { recursive: true });
for (const f of fs.readdirSync(path.join(fieldDir, 'profiles'))) {
  const bytes = fs.readFileSync(path.join(fieldDir, 'profiles', f));
  fs.writeFileSync(path.join(badProfiles, f), bytes.subarray(0, bytes.length >> 1));
}
fs.writeFileSync(path.join(fieldDir, 'plain.gltf'),
  JSON.stringify({ asset: { version: '2.0' }, scene: 0, scenes: [{ nodes: [0] }], nodes: [{ name: 'empty' }] }));

// The server: any free port on 127.0.0.1; its first line is the URL.
const server = spawn(process.execPath, [path.join(here, '..', 'serve.mjs'), '--port', '0', '--content', fieldDir,
                                        '--wasm', env('ACUITY_WASM_DIR')], { stdio: ['ignore', 'pipe', 'inherit'] });
const base = await new Promise((resolve, reject) => {
  let out = '';
  server.stdout.on('data', d => {
    out += d;
    const m = out.match(/http:\/\/127\.0\.0\.1:\d+\//);
    if (m) resolve(m[0]);
  });
  server.on('exit', code => reject(new Error(`serve.mjs exited with ${code}`)));
  setTimeout(() => reject(new Error('serve.mjs printed no URL in 10 s')), 10000);
});

// The server answers inside its folders only, read-only.
for (const [method, url, status] of [['GET', 'content/field.glb', 200], ['GET', 'wasm/acuity.wasm', 200], ['GET', 'three/package.json', 200],
                                     ['GET', 'content/..%2F..%2F..%2F..%2F..%2Fetc%2Fpasswd', 404], ['GET', 'content/%2e%2e/field.glb', 404],
                                     ['GET', 'tests/scene.mjs', 404], ['GET', 'serve.mjs', 404], ['POST', 'index.html', 405]]) {
  const r = await fetch(base + url, { method });
  assert.equal(r.status, status, `${method} /${url}`);
  await r.arrayBuffer();
}

const userDataDir = fs.mkdtempSync(path.join(os.tmpdir(), 'acuity-chromium-'));
let context;
try {
  context = await chromium.launchPersistentContext(userDataDir, {
    executablePath: env('ACUITY_CHROMIUM'),
    headless: true,
    viewport: { width: 1280, height: 720 },
    args: ['--headless', '--no-sandbox', '--disable-gpu', '--use-gl=angle', '--use-angle=swiftshader', '--enable-unsafe-swiftshader',
           '--disable-dev-shm-usage', '--disable-quic', '--no-first-run', '--disable-background-networking', '--disable-component-update', '--disable-sync'],
  });

  async function open(query) {
    const page = await context.newPage();
    const errors = [], uncaught = [];
    page.on('console', m => { if (m.type() === 'error') errors.push(m.text()); });
    page.on('pageerror', e => uncaught.push(String(e)));
    await page.goto(base + query);
    await page.waitForFunction(() => window.acuityDone === true, null, { timeout: 180000 });
    return { page, errors, uncaught };
  }

  // ---- The field, scripted ---------------------------------------------------------------------
  const { page, errors, uncaught } = await open(`?frames=${FRAMES}`);
  assert.equal(await page.evaluate(() => window.acuityError ?? null), null, 'the page stopped with an error');
  assert.deepEqual(uncaught, [], 'uncaught exceptions');
  assert.deepEqual(errors, [], 'console errors');
  const rec = await page.evaluate(() => window.acuityRecord);
  assert.equal(rec.frames.length, FRAMES);
  assert.equal(rec.objects.profiles.length, 64);

  // The native library on the inputs the page recorded.
  const scene = {
    config: {}, profiles: rec.profiles.map(p => `${p}.acuity`), profileDir: path.join(fieldDir, 'profiles'),
    objects: { profiles: Int32Array.from(rec.objects.profiles), positions: Float64Array.from(rec.objects.positions),
               rotations: Float32Array.from(rec.objects.rotations), scales: Float32Array.from(rec.objects.scales) },
    frames: rec.frames.map(f => ({ dt: f.dt, eyeCount: f.eyeCount, eyes: Float64Array.from(f.eyes), moves: null })),
  };
  const native = runNative(scene, path.join(work, 'native'), 'page');
  const pageFrames = rec.frames.map((f, k) => ({ triangles: native[k].triangles, levels: Uint8Array.from(f.levels), flags: Uint8Array.from(f.flags) }));
  const diff = firstDifference(pageFrames, native);
  assert.equal(diff, '', `the page's levels differ from the native library's: ${diff}`);
  rec.frames.forEach((f, k) => assert.deepEqual(f.lodLevels, f.levels, `frame ${k}: THREE.LOD shows other levels`));
  const distinct = new Set(rec.frames.flatMap(f => f.levels));
  assert.ok(distinct.size >= 3, `only levels ${[...distinct]} on the walk`);
  const noGaze = rec.frames.map(f => f.flags.some(x => x & FLAG.noGaze));
  assert.ok(noGaze.includes(true) && noGaze.includes(false), 'frames with and without the gaze proxy');
  const last = rec.frames[FRAMES - 1];
  assert.ok(last.drawn > 0 && last.drawn < last.finest, `drawn ${last.drawn} of ${last.finest} all-finest`);

  // Pixels: the shaded canvas is not blank; coloured by level it shows acuity's levels.
  async function canvasPng(file) {
    const url = await page.evaluate(() => document.querySelector('canvas').toDataURL('image/png'));
    const bytes = Buffer.from(url.slice(url.indexOf(',') + 1), 'base64');
    fs.writeFileSync(path.join(work, file), bytes);
    return PNG.sync.read(bytes);
  }
  await page.screenshot({ path: path.join(work, 'page.png') });
  const shaded = await canvasPng('canvas_shaded.png');
  let sum = 0, sum2 = 0;
  const grey = new Set();
  for (let i = 0; i < shaded.data.length; i += 4) {
    const y = 0.299 * shaded.data[i] + 0.587 * shaded.data[i + 1] + 0.114 * shaded.data[i + 2];
    sum += y;
    sum2 += y * y;
    grey.add(Math.round(y));
  }
  const pixels = shaded.width * shaded.height, deviation = Math.sqrt(sum2 / pixels - (sum / pixels) ** 2);
  assert.ok(deviation > 8 && grey.size > 40, `the canvas looks blank: luminance deviation ${deviation.toFixed(2)}, ${grey.size} grey levels`);

  await page.click('#colour');
  await page.screenshot({ path: path.join(work, 'page_levels.png') });
  const coloured = await canvasPng('canvas_levels.png');
  const hits = new Array(PALETTE.length).fill(0);
  for (let i = 0; i < coloured.data.length; i += 4)
    PALETTE.forEach((c, k) => {
      if (Math.abs(coloured.data[i] - (c >> 16)) <= 4 && Math.abs(coloured.data[i + 1] - ((c >> 8) & 255)) <= 4 &&
          Math.abs(coloured.data[i + 2] - (c & 255)) <= 4) hits[k]++;
    });
  const shown = hits.map((h, k) => (h > 300 ? k : -1)).filter(k => k >= 0);
  assert.ok(shown.length >= 2, `levels seen in the coloured canvas: ${hits}`);
  for (const k of shown) assert.ok(last.levels.includes(k), `colour of level ${k} drawn, but acuity chose ${[...new Set(last.levels)]}`);
  const drawnAll = rec.frames.reduce((a, f) => a + f.drawn, 0), finestAll = rec.frames.reduce((a, f) => a + f.finest, 0);
  console.log(`page: ${FRAMES} frames equal to native; levels ${[...distinct].sort()}; drawn ${(drawnAll / FRAMES).toFixed(0)} of ` +
              `${(finestAll / FRAMES).toFixed(0)} all-finest triangles per frame on average (${(100 * drawnAll / finestAll).toFixed(1)} %); last frame ${last.drawn} of ${last.finest} triangles ` +
              `(${(100 * last.drawn / last.finest).toFixed(1)} %); luminance deviation ${deviation.toFixed(1)}; level pixels ${hits.slice(0, 5)}`);
  console.log(`page: acuity ${(await page.evaluate(() => window.acuityStats.acuityMs)).toFixed(3)} ms per frame in Chromium (moving average, ${rec.objects.profiles.length} objects)`);
  await page.close();

  // ---- A cluster cut: an object drawn as acuity's cut while the gaze sweeps across it ----------------
  // Under a triangle budget (?cutBudget=) that binds while the gaze is on the object and not while it
  // is far from it. Each frame the page's index buffer holds exactly the cut's triangles; the same cuts
  // come out of acuity.js in node and, bit for bit, of the native library (native_reference) on the
  // eyes the page recorded (the same hysteresis, frame after frame); the triangle count changes with
  // the gaze, and the buffer is rebuilt only when the cut changes.
  {
    const CUT_FRAMES = 60, CUT_BUDGET = 8000;
    const cutRun = await open(`?cut=content/${env('ACUITY_CUT_GLB')}&cutProfile=content/profiles/${env('ACUITY_CUT_PROFILE')}` +
                              `&cutBudget=${CUT_BUDGET}&frames=${CUT_FRAMES}`);
    assert.equal(await cutRun.page.evaluate(() => window.acuityError ?? null), null, 'the cut page stopped with an error');
    assert.deepEqual(cutRun.uncaught, [], 'uncaught exceptions');
    assert.deepEqual(cutRun.errors, [], 'console errors');
    const cr = await cutRun.page.evaluate(() => window.acuityRecord);
    await cutRun.page.screenshot({ path: path.join(work, 'page_cut.png') });
    await cutRun.page.close();
    assert.equal(cr.frames.length, CUT_FRAMES);
    const acuity = await loadWasm();
    const s = acuity.createScheduler({});
    const h = acuity.createHierarchy(Uint32Array.from(cr.cut.clusters), Uint8Array.from(cr.cut.groups),
                                     new Uint8Array(fs.readFileSync(path.join(fieldDir, 'profiles', env('ACUITY_CUT_PROFILE')))));
    const state = h.createCut();
    const native = runNative({
      config: {}, profiles: [], profileDir: path.join(fieldDir, 'profiles'),
      objects: { profiles: new Int32Array(0), positions: new Float64Array(0), rotations: new Float32Array(0), scales: new Float32Array(0) },
      cut: { clusters: Uint32Array.from(cr.cut.clusters), groups: Uint8Array.from(cr.cut.groups), profile: env('ACUITY_CUT_PROFILE'), budget: CUT_BUDGET },
      frames: cr.frames.map(f => ({ dt: f.dt, eyeCount: f.eyeCount, eyes: Float64Array.from(f.eyes), moves: null, cut: f.cut.transform })),
    }, path.join(work, 'native'), 'page_cut');
    let previous = null;
    cr.frames.forEach((f, k) => {
      const c = f.cut;
      assert.equal(c.status, 0, `frame ${k}: cut status`);
      assert.equal(c.drawnIndices, 3 * c.triangles, `frame ${k}: the index buffer holds the cut's triangles`);
      s.beginFrame(Float64Array.from(f.eyes), f.eyeCount, f.dt);
      const r = s.selectCut(h, state, c.transform.position, c.transform.rotation, c.transform.scale, null, CUT_BUDGET);
      s.endFrame();
      const fields = x => ({ status: x.status, flags: x.flags, triangles: x.triangles, held: x.held,
                             budgetCoarsened: x.budgetCoarsened, budgetForced: x.budgetForced, clusters: Array.from(x.clusters) });
      const page = fields(c);
      assert.deepEqual(fields(r), page, `frame ${k}: the page drew another cut than select_cut's in node`);
      assert.deepEqual(page, native[k].cut, `frame ${k}: the wasm module's budgeted cut differs from the native library's`);
      if (c.budgetCoarsened > 0) assert.ok(c.triangles <= CUT_BUDGET, `frame ${k}: ${c.triangles} triangles over the budget`);
      const changed = !previous || previous.length !== c.clusters.length || previous.some((x, i) => x !== c.clusters[i]);
      assert.equal(c.rebuilt, changed, `frame ${k}: rebuilt exactly when the cut changed`);
      previous = c.clusters;
    });
    const counts = cr.frames.map(f => f.cut.triangles), budgeted = cr.frames.filter(f => f.cut.budgetCoarsened > 0).length;
    assert.ok(new Set(counts).size >= 2, `the cut never changed as the gaze swept across it: ${counts[0]} triangles`);
    assert.ok(budgeted > 0 && budgeted < CUT_FRAMES, `the budget of ${CUT_BUDGET} triangles bound in ${budgeted} of ${CUT_FRAMES} frames (some, not all, wanted)`);
    console.log(`cut: ${CUT_FRAMES} frames equal to select_cut in node and to the native library; triangles ${Math.min(...counts)} .. ${Math.max(...counts)} ` +
                `(first ${counts[0]}, middle ${counts[CUT_FRAMES >> 1]}, last ${counts[CUT_FRAMES - 1]}); budget ${CUT_BUDGET} bound in ${budgeted} frames ` +
                `(${Math.max(...cr.frames.map(f => f.cut.budgetCoarsened))} groups coarsened at most); ` +
                `${cr.frames.filter(f => f.cut.rebuilt).length} rebuilds`);
    state.destroy();
    h.destroy();
    s.destroy();
  }

  // ---- Bad content -------------------------------------------------------------------------------
  for (const [query, pattern] of [
    ['?scene=content/missing.glb', /content\/missing\.glb: 404/],
    ['?profiles=content/bad-profiles/', /profile content\/bad-profiles\/\w+\.acuity failed validation: acuity_load_profile: \S/],
    ['?scene=content/profiles/cow.acuity', /not a glTF scene/],
    ['?scene=content/plain.gltf', /not a scene from acuity lodgen/],
  ]) {
    const bad = await open(query);
    const shownText = await bad.page.evaluate(() => {
      const m = document.getElementById('message');
      return getComputedStyle(m).display !== 'none' ? m.textContent : '';
    });
    assert.match(shownText, pattern, `${query}: the page says`);
    assert.ok(bad.errors.some(e => pattern.test(e)), `${query}: the console says ${JSON.stringify(bad.errors)}`);
    assert.deepEqual(bad.uncaught, [], `${query}: uncaught exceptions`);
    console.log(`${query}: "${shownText}"`);
    await bad.page.close();
  }
} finally {
  if (context) await context.close();
  server.kill();
  fs.rmSync(userDataDir, { recursive: true, force: true });
}
