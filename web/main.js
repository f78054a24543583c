// The acuity page: lodgen's MSFT_lod scene as THREE.LOD objects whose level acuity (WebAssembly)
// chooses every frame from the camera, the mouse as a gaze proxy, or WebXR's eyes and gaze.
//
// URL parameters: scene (default content/field.glb), profiles (default content/profiles/), quality,
// cut and cutProfile (an object with a cluster hierarchy, lodgen --clusters' glTF, and its chain's
// profile: drawn as acuity's cut, 3 m across, in front of the field), cutBudget (the most triangles
// the cut may draw, spent on its least visible groups first; default none), and for tests frames=N: a
// scripted camera and gaze for N frames at 60 Hz (with a cut: the camera still before it, the gaze
// sweeping across it), then window.acuityRecord holds every frame's inputs and levels (and cuts)
// and window.acuityDone is true.
import * as THREE from 'three';
import { OrbitControls } from 'three/addons/controls/OrbitControls.js';

// acuity-web's exports (web/package.json), mapped to the served files by index.html's import map.
import { AcuityError, EYE_DOUBLES, loadAcuity, writeEye } from 'acuity-web';
import { ContentError, fetchBytes, loadClusterObject, loadLodScene, showCut, showLevel } from 'acuity-web/lod-scene';

const params = new URLSearchParams(location.search);
const sceneUrl = params.get('scene') || 'content/field.glb';
const profileDir = params.get('profiles') || 'content/profiles/';
const scriptedFrames = Number(params.get('frames') || 0);
const cutUrl = params.get('cut'), cutProfileUrl = params.get('cutProfile');
const cutBudget = Number(params.get('cutBudget') || 0);
const PALETTE = [0x2060ff, 0x20d0e0, 0x30c040, 0xf0e020, 0xff8020, 0xe02020, 0xc040c0, 0xffffff];

const overlay = document.getElementById('overlay');
const messageBox = document.getElementById('message');
window.acuityDone = false;

// Bad content (missing file, profile failing validation, not lodgen's scene): said on the page and
// in the console; nothing is left to throw uncaught.
function fail(error) {
  const known = error instanceof ContentError || error instanceof AcuityError;
  const text = known ? error.message : `unexpected error: ${error && error.stack || error}`;
  console.error(`acuity: ${text}`);
  messageBox.textContent = text;
  messageBox.style.display = 'block';
  overlay.textContent = 'acuity: stopped';
  window.acuityError = text;
  window.acuityDone = true;
}
window.addEventListener('unhandledrejection', e => { e.preventDefault(); fail(e.reason); });

async function loadModule() {
  let factory;
  try {
    factory = (await import('acuity-web/wasm')).default;
  } catch (e) {
    throw new ContentError(`wasm/acuity.mjs: the WebAssembly module is missing; build it (cmake --build build --target acuity_wasm) (${e.message})`);
  }
  return loadAcuity(factory);
}

async function main() {
  const renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
  renderer.setPixelRatio(window.devicePixelRatio);
  renderer.setSize(window.innerWidth, window.innerHeight);
  document.body.appendChild(renderer.domElement);

  const acuity = await loadModule();
  const content = await loadLodScene(await fetchBytes(sceneUrl, 'scene'), sceneUrl);
  const scheduler = acuity.createScheduler(params.has('quality') ? { quality: Number(params.get('quality')) } : {});
  for (const name of content.profiles) {
    const url = `${profileDir}${name}.acuity`;
    const bytes = await fetchBytes(url, 'profile');
    try {
      scheduler.loadProfile(bytes);
    } catch (e) {
      throw new ContentError(`profile ${url} failed validation: ${e.message}`);
    }
  }

  // The object drawn as a cluster cut: 3 m across, its centre at CUT_AT.
  const CUT_AT = new THREE.Vector3(0, 1.5, -8);
  let cut = null;
  if (cutUrl) {
    const object = await loadClusterObject(await fetchBytes(cutUrl, 'cut'), cutUrl);
    let hierarchy;
    try {
      hierarchy = acuity.createHierarchy(object.clusters, object.groups, await fetchBytes(cutProfileUrl || '', 'cut profile'));
    } catch (e) {
      if (e instanceof AcuityError) throw new ContentError(`cut ${cutUrl}: ${e.message}`);
      throw e;
    }
    const holder = new THREE.Group();
    const s = 3 / (2 * object.sphere.radius);
    holder.scale.setScalar(s);
    holder.position.copy(CUT_AT).addScaledVector(object.sphere.center, -s);
    holder.add(object.scene);
    cut = { ...object, holder, hierarchy, state: hierarchy.createCut(), ids: null, triangles: 0 };
  }

  const scene = new THREE.Scene();
  scene.background = new THREE.Color(0x9fb4c8);
  scene.add(new THREE.HemisphereLight(0xe8f0ff, 0x404030, 2.0));
  const sun = new THREE.DirectionalLight(0xffffff, 2.0);
  sun.position.set(5, 10, 4);
  scene.add(sun);
  const fill = new THREE.DirectionalLight(0xffffff, 0.8);
  fill.position.set(-4, 3, 8);
  scene.add(fill);
  const ground = new THREE.Mesh(new THREE.PlaneGeometry(200, 200), new THREE.MeshLambertMaterial({ color: 0x6b7260 }));
  ground.rotation.x = -Math.PI / 2;
  scene.add(ground);
  scene.add(content.scene);
  content.scene.updateMatrixWorld(true);
  if (cut) {
    scene.add(cut.holder);
    cut.holder.updateMatrixWorld(true);
  }

  // acuity's objects: one per LOD, its transform from the LOD's world matrix.
  const n = content.lods.length;
  const profiles = new Int32Array(n), positions = new Float64Array(3 * n), rotations = new Float32Array(4 * n), scales = new Float32Array(n);
  const p = new THREE.Vector3(), q = new THREE.Quaternion(), sc = new THREE.Vector3();
  content.lods.forEach(({ lod, profile }, i) => {
    lod.matrixWorld.decompose(p, q, sc);
    profiles[i] = profile;
    positions.set([p.x, p.y, p.z], 3 * i);
    rotations.set([q.x, q.y, q.z, q.w], 4 * i);
    scales[i] = Math.max(sc.x, sc.y, sc.z);
  });
  const ids = scheduler.addObjects(profiles, positions, rotations, scales);
  const levels = new Uint8Array(n), flags = new Uint8Array(n);
  const maxLevels = Math.max(...content.lods.map(l => l.lod.levels.length));

  // Colour by level: unlit palette materials swapped in and out.
  const paletteMaterials = PALETTE.map(c => new THREE.MeshBasicMaterial({ color: c }));
  const originals = new Map();
  content.scene.traverse(o => { if (o.isMesh) originals.set(o, o.material); });
  const colourBox = document.getElementById('colour');
  const legend = document.getElementById('legend');
  legend.innerHTML = PALETTE.slice(0, maxLevels).map((c, k) => `<span style="background:#${c.toString(16).padStart(6, '0')}"></span>${k}`).join('');
  function applyColours() {
    const on = colourBox.checked;
    legend.hidden = !on;
    for (const { lod } of content.lods)
      lod.levels.forEach(({ object }, k) => object.traverse(o => {
        if (o.isMesh) o.material = on ? paletteMaterials[Math.min(k, PALETTE.length - 1)] : originals.get(o);
      }));
  }
  applyColours();

  const camera = new THREE.PerspectiveCamera(70, window.innerWidth / window.innerHeight, 0.05, 400);
  camera.position.set(0, 2.2, 3);
  const controls = new OrbitControls(camera, renderer.domElement);
  controls.target.set(0, 0.75, -14);
  controls.maxPolarAngle = 0.49 * Math.PI;  // stay above the ground
  controls.update();
  colourBox.addEventListener('change', () => { applyColours(); renderer.render(scene, camera); });
  window.addEventListener('resize', () => {
    camera.aspect = window.innerWidth / window.innerHeight;
    camera.updateProjectionMatrix();
    renderer.setSize(window.innerWidth, window.innerHeight);
  });

  // The mouse as a gaze proxy: normalised device coordinates while over the canvas.
  let mouse = null;
  renderer.domElement.addEventListener('pointermove', e => {
    const r = renderer.domElement.getBoundingClientRect();
    mouse = [2 * (e.clientX - r.left) / r.width - 1, 1 - 2 * (e.clientY - r.top) / r.height];
  });
  renderer.domElement.addEventListener('pointerleave', () => { mouse = null; });

  const eyes = new Float64Array(2 * EYE_DOUBLES);
  const previous = [null, null];
  const size = new THREE.Vector2();
  function cameraEye(cam, i, dt, fovTan, viewport, gazeDirection) {
    cam.getWorldPosition(p);
    cam.getWorldQuaternion(q);
    const velocity = previous[i] && dt > 0 ? [(p.x - previous[i][0]) / dt, (p.y - previous[i][1]) / dt, (p.z - previous[i][2]) / dt] : [0, 0, 0];
    previous[i] = [p.x, p.y, p.z];
    const deg = t => Math.atan(t) * 180 / Math.PI;
    writeEye(eyes, i, { position: [p.x, p.y, p.z], orientation: [q.x, q.y, q.z, q.w],
                        fov: fovTan.map(deg), viewport, velocity,
                        gaze: gazeDirection ? { direction: gazeDirection, confidence: 1 } : null });
  }
  function gazeFromNdc(ndc, fovTan) {  // the eye-space direction through a point of the image
    if (!ndc) return null;
    const x = ndc[0] < 0 ? -ndc[0] * fovTan[0] : ndc[0] * fovTan[1];
    const y = ndc[1] < 0 ? -ndc[1] * fovTan[3] : ndc[1] * fovTan[2];
    const d = new THREE.Vector3(x, y, -1).normalize();
    return [d.x, d.y, d.z];
  }
  function monoEye(dt, ndc) {
    const ty = Math.tan(camera.fov * Math.PI / 360), tx = ty * camera.aspect;
    const fovTan = [-tx, tx, ty, -ty];  // tangents of left, right, up, down
    renderer.getDrawingBufferSize(size);
    cameraEye(camera, 0, dt, fovTan, [size.x, size.y], gazeFromNdc(ndc, fovTan));
    return 1;
  }
  // WebXR: both eyes from the XR camera; gaze from a 'gaze' input source when the browser offers one.
  let xrReference = null;
  function xrEyes(dt, frame) {
    const cams = renderer.xr.getCamera().cameras;
    let gazeWorld = null;
    if (frame && xrReference)
      for (const source of frame.session.inputSources)
        if (source.targetRayMode === 'gaze') {
          const pose = frame.getPose(source.targetRaySpace, xrReference);
          if (pose) gazeWorld = new THREE.Vector3(0, 0, -1).applyQuaternion(new THREE.Quaternion().copy(pose.transform.orientation));
        }
    const count = Math.min(2, cams.length);
    for (let i = 0; i < count; ++i) {
      const e = cams[i].projectionMatrix.elements;  // tangents from the projection matrix
      const fovTan = [(e[8] - 1) / e[0], (e[8] + 1) / e[0], (e[9] + 1) / e[5], (e[9] - 1) / e[5]];
      let dir = null;
      if (gazeWorld) {
        const d = gazeWorld.clone().applyQuaternion(cams[i].getWorldQuaternion(new THREE.Quaternion()).invert());
        dir = [d.x, d.y, d.z];
      }
      cameraEye(cams[i], i, dt, fovTan, [cams[i].viewport.z, cams[i].viewport.w], dir);
    }
    return count;
  }
  const vrButton = document.getElementById('vr');
  if (navigator.xr && navigator.xr.isSessionSupported) {
    navigator.xr.isSessionSupported('immersive-vr').then(ok => {
      if (!ok) return;
      vrButton.hidden = false;
      vrButton.addEventListener('click', async () => {
        try {
          const session = await navigator.xr.requestSession('immersive-vr', { optionalFeatures: ['local-floor'] });
          renderer.xr.enabled = true;
          await renderer.xr.setSession(session);
          xrReference = renderer.xr.getReferenceSpace();
          session.addEventListener('end', () => { renderer.xr.enabled = false; xrReference = null; });
        } catch (e) {
          console.warn(`acuity: WebXR session not started: ${e.message}`);
        }
      });
    }).catch(() => {});
  }

  // Scripted run for tests: a walk into the field while turning, the gaze on a slow circle.
  function scriptCamera(frame) {
    const t = frame / Math.max(1, scriptedFrames - 1);
    if (cut) {  // still, 12 m before the cut's object; the gaze sweeps from far left to far right
      camera.position.set(CUT_AT.x, CUT_AT.y, CUT_AT.z + 12);
      camera.lookAt(CUT_AT);
      camera.updateMatrixWorld(true);
      return [-0.9 + 1.8 * t, 0];
    }
    camera.position.set(-2 + 4 * t, 2.0 - 0.3 * t, 3 - 9 * t);
    camera.lookAt(6 * Math.sin(2 * t) - 1, 0.6, camera.position.z - 12);
    camera.updateMatrixWorld(true);
    const a = 6 * t;
    return frame % 20 < 15 ? [0.4 * Math.cos(a), -0.3 + 0.3 * Math.sin(a)] : null;  // blinks: no gaze
  }

  const record = { profiles: content.profiles, objects: { profiles: Array.from(profiles), positions: Array.from(positions),
                   rotations: Array.from(rotations), scales: Array.from(scales) }, frames: [],
                   cut: cut ? { clusters: Array.from(cut.clusters), groups: Array.from(cut.groups) } : null };
  const frustum = new THREE.Frustum(), projScreen = new THREE.Matrix4(), sphere = new THREE.Sphere();
  let last = performance.now(), frameIndex = 0, acuityMs = 0;
  function frame(time, xrFrame) {
    try {
      let dt = Math.min(0.1, (time - last) / 1000);
      last = time;
      let ndc = mouse;
      if (scriptedFrames) {
        dt = 1 / 60;
        ndc = scriptCamera(frameIndex);
      }
      const eyeCount = renderer.xr.isPresenting ? xrEyes(dt, xrFrame) : monoEye(dt, ndc);
      const t0 = performance.now();
      scheduler.frame(eyes, eyeCount, dt);
      scheduler.getLevels(ids, levels, flags);
      acuityMs = 0.9 * acuityMs + 0.1 * (performance.now() - t0);
      let cutFrame = null;
      if (cut) {  // the cut of this frame's eyes and gaze; the index buffer rebuilt when it changed
        cut.mesh.updateMatrixWorld(true);
        cut.mesh.matrixWorld.decompose(p, q, sc);
        const r = scheduler.selectCut(cut.hierarchy, cut.state, [p.x, p.y, p.z], [q.x, q.y, q.z, q.w], Math.max(sc.x, sc.y, sc.z),
                                      null, cutBudget);
        const same = cut.ids && cut.ids.length === r.clusters.length && cut.ids.every((c, k) => c === r.clusters[k]);
        if (!same) {
          cut.triangles = showCut(cut, r.clusters);
          cut.ids = r.clusters;
        }
        cutFrame = { triangles: r.triangles, clusters: Array.from(r.clusters), drawnIndices: cut.mesh.geometry.index.count,
                     status: r.status, flags: r.flags, held: r.held, budgetCoarsened: r.budgetCoarsened,
                     budgetForced: r.budgetForced, rebuilt: !same,
                     transform: { position: [p.x, p.y, p.z], rotation: [q.x, q.y, q.z, q.w], scale: Math.max(sc.x, sc.y, sc.z) } };
      }
      const lodLevels = [];
      content.lods.forEach(({ lod }, i) => {
        showLevel(lod, Math.min(levels[i], lod.levels.length - 1));
        lodLevels.push(lod.getCurrentLevel());
      });

      // What is drawn against every in-view object at its finest.
      projScreen.multiplyMatrices(camera.projectionMatrix, camera.matrixWorldInverse);
      frustum.setFromProjectionMatrix(projScreen);
      let drawn = 0, finest = 0, inView = 0;
      content.lods.forEach(({ lod, triangles, sphere: local }) => {
        sphere.copy(local).applyMatrix4(lod.matrixWorld);
        if (!frustum.intersectsSphere(sphere)) return;
        ++inView;
        drawn += triangles[lod.getCurrentLevel()];
        finest += triangles[0];
      });
      renderer.render(scene, camera);
      const counts = new Array(maxLevels).fill(0);
      for (let i = 0; i < n; ++i) counts[Math.min(levels[i], maxLevels - 1)]++;
      overlay.textContent =
        `acuity ${acuity.version} (WebAssembly), ${n} objects, ${inView} in view\n` +
        `triangles drawn   ${drawn.toLocaleString('en')}  (renderer: ${renderer.info.render.triangles.toLocaleString('en')})\n` +
        `all-finest        ${finest.toLocaleString('en')}\n` +
        `savings           ${finest ? (100 * (1 - drawn / finest)).toFixed(1) : '0.0'} %\n` +
        `acuity per frame  ${acuityMs.toFixed(3)} ms\n` +
        `objects per level ${counts.join(' / ')}\n` +
        `gaze              ${renderer.xr.isPresenting ? 'WebXR' : !ndc ? 'none' : scriptedFrames ? 'scripted' : 'mouse'}` +
        (cut ? `\ncut               ${cut.triangles.toLocaleString('en')} of ${(cut.indices.length / 3).toLocaleString('en')} hierarchy triangles, ${cut.ids.length} clusters` +
               (cutBudget ? ` (budget ${cutBudget.toLocaleString('en')})` : '') : '');
      window.acuityStats = { drawn, finest, inView, acuityMs };

      if (scriptedFrames) {
        record.frames.push({ dt, eyeCount, eyes: Array.from(eyes.subarray(0, eyeCount * EYE_DOUBLES)),
                             levels: Array.from(levels), flags: Array.from(flags), lodLevels, drawn, finest, cut: cutFrame });
        if (++frameIndex === scriptedFrames) {
          renderer.setAnimationLoop(null);
          window.acuityRecord = record;
          window.acuityDone = true;
        }
      }
    } catch (e) {
      renderer.setAnimationLoop(null);
      fail(e);
    }
  }
  renderer.setAnimationLoop(frame);
}

main().catch(fail);
