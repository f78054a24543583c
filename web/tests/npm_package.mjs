// The npm package acuity-web as a user gets it: `npm pack` of the staged package (build/web/package),
// the tarball's files checked, installed offline (an empty npm cache, --offline: nothing fetched) into
// a scratch project, imported there through its exports by a node program that runs a frame.
import assert from 'node:assert/strict';
import { execFileSync } from 'node:child_process';
import fs from 'node:fs';
import path from 'node:path';

import { env } from './scene.mjs';

const npm = env('ACUITY_NPM'), pkgDir = env('ACUITY_NPM_DIR'), profile = env('ACUITY_PROFILE');
const work = env('ACUITY_WEB_WORK');
fs.rmSync(work, { recursive: true, force: true });
const project = path.join(work, 'project');
fs.mkdirSync(project, { recursive: true });
const npmEnv = { ...process.env, npm_config_cache: path.join(work, 'npm-cache'), npm_config_update_notifier: 'false' };
const run = (args, cwd) => execFileSync(npm, args, { cwd, env: npmEnv, encoding: 'utf8' });

const [packed] = JSON.parse(run(['pack', pkgDir, '--pack-destination', work, '--json'], work));
assert.equal(packed.name, 'acuity-web');
assert.equal(packed.version, env('ACUITY_VERSION'), 'web/package.json version is the project version');
const files = packed.files.map(f => f.path).sort();
assert.deepEqual(files, ['acuity.d.ts', 'acuity.js', 'dist/acuity.mjs', 'dist/acuity.wasm', 'lod_scene.js',
                         'package.json', 'wasm.d.ts']);

fs.writeFileSync(path.join(project, 'package.json'), JSON.stringify({ name: 'consumer', private: true, type: 'module' }));
run(['install', '--offline', '--no-audit', '--no-fund', path.join(work, packed.filename)], project);
assert.ok(!fs.existsSync(path.join(project, 'node_modules', 'three')), 'three is a peer: not installed');

// What a node user writes (docs/web.md).
fs.writeFileSync(path.join(project, 'main.mjs'), `
import fs from 'node:fs';
import { EYE_DOUBLES, loadAcuity, writeEye } from 'acuity-web';
import createAcuityModule from 'acuity-web/wasm';
const wasmBinary = fs.readFileSync(new URL(import.meta.resolve('acuity-web/acuity.wasm')));
const acuity = await loadAcuity(createAcuityModule, { wasmBinary });
const s = acuity.createScheduler({ max_objects: 16 });
const p = s.loadProfile(new Uint8Array(fs.readFileSync(process.argv[2])));
const n = 8, ids = s.addObjects(new Int32Array(n).fill(p), Float64Array.from({ length: 3 * n }, (_, i) => i % 3 === 2 ? -2 - 40 * (i - 2) : 0),
                                new Float32Array(4 * n).map((_, i) => i % 4 === 3 ? 1 : 0));
const eyes = new Float64Array(EYE_DOUBLES);
writeEye(eyes, 0, { position: [0, 0, 0], orientation: [0, 0, 0, 1], fov: [-45, 45, 45, -45], viewport: [1920, 1920] });
s.frame(eyes, 1, 1 / 90);
const levels = new Uint8Array(n);
s.getLevels(ids, levels);
console.log(JSON.stringify({ version: acuity.version, levels: [...levels], triangles: s.frameTriangles(),
                             from: import.meta.resolve('acuity-web') }));
s.destroy();
`);
const out = JSON.parse(execFileSync(process.execPath, ['main.mjs', profile], { cwd: project, encoding: 'utf8' }));
assert.equal(out.version, env('ACUITY_VERSION'));
assert.ok(out.from.startsWith('file://' + fs.realpathSync(path.join(project, 'node_modules', 'acuity-web'))), out.from);
assert.equal(out.levels.length, 8);
assert.ok(out.triangles > 0, JSON.stringify(out));
console.log(`npm pack ${packed.filename} (${files.length} files), installed offline: ${JSON.stringify(out)}`);
