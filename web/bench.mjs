#!/usr/bin/env node
// node web/bench.mjs [BUILD_DIR]: the WebAssembly module's cost per object as a ratio to the native
// library's, in the same run on the same scene: 10,000 objects (the demo field's seven profiles on a
// 100 x 100 grid), 60 frames of a moving head with gaze and 100 moved objects per frame, each frame
// set_transforms + begin + update + end + get_levels. Native: build/web/native_reference --repeat.
// Needs the field and profiles `ctest -L web` makes in BUILD_DIR/web/field (or `acuity demo`'s BUILD_DIR/demo).
import fs from 'node:fs';
import path from 'node:path';
import { execFileSync } from 'node:child_process';
import { fileURLToPath } from 'node:url';

const repo = path.dirname(path.dirname(fileURLToPath(import.meta.url)));
const build = path.resolve(process.argv[2] || path.join(repo, 'build'));
const fieldDir = [path.join(build, 'web', 'field'), path.join(build, 'demo')].find(d => fs.existsSync(path.join(d, 'field.glb')));
if (!fieldDir) {
  console.error(`bench.mjs: no field.glb in ${build}/web/field or ${build}/demo: run ctest --test-dir ${build} -L web (or acuity demo) first`);
  process.exit(1);
}
process.env.ACUITY_WASM_DIR ??= path.join(build, 'web');
process.env.ACUITY_NATIVE_REFERENCE ??= path.join(build, 'web', 'native_reference');
const { EYE_DOUBLES, writeEye } = await import('./acuity.js');
const { loadWasm, readField, sceneText } = await import('./tests/scene.mjs');

const field = readField(fieldDir);
const side = 100, n = side * side, FRAMES = 60, MOVED = 100;
const objects = { profiles: new Int32Array(n), positions: new Float64Array(3 * n), rotations: new Float32Array(4 * n), scales: new Float32Array(n) };
for (let i = 0; i < n; ++i) {
  objects.profiles[i] = i % field.profiles.length;
  objects.positions.set([(i % side - side / 2) * 3, 0.75, -4 - Math.floor(i / side) * 3], 3 * i);
  const yaw = 0.7 * i;
  objects.rotations.set([0, Math.fround(Math.sin(yaw / 2)), 0, Math.fround(Math.cos(yaw / 2))], 4 * i);
  objects.scales[i] = field.objects.scales[i % field.objects.scales.length];
}
const frames = [];
for (let f = 0; f < FRAMES; ++f) {
  const eyes = new Float64Array(EYE_DOUBLES);
  const a = f * 0.01;
  writeEye(eyes, 0, { position: [0.2 * f, 1.7, -0.5 * f], orientation: [0, Math.fround(Math.sin(a)), 0, Math.fround(Math.cos(a))],
                      fov: [-50, 50, 47, -47], viewport: [1440, 1600], velocity: [12, 0, -30],
                      gaze: { direction: [Math.fround(Math.sin(0.1 * f) * 0.2), -0.1, -0.97], confidence: 1 } });
  const moves = { indices: new Uint32Array(MOVED), positions: new Float64Array(3 * MOVED), rotations: new Float32Array(4 * MOVED), scales: new Float32Array(MOVED) };
  for (let k = 0; k < MOVED; ++k) {
    const i = (k * 97 + f * 13) % n;
    moves.indices[k] = i;
    moves.positions.set([objects.positions[3 * i] + Math.sin(f), 0.75, objects.positions[3 * i + 2] + Math.cos(f)], 3 * k);
    moves.rotations.set(objects.rotations.subarray(4 * i, 4 * i + 4), 4 * k);
    moves.scales[k] = objects.scales[i];
  }
  frames.push({ dt: 1 / 72, eyeCount: 1, eyes, moves });
}
const scene = { config: { max_objects: n }, profiles: field.profiles, profileDir: path.join(fieldDir, 'profiles'), objects, frames };

// WebAssembly: the scheduler, then each round is the 60 frames.
const acuity = await loadWasm();
const s = acuity.createScheduler(scene.config);
for (const p of scene.profiles) s.loadProfile(new Uint8Array(fs.readFileSync(path.join(scene.profileDir, p))));
const ids = s.addObjects(objects.profiles, objects.positions, objects.rotations, objects.scales);
const levels = new Uint8Array(n), flags = new Uint8Array(n);
const moveIds = frames.map(f => Uint32Array.from(f.moves.indices, i => ids[i]));
function round() {
  frames.forEach((f, k) => {
    s.setTransforms(moveIds[k], f.moves.positions, f.moves.rotations, f.moves.scales);
    s.frame(f.eyes, 1, f.dt);
    s.getLevels(ids, levels, flags);
  });
}
// Alternating wasm and native timings, three each, the best of each kept (the machine is shared).
const work = path.join(build, 'web', 'bench');
fs.mkdirSync(work, { recursive: true });
for (const p of scene.profiles) fs.copyFileSync(path.join(scene.profileDir, p), path.join(work, p));
fs.writeFileSync(path.join(work, 'bench.txt'), sceneText(scene));
round();  // warm-up
let rounds = 0, wasmSeconds = Infinity, nativeSeconds = Infinity;
for (let trial = 0; trial < 3; ++trial) {
  let r = 0;
  const t0 = performance.now();
  while (performance.now() - t0 < 1000 || r < 3) { round(); ++r; }
  wasmSeconds = Math.min(wasmSeconds, (performance.now() - t0) / 1000 / (r * FRAMES));
  rounds = Math.max(rounds, r);
  const native = JSON.parse(execFileSync(process.env.ACUITY_NATIVE_REFERENCE, [path.join(work, 'bench.txt'), '--repeat', String(r)], { encoding: 'utf8' }));
  nativeSeconds = Math.min(nativeSeconds, native.seconds_per_frame);
}
s.destroy();
const native = { seconds_per_frame: nativeSeconds };

const wasmBytes = fs.statSync(path.join(process.env.ACUITY_WASM_DIR, 'acuity.wasm')).size;
const glueBytes = fs.statSync(path.join(process.env.ACUITY_WASM_DIR, 'acuity.mjs')).size;
const result = {
  objects: n, frames_per_trial: rounds * FRAMES, trials: 3, wasm_bytes: wasmBytes, mjs_bytes: glueBytes,
  wasm_ns_per_object: 1e9 * wasmSeconds / n, native_ns_per_object: 1e9 * native.seconds_per_frame / n,
  ratio_wasm_to_native: wasmSeconds / native.seconds_per_frame,
};
console.log(JSON.stringify(result, null, 2));
console.log(`acuity.wasm ${(wasmBytes / 1024).toFixed(1)} KiB + acuity.mjs ${(glueBytes / 1024).toFixed(1)} KiB; ` +
            `per object per frame: wasm ${result.wasm_ns_per_object.toFixed(1)} ns, native ${result.native_ns_per_object.toFixed(1)} ns, ` +
            `ratio ${result.ratio_wasm_to_native.toFixed(2)}x (${n} objects, node ${process.version})`);
