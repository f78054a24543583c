// The WebAssembly module chooses the same levels and flags, bit for bit, as the native library on a
// recorded scene: the demo's field (64 objects, seven real profiles: four libcgal-demo meshes and
// three third-party ones) seen still, with and without gaze, during a saccade, moving with moved
// objects, with two eyes, and through hard cases (an eye inside an object, NaN and huge positions,
// zero scale, an invalid eye), under four configurations.
import assert from 'node:assert/strict';
import path from 'node:path';
import { Euler, Quaternion, Vector3 } from 'three';

import { EYE_DOUBLES, FLAG, RULE, writeEye } from '../acuity.js';
import { env, firstDifference, loadWasm, readField, runNative, runWasm } from './scene.mjs';

const fieldDir = env('ACUITY_FIELD_DIR');
const field = readField(fieldDir);
const n = field.objects.profiles.length;
assert.equal(n, 64, 'the demo field has 64 objects');
assert.equal(field.profiles.length, 7, 'seven profiles');

const dt = 1 / 72;
const fov = [-50, 50, 47, -47], viewport = [1440, 1600];
function headEye(pos, yawDeg, pitchDeg, opts = {}) {
  const q = new Quaternion().setFromEuler(new Euler(pitchDeg * Math.PI / 180, yawDeg * Math.PI / 180, 0, 'YXZ'));
  const offset = new Vector3(opts.ipdOffset || 0, 0, 0).applyQuaternion(q);
  return { position: [pos[0] + offset.x, pos[1] + offset.y, pos[2] + offset.z], orientation: [q.x, q.y, q.z, q.w],
           fov, viewport, velocity: opts.velocity, angularVelocity: opts.angularVelocity, gaze: opts.gaze || null };
}
function gazeAt(xDeg, yDeg, opts = {}) {  // a direction in eye space, degrees right and up of -Z
  const d = new Vector3(Math.tan(xDeg * Math.PI / 180), Math.tan(yDeg * Math.PI / 180), -1).normalize();
  return { direction: [d.x, d.y, d.z], confidence: opts.confidence ?? 1, angularVelocity: opts.angularVelocity };
}
function frame(eyes, moves = null, frameDt = dt) {
  const data = new Float64Array(EYE_DOUBLES * eyes.length);
  eyes.forEach((e, i) => writeEye(data, i, e));
  return { dt: frameDt, eyeCount: eyes.length, eyes: data, moves };
}
function moves(list) {  // [[index, [x y z], yawDeg, scale]]
  const m = { indices: new Uint32Array(list.length), positions: new Float64Array(3 * list.length),
              rotations: new Float32Array(4 * list.length), scales: new Float32Array(list.length) };
  list.forEach(([i, p, yaw, s], k) => {
    const q = new Quaternion().setFromEuler(new Euler(0, yaw * Math.PI / 180, 0));
    m.indices[k] = i;
    m.positions.set(p, 3 * k);
    m.rotations.set([q.x, q.y, q.z, q.w], 4 * k);
    m.scales[k] = s;
  });
  return m;
}

const frames = [];
const start = [0, 1.6, 0];
// Still, no gaze: hysteresis settles.
for (let i = 0; i < 6; ++i) frames.push(frame([headEye(start, 0, -5)]));
// Fixations around the field, then a saccade with measured eye velocity.
for (const [x, y] of [[0, -5], [0, -5], [-20, -8], [-20, -8], [15, -3], [15, -3], [5, -10], [5, -10]])
  frames.push(frame([headEye(start, 0, -5, { gaze: gazeAt(x, y) })]));
for (const x of [-10, 0, 10]) frames.push(frame([headEye(start, 0, -5, { gaze: gazeAt(x, -4, { angularVelocity: [0, 450, 0] }) })]));
// Moving: the head walks into the field and turns; three objects move on circles.
for (let i = 0; i < 12; ++i) {
  const pos = [0.3 * i * dt * 10, 1.6, -1.5 * i * dt * 10], yaw = 2 * i;
  const circle = [5, 20, 41].map((o, k) => {
    const a = 0.4 * i + k, p = field.objects.positions;
    return [o, [p[3 * o] + Math.cos(a), p[3 * o + 1], p[3 * o + 2] + Math.sin(a)], 10 * i, field.objects.scales[o]];
  });
  frames.push(frame([headEye(pos, yaw, -4, { velocity: [3 / 7.2, 0, -15 / 7.2], angularVelocity: [0, 20, 0],
                                             gaze: gazeAt(-3 * i, -6) })], moves(circle)));
}
// Two eyes: gaze, low confidence, no gaze, one eye invalid.
const head = [0.5, 1.65, -2];
for (let i = 0; i < 4; ++i)
  frames.push(frame([-1, 1].map(s => headEye(head, -10, -5, { ipdOffset: 0.032 * s, gaze: gazeAt(-8 + 4 * i - 1.5 * s, -6) }))));
for (let i = 0; i < 3; ++i)
  frames.push(frame([-1, 1].map(s => headEye(head, -10, -5, { ipdOffset: 0.032 * s, gaze: gazeAt(2, -6, { confidence: 0.2 }) }))));
for (let i = 0; i < 3; ++i) frames.push(frame([-1, 1].map(s => headEye(head, -10, -5, { ipdOffset: 0.032 * s }))));
frames.push(frame([headEye([NaN, 1.6, 0], 0, 0), headEye(head, -10, -5, { ipdOffset: 0.032 })]));
// Hard cases: an eye inside object 0, NaN / huge positions and a zero scale, dt 0.
const p0 = Array.from(field.objects.positions.subarray(0, 3));
frames.push(frame([headEye(p0, 0, 0, { gaze: gazeAt(0, 0) })], moves([[9, [NaN, 0.75, -7], 0, 1], [10, [1e7, 0.75, -7], 0, 1], [11, [3, 0.75, -7], 0, 0]])));
frames.push(frame([headEye(p0, 30, 0)], null, 0));
frames.push(frame([headEye(start, 0, -5, { gaze: gazeAt(0, -5) })], moves([[9, [-7.5, 0.75, -7], 0, 1], [10, [-4.5, 0.75, -7], 0, 1], [11, [-1.5, 0.75, -7], 0, 1]])));

const configs = {
  perceptual: {},
  reddy: { rule: RULE.reddy },
  budget: { triangle_budget: 60000, hysteresis_frames: 3, quality: 0.5, gaze_uncertainty_deg: 2 },
  distance: { rule: RULE.distance, max_objects: 64 },
};

const acuity = await loadWasm();
const work = path.join(env('ACUITY_WEB_WORK'), 'matches_native');
const results = {};
for (const [name, config] of Object.entries(configs)) {
  const scene = { config, profiles: field.profiles, profileDir: path.join(fieldDir, 'profiles'), objects: field.objects, frames };
  const native = runNative(scene, work, name);
  const wasm = runWasm(acuity, scene);
  const diff = firstDifference(wasm, native);
  assert.equal(diff, '', `${name}: the wasm module differs from the native library: ${diff}`);
  // The scene is not trivial: levels vary across objects and frames, and the flags say why.
  const distinct = new Set(native.flatMap(f => Array.from(f.levels)));
  assert.ok(distinct.size >= 3, `${name}: only levels ${[...distinct]} chosen`);
  const changed = native.slice(1).some((f, i) => f.levels.some((l, k) => l !== native[i].levels[k]));
  assert.ok(changed, `${name}: no level changed across frames`);
  const seen = native.reduce((acc, f) => acc | f.flags.reduce((a, x) => a | x, 0), 0);
  assert.ok(seen & FLAG.invalidInput, `${name}: the NaN object is flagged`);
  if (config.rule !== RULE.distance) assert.ok(seen & FLAG.noGaze, `${name}: no-gaze frames are flagged`);
  results[name] = native;
  console.log(`${name}: ${frames.length} frames x ${n} objects equal, levels ${[...distinct].sort().join(',')}, flags seen 0x${seen.toString(16)}`);
}
// The comparison notices a difference: the configurations chose differently on the same frames.
for (const other of ['reddy', 'budget', 'distance'])
  assert.notEqual(firstDifference(results.perceptual, results[other]), '', `perceptual and ${other} chose the same`);
