// Shared by the web tests and bench.mjs: a recorded scene (profiles, objects, frames) run through the
// WebAssembly module (acuity.js) and through the native C ABI (native_reference, same scene as text).
import { execFileSync } from 'node:child_process';
import fs from 'node:fs';
import path from 'node:path';
import { pathToFileURL } from 'node:url';
import { Matrix4, Quaternion, Vector3 } from 'three';

import { EYE_DOUBLES, loadAcuity } from '../acuity.js';

export function env(name) {
  const v = process.env[name];
  if (!v) throw new Error(`${name} is not set (run the web tests through ctest)`);
  return v;
}

// The module of this build (ACUITY_WASM_DIR), given its .wasm bytes: node has no fetch of file URLs.
export async function loadWasm() {
  const dir = env('ACUITY_WASM_DIR');
  const factory = (await import(pathToFileURL(path.resolve(dir, 'acuity.mjs')).href)).default;
  return loadAcuity(factory, { wasmBinary: fs.readFileSync(path.join(dir, 'acuity.wasm')) });
}

// The field of `acuity demo`: its .glb's MSFT_lod nodes, in scene order, as acuity objects whose
// profile is <mesh name>.acuity. Reads the GLB's JSON chunk only.
export function readField(dir) {
  const glb = fs.readFileSync(path.join(dir, 'field.glb'));
  if (glb.readUInt32LE(0) !== 0x46546c67 || glb.readUInt32LE(16) !== 0x4e4f534a) throw new Error('field.glb: not a GLB');
  const json = JSON.parse(glb.subarray(20, 20 + glb.readUInt32LE(12)).toString('utf8'));
  const names = [], profiles = [], positions = [], rotations = [], scales = [];
  const m = new Matrix4(), p = new Vector3(), q = new Quaternion(), s = new Vector3();
  for (const n of json.scenes[json.scene ?? 0].nodes) {
    const node = json.nodes[n];
    if (!node.extensions || !node.extensions.MSFT_lod) continue;
    const name = json.meshes[node.mesh].name.replace(/[^A-Za-z0-9_-]/g, '_');
    if (!names.includes(name)) names.push(name);
    profiles.push(names.indexOf(name));
    m.fromArray(node.matrix || [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1]).decompose(p, q, s);
    positions.push(p.x, p.y, p.z);
    rotations.push(q.x, q.y, q.z, q.w);
    scales.push(Math.max(s.x, s.y, s.z));
  }
  return {
    profiles: names.map(n => `${n}.acuity`),
    objects: { profiles: Int32Array.from(profiles), positions: Float64Array.from(positions),
               rotations: Float32Array.from(rotations), scales: Float32Array.from(scales) },
  };
}

// scene: { config: {name: value}, profiles: [file names], profileDir, objects: {profiles, positions,
// rotations, scales}, frames: [{ dt, eyeCount, eyes: Float64Array, moves: null | {indices: Uint32Array,
// positions, rotations, scales}, cut: with scene.cut, { position [3], rotation [4], scale } }],
// cut: optional, one object drawn as a cluster cut: { clusters: Uint32Array, groups: Uint8Array (the
// hierarchy's records), profile: a file name in profileDir, budget: triangles (0: none) } }. Numbers
// print as JS's shortest round-trip text, which strtod reads back to the same double (and float32
// values to the same float). cutFiles: the names runNative writes the records under.
export function sceneText(scene, cutFiles = null) {
  const out = ['acuity-scene 1'];
  for (const [k, v] of Object.entries(scene.config || {})) out.push(`config ${k} ${v}`);
  for (const p of scene.profiles) out.push(`profile ${p}`);
  const o = scene.objects, n = o.profiles.length;
  out.push(`objects ${n}`);
  const tf = (pos, rot, sc, i) => [...pos.subarray(3 * i, 3 * i + 3), ...rot.subarray(4 * i, 4 * i + 4), sc[i]].map(String).join(' ');
  for (let i = 0; i < n; ++i) out.push(`${o.profiles[i]} ${tf(o.positions, o.rotations, o.scales, i)}`);
  if (scene.cut) out.push(`cut ${cutFiles.clusters} ${cutFiles.groups} ${scene.cut.profile} ${scene.cut.budget}`);
  out.push(`frames ${scene.frames.length}`);
  for (const f of scene.frames) {
    const moves = f.moves ? f.moves.indices.length : 0;
    out.push(`frame ${f.dt} ${f.eyeCount} ${moves}`);
    for (let e = 0; e < f.eyeCount; ++e) out.push('eye ' + Array.from(f.eyes.subarray(e * EYE_DOUBLES, (e + 1) * EYE_DOUBLES)).map(String).join(' '));
    for (let k = 0; k < moves; ++k) out.push(`move ${f.moves.indices[k]} ${tf(f.moves.positions, f.moves.rotations, f.moves.scales, k)}`);
    if (scene.cut) out.push(`cut ${[...f.cut.position, ...f.cut.rotation, f.cut.scale].map(String).join(' ')}`);
  }
  out.push('end', '');
  return out.join('\n');
}

// Writes the scene beside copies of its profiles (the runner reads only its own folder) and runs
// native_reference: [{ triangles, levels: Uint8Array, flags: Uint8Array }] per frame, and with a cut
// also cut: { status, flags, triangles, held, budgetCoarsened, budgetForced, clusters: [ids] }.
export function runNative(scene, workDir, name) {
  fs.mkdirSync(workDir, { recursive: true });
  const copies = scene.cut ? [...scene.profiles, scene.cut.profile] : scene.profiles;
  for (const p of copies) fs.copyFileSync(path.join(scene.profileDir, p), path.join(workDir, p));
  let cutFiles = null;
  if (scene.cut) {
    cutFiles = { clusters: `${name}.clusters`, groups: `${name}.groups` };
    const c = scene.cut.clusters;
    fs.writeFileSync(path.join(workDir, cutFiles.clusters), new Uint8Array(c.buffer, c.byteOffset, c.byteLength));
    fs.writeFileSync(path.join(workDir, cutFiles.groups), scene.cut.groups);
  }
  const file = path.join(workDir, `${name}.txt`);
  fs.writeFileSync(file, sceneText(scene, cutFiles));
  const text = execFileSync(env('ACUITY_NATIVE_REFERENCE'), [file], { encoding: 'utf8', maxBuffer: 1 << 28 });
  const lines = text.trim().split('\n'), frames = [], step = scene.cut ? 4 : 3;
  for (let i = 0; i < lines.length; i += step) {
    const head = lines[i].split(' '), lv = lines[i + 1].split(' '), fl = lines[i + 2].split(' ');
    if (head[0] !== 'frame' || lv[0] !== 'levels' || fl[0] !== 'flags') throw new Error(`native_reference: bad output at line ${i}`);
    const frame = { triangles: Number(head[3]), levels: Uint8Array.from(lv.slice(1), Number), flags: Uint8Array.from(fl.slice(1), Number) };
    if (scene.cut) {
      const c = lines[i + 3].split(' ');
      if (c[0] !== 'cut') throw new Error(`native_reference: bad output at line ${i + 3}`);
      const [status, flags, triangles, held, budgetCoarsened, budgetForced] = c.slice(1, 7).map(Number);
      frame.cut = { status, flags, triangles, held, budgetCoarsened, budgetForced, clusters: c.slice(7).map(Number) };
    }
    frames.push(frame);
  }
  return frames;
}

// The same scene through the WebAssembly module.
export function runWasm(acuity, scene) {
  const s = acuity.createScheduler(scene.config || {});
  try {
    for (const p of scene.profiles) s.loadProfile(new Uint8Array(fs.readFileSync(path.join(scene.profileDir, p))));
    const o = scene.objects;
    const ids = s.addObjects(o.profiles, o.positions, o.rotations, o.scales);
    const frames = [];
    for (const f of scene.frames) {
      if (f.moves) {
        const m = f.moves;
        s.setTransforms(Uint32Array.from(m.indices, i => ids[i]), m.positions, m.rotations, m.scales);
      }
      s.frame(f.eyes, f.eyeCount, f.dt);
      const levels = new Uint8Array(ids.length), flags = new Uint8Array(ids.length);
      s.getLevels(ids, levels, flags);
      frames.push({ triangles: s.frameTriangles(), levels, flags });
    }
    return frames;
  } finally {
    s.destroy();
  }
}

// Frame-by-frame equality; returns the first difference as text, or '' when bit for bit equal.
export function firstDifference(a, b) {
  if (a.length !== b.length) return `${a.length} frames against ${b.length}`;
  for (let f = 0; f < a.length; ++f) {
    if (a[f].triangles !== b[f].triangles) return `frame ${f}: triangles ${a[f].triangles} against ${b[f].triangles}`;
    for (const key of ['levels', 'flags']) {
      if (a[f][key].length !== b[f][key].length) return `frame ${f}: ${a[f][key].length} ${key} against ${b[f][key].length}`;
      for (let i = 0; i < a[f][key].length; ++i)
        if (a[f][key][i] !== b[f][key][i]) return `frame ${f}, object ${i}: ${key} ${a[f][key][i]} against ${b[f][key][i]}`;
    }
  }
  return '';
}
