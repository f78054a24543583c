// web/acuity.js over the WebAssembly module: failures are AcuityErrors carrying acuity_last_error()'s
// text and status, bad arguments never reach the module, the heap grows under 100k objects without
// stale views, and the scheduler goes on working after every error.
import assert from 'node:assert/strict';
import fs from 'node:fs';
import path from 'node:path';

import { AcuityError, EYE_DOUBLES, FLAG, PROJECTION, VIEW_DOUBLES, writeEye, writeView } from '../acuity.js';
import { env, loadWasm, readField } from './scene.mjs';

const acuity = await loadWasm();
assert.match(acuity.version, /^\d+\.\d+\.\d+$/);

function throwsAcuity(fn, status, pattern) {
  let caught = null;
  try { fn(); } catch (e) { caught = e; }
  assert.ok(caught instanceof AcuityError, `expected an AcuityError, got ${caught}`);
  assert.equal(caught.status, status, caught.message);
  assert.match(caught.message, pattern);
  return caught;
}

// Configuration: unknown fields, values that do not fit, and the C ABI's own checks.
throwsAcuity(() => acuity.createScheduler({ no_such_field: 1 }), 1, /no_such_field/);
throwsAcuity(() => acuity.createScheduler({ max_objects: -1 }), 1, /max_objects/);
throwsAcuity(() => acuity.createScheduler({ hysteresis_frames: 1.5 }), 1, /hysteresis_frames/);
let e = throwsAcuity(() => acuity.createScheduler({ max_objects: 0 }), 1, /^acuity_create: /);
assert.ok(e.message.endsWith(acuity.lastError()) && acuity.lastError().length > 0, 'the message is acuity_last_error()');
throwsAcuity(() => acuity.createScheduler({ rule: 99 }), 1, /bad rule/);

const fieldDir = env('ACUITY_FIELD_DIR');
const field = readField(fieldDir);
const profile = new Uint8Array(fs.readFileSync(path.join(fieldDir, 'profiles', field.profiles[0])));
const s = acuity.createScheduler({ max_objects: 100000, max_profiles: 2 });

// Profiles: garbage, truncated, empty bytes fail validation with the reader's message.
e = throwsAcuity(() => s.loadProfile(new Uint8Array(64).fill(7)), 2, /^acuity_load_profile: \S/);
assert.ok(e.message.endsWith(acuity.lastError()) && acuity.lastError().length > 0);
throwsAcuity(() => s.loadProfile(profile.subarray(0, profile.length - 9)), 2, /acuity_load_profile/);
throwsAcuity(() => s.loadProfile(new Uint8Array(0)), 2, /acuity_load_profile/);
throwsAcuity(() => s.loadProfile([1, 2, 3]), 1, /Uint8Array/);
assert.equal(s.loadProfile(profile), 0);
assert.equal(s.loadProfile(profile), 1);
throwsAcuity(() => s.loadProfile(profile), 3, /acuity_load_profile/);  // max_profiles reached

// Objects: bad profile index, short or mistyped arrays.
const one = [Int32Array.of(0), Float64Array.of(0, 0, -5), Float32Array.of(0, 0, 0, 1), Float32Array.of(1)];
throwsAcuity(() => s.addObjects(Int32Array.of(7), ...one.slice(1)), 1, /^acuity_add_objects: profiles\[0\] = 7 is not a loaded profile/);  // INVALID_ARGUMENT, not FULL
throwsAcuity(() => s.addObjects(one[0], new Float64Array(2), one[2], one[3]), 1, /positions: 3 values/);
throwsAcuity(() => s.addObjects(one[0], one[1], new Float64Array(4), one[3]), 1, /Float32Array/);

// 100k objects in a grid: the heap grows while staging, and levels come back for every one.
const n = 100000;
const profiles = new Int32Array(n), positions = new Float64Array(3 * n), rotations = new Float32Array(4 * n), scales = new Float32Array(n);
for (let i = 0; i < n; ++i) {
  profiles[i] = i % 2;
  positions.set([(i % 316) * 2 - 316, 0, -2 - Math.floor(i / 316) * 2], 3 * i);
  rotations[4 * i + 3] = 1;
  scales[i] = 1;
}
// The heap must grow inside addObjects whatever slack the allocator has left: its first allocation
// takes a ballast block as big as the whole heap before the staging block.
const bufferBefore = acuity.m.HEAPU8.buffer.byteLength;
const malloc = acuity.m._malloc;
let ballast = 0;
acuity.m._malloc = bytes => { if (!ballast) ballast = malloc(acuity.m.HEAPU8.buffer.byteLength); return malloc(bytes); };
const ids = s.addObjects(profiles, positions, rotations, scales);
acuity.m._malloc = malloc;
assert.ok(ballast !== 0, 'the ballast block was allocated');
acuity.m._free(ballast);
assert.equal(ids.length, n);
assert.equal(new Set(ids).size, n, 'distinct ids');
assert.ok(acuity.m.HEAPU8.buffer.byteLength > bufferBefore, 'the heap grew');

const eyes = new Float64Array(EYE_DOUBLES * 2);
writeEye(eyes, 0, { position: [0, 1.6, 0], orientation: [0, 0, 0, 1], fov: [-45, 45, 45, -45], viewport: [1920, 1920] });
throwsAcuity(() => s.frame(new Float64Array(3 * EYE_DOUBLES), 3, 1 / 72), 1, /one or two eyes/);
throwsAcuity(() => s.frame(eyes, 0, 1 / 72), 1, /one or two eyes/);
s.frame(eyes, 1, 1 / 72);
const levels = new Uint8Array(n), flags = new Uint8Array(n);
s.getLevels(ids, levels, flags);
const near = levels[158], far = levels[315 * 316 + 158];  // straight ahead at 2 m and at 632 m
assert.ok(near < far, `a near object (level ${near}) is finer than a far one (${far})`);
assert.ok(flags.every(f => (f & FLAG.invalidInput) === 0), 'no invalid input');
assert.ok(flags[0] & FLAG.noGaze, 'no gaze given');
// The frame's stats: its triangles, and as many changes as flags say (a first frame: some).
const stats = s.frameStats();
assert.equal(stats.triangles, s.frameTriangles());
assert.equal(stats.changed, flags.filter(f => f & FLAG.changed).length);
assert.ok(stats.changed > 0, 'levels changed from the fallback');
assert.equal(stats.invalid, 0);
assert.equal(stats.gazeUsed, false);
throwsAcuity(() => s.getLevels(Uint32Array.of(n + 5), new Uint8Array(1)), 1, /acuity_get_levels/);
throwsAcuity(() => s.getLevels(ids, new Uint8Array(3)), 1, /levels: 100000 values/);

// Remove, then set transforms of a removed id: an error, and the rest still works.
s.removeObjects(ids.subarray(0, 10));
throwsAcuity(() => s.setTransforms(ids.subarray(0, 1), positions.subarray(0, 3), rotations.subarray(0, 4)), 1, /acuity_set_transforms/);
s.setTransforms(ids.subarray(10, 11), Float64Array.of(0, 0, -1000), Float32Array.of(0, 0, 0, 1), Float32Array.of(1));
s.frame(eyes, 1, 1 / 72);
s.getLevels(ids.subarray(10), levels.subarray(10), flags.subarray(10));
assert.ok(levels[10] > near, 'the moved object is coarser now');
assert.ok(s.frameTriangles() > 0);
s.destroy();

// The waits in seconds of dt (C ABI 6): 0.1 s of hysteresis and 0.3 s of waiting for a saccade go
// on the first frame at or past 0.4 s at 72 and 120 Hz; the frame counts apply while they are 0.
throwsAcuity(() => acuity.createScheduler({ hysteresis_seconds: -1 }), 1, /hysteresis_seconds/);
throwsAcuity(() => acuity.createScheduler({ max_coarsen_wait_seconds: NaN }), 1, /max_coarsen_wait_seconds/);
function framesToCoarsen(options, hz) {
  const t = acuity.createScheduler({ max_objects: 4, saccade_speed_deg_s: 200, ...options });
  t.loadProfile(profile);
  const id = t.addObjects(Int32Array.of(0), Float64Array.of(0, 0, -2), Float32Array.of(0, 0, 0, 1), null);
  t.setVelocities(id, new Float32Array(3));
  const eye = new Float64Array(EYE_DOUBLES);
  writeEye(eye, 0, { position: [0, 0, 0], orientation: [0, 0, 0, 1], fov: [-45, 45, 45, -45], viewport: [1920, 1920],
                     gaze: { angularVelocity: [0, 0, 0] } });  // a still gaze: no saccade
  const level = new Uint8Array(1);
  t.frame(eye, 1, 1 / hz);
  t.getLevels(id, level);
  const nearLevel = level[0];
  t.setTransforms(id, Float64Array.of(0, 0, -500), Float32Array.of(0, 0, 0, 1), null);
  let frames = 0;
  while (level[0] === nearLevel && frames < 400) {
    t.frame(eye, 1, 1 / hz);
    t.getLevels(id, level);
    ++frames;
  }
  t.destroy();
  return frames;
}
for (const hz of [72, 120]) {
  const frames = framesToCoarsen({ hysteresis_seconds: 0.1, max_coarsen_wait_seconds: 0.3, hysteresis_frames: 50 }, hz);
  assert.ok(frames / hz >= 0.4 * (1 - 1e-4) && frames / hz < 0.4 + 1 / hz, `${frames} frames at ${hz} Hz`);
  assert.equal(framesToCoarsen({ hysteresis_frames: 4, max_coarsen_wait: 6 }, hz), 10);
}
// Deferred tables (C ABI 10): a profile loaded deferred decides as exact evaluation does until
// buildTables, then as one loaded with its tables (fresh objects each time: their level at once;
// moving, so that the two evaluations differ somewhere).
{
  const m = 3000;
  const p0 = new Int32Array(m), velocities = new Float32Array(3 * m);
  for (let i = 0; i < m; ++i) velocities.set([Math.sin(i) * 3, Math.cos(3 * i) * 2, Math.sin(7 * i)], 3 * i);
  const levelsOf = t => {
    const made = t.addObjects(p0, positions.subarray(0, 3 * m), rotations.subarray(0, 4 * m), scales.subarray(0, m));
    t.setVelocities(made, velocities);
    t.frame(eyes, 1, 1 / 72);
    const out = new Uint8Array(m);
    t.getLevels(made, out);
    t.removeObjects(made);
    return out;
  };
  const scheduler = (options, deferred = false) => {
    const t = acuity.createScheduler({ max_objects: m, ...options });
    assert.equal(t.loadProfile(profile, { deferred }), 0);
    return t;
  };
  const built = scheduler({}), exact = scheduler({ evaluation: 1 }), deferred = scheduler({}, true);
  const want = levelsOf(built), wantExact = levelsOf(exact);
  assert.ok(want.some((l, i) => l !== wantExact[i]), 'the two evaluations differ somewhere here');
  assert.deepEqual(levelsOf(deferred), wantExact);
  throwsAcuity(() => deferred.buildTables(1), 1, /^acuity_make_tables: profile 1/);
  deferred.buildTables(0);
  assert.deepEqual(levelsOf(deferred), want);
  throwsAcuity(() => deferred.buildTables(0), 1, /^acuity_install_tables: .*has tables/);  // and freed
  throwsAcuity(() => exact.buildTables(0), 1, /keeps no tables/);
  // One view at a time, those wantedTables() lists (three a call: the list goes on): then the same
  // objects decide as with every table, and nothing more is wanted.
  const lazy = scheduler({}, true);
  assert.deepEqual(levelsOf(lazy), wantExact);
  const seen = new Set();
  for (let got; (got = lazy.wantedTables(3)).length > 0;)
    for (const { profile: p, view } of got) {
      assert.equal(p, 0);
      assert.ok(!seen.has(view), `view ${view} listed twice`);
      seen.add(view);
      lazy.buildTables(p, view);
    }
  assert.ok(seen.size > 0);
  assert.deepEqual(levelsOf(lazy), want);
  assert.deepEqual(lazy.wantedTables(), []);
  throwsAcuity(() => lazy.buildTables(0, 4096), 1, /^acuity_make_view_tables: profile 0 view 4096/);
  // Dropped when idle (C ABI 11): kept while read lately; with 0 all go, the objects decide exactly
  // again and their views are listed again.
  assert.equal(lazy.dropIdleTables(1000), 0);
  assert.ok(lazy.dropIdleTables(0) > 0);
  assert.deepEqual(levelsOf(lazy), wantExact);
  assert.deepEqual(new Set(lazy.wantedTables().map(w => w.view)), seen);
  for (const t of [built, exact, deferred, lazy]) t.destroy();
}
// Views beyond the eyes (C ABI 7): an orthographic sun over 80 m gives an object behind the eye a
// shadow level from its texels, finer for a finer map; a class no view names: the coarsest.
{
  const t = acuity.createScheduler({ max_objects: 4, max_views: 2, max_view_classes: 2 });
  t.loadProfile(profile);
  const id = t.addObjects(Int32Array.of(0), Float64Array.of(0, 0, 30), Float32Array.of(0, 0, 0, 1), null);
  const eye = new Float64Array(EYE_DOUBLES);
  writeEye(eye, 0, { position: [0, 0, 0], orientation: [0, 0, 0, 1], fov: [-45, 45, 45, -45], viewport: [1920, 1920] });
  const views = new Float64Array(VIEW_DOUBLES);
  const shadow = {};
  for (const texels of [128, 8192]) {
    writeView(views, 0, { projection: PROJECTION.orthographic, position: [0, 50, 0], orientation: [-Math.SQRT1_2, 0, 0, Math.SQRT1_2],
                          extent: [-40, 40, 40, -40], viewport: [texels, texels] });
    t.frame(eye, 1, 1 / 72, views, 1);
    const level = new Uint8Array(1);
    t.getViewLevels(0, id, level);
    shadow[texels] = level[0];
  }
  assert.ok(shadow[8192] < shadow[128], `a finer map, a finer shadow level (${shadow[8192]} < ${shadow[128]})`);
  const none = new Uint8Array(1), eyeLevel = new Uint8Array(1);
  t.getViewLevels(1, id, none);
  t.getLevels(id, eyeLevel);
  assert.ok(none[0] >= shadow[128] && none[0] >= eyeLevel[0], 'a class no view named: the coarsest');
  throwsAcuity(() => t.getViewLevels(2, id, none), 1, /view_class/);
  writeView(views, 0, { viewClass: 5, position: [0, 0, 0], orientation: [0, 0, 0, 1], viewport: [64, 64] });
  throwsAcuity(() => t.frame(eye, 1, 1 / 72, views, 1), 1, /views\[0\]/);
  throwsAcuity(() => t.frame(eye, 1, 1 / 72, views, 3), 1, /beginFrame views/);
  t.frame(eye, 1, 1 / 72);  // still works
  t.destroy();
}
console.log(`wasm api: errors as AcuityError with acuity_last_error(); ${n} objects, heap ${bufferBefore} -> ${acuity.m.HEAPU8.buffer.byteLength} bytes`);
