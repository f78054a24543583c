// acuity.js — acuity's runtime in WebAssembly (acuity.mjs + acuity.wasm, built by web/CMakeLists.txt)
// for the browser and node. Calls are batched on typed arrays: a frame is a few calls whatever the
// number of objects. Every failing call throws an AcuityError carrying acuity_last_error()'s text.
//
//   import createAcuityModule from './acuity.mjs';
//   const acuity = await loadAcuity(createAcuityModule);      // node: loadAcuity(f, { wasmBinary })
//   const s = acuity.createScheduler({ quality: 1 });         // acuity_config field names
//   const p = s.loadProfile(bytes);                           // Uint8Array of a .acuity file
//   const ids = s.addObjects(profiles, positions, rotations, scales);  // Int32 n, Float64 3n, Float32 4n, Float32 n
//   each frame: s.setTransforms(ids, positions, rotations, scales);
//               s.frame(eyes, eyeCount, dt);                  // eyes: Float64Array, EYE_DOUBLES per eye
//               s.getLevels(ids, levels, flags);              // Uint8Arrays of ids.length
//   views beyond the eyes (a shadow map's light, a mirror): createScheduler({ max_views, max_view_classes }),
//               s.frame(eyes, eyeCount, dt, views, viewCount); // views: Float64Array, VIEW_DOUBLES per view
//               s.getViewLevels(viewClass, ids, levels);
//   cluster cuts (detail inside one object; lodgen --clusters, docs/design.md section 6):
//               const h = acuity.createHierarchy(clusters, groups, profileBytes);  // Uint32Array 4n, Uint8Array 32 per group
//               const cut = h.createCut();                    // per object: hysteresis memory and the drawn ids
//               each frame, after s.frame(...): s.selectCut(h, cut, position, rotation, scale) -> { clusters, triangles, ... }
//   s.destroy();

export const RULE = Object.freeze({ perceptual: 0, reddy: 1, distance: 2, screenSize: 3 });
export const FLAG = Object.freeze({ invalidInput: 1, eyeInside: 2, noGaze: 4, budgetForced: 8, changed: 16, held: 32 });
export const STATUS = Object.freeze(['ok', 'invalid argument', 'bad profile', 'full', 'out of memory', 'internal error']);
const CUT_RESULT_BYTES = 40;  // acuity_cut_result as C ABI version 9 lays it out (ACUITY_CUT_RESULT_SIZE_V9)

export class AcuityError extends Error {
  constructor(message, status) {
    super(message);
    this.name = 'AcuityError';
    this.status = status;  // acuity_status
  }
}

// One eye as EYE_DOUBLES doubles (the layout of web/acuity_web.c), written at eyes[i * EYE_DOUBLES].
// eye: { position[3] m, orientation[4] x y z w (looks along -Z, +Y up), fov[4] deg (left<0, right,
// up, down<0), viewport[2] px, velocity[3] m/s, angularVelocity[3] deg/s,
// gaze: { direction[3] unit eye space, confidence, angularVelocity[3] deg/s } or null }.
export const EYE_DOUBLES = 28;
export function writeEye(eyes, i, eye) {
  const o = i * EYE_DOUBLES;
  const put = (at, values, n, fallback) => { for (let k = 0; k < n; ++k) eyes[o + at + k] = values ? values[k] : fallback[k]; };
  put(0, eye.position, 3);
  put(3, eye.orientation, 4);
  put(7, eye.fov, 4);
  put(11, eye.viewport, 2);
  put(13, eye.velocity, 3, [0, 0, 0]);
  put(16, eye.angularVelocity, 3, [0, 0, 0]);
  const g = eye.gaze;
  put(19, g && g.direction, 3, [0, 0, -1]);
  eyes[o + 22] = g ? (g.confidence ?? 1) : 0;
  put(23, g && g.angularVelocity, 3, [0, 0, 0]);
  eyes[o + 26] = g ? 1 : 0;
  eyes[o + 27] = g && g.angularVelocity ? 1 : 0;
}

// One view beyond the eyes as VIEW_DOUBLES doubles (web/acuity_web.c), written at views[i * VIEW_DOUBLES]
// (acuity_view, acuity::View). view: { viewClass, projection (PROJECTION), rule (VIEW_RULE),
// pixelError (texels, default 1), position[3] m, orientation[4] x y z w (looks along -Z),
// fov[4] deg (perspective), extent[4] m left right top bottom (orthographic), viewport[2] texels }.
export const PROJECTION = Object.freeze({ perspective: 0, orthographic: 1 });
export const VIEW_RULE = Object.freeze({ footprint: 0, asEye: 1 });
export const VIEW_DOUBLES = 21;
export const MAX_VIEWS = 64;  // per frame through acuity.js
export function writeView(views, i, view) {
  const o = i * VIEW_DOUBLES;
  const put = (at, values, n, fallback) => { for (let k = 0; k < n; ++k) views[o + at + k] = values ? values[k] : fallback[k]; };
  views[o] = view.viewClass ?? 0;
  views[o + 1] = view.projection ?? PROJECTION.perspective;
  views[o + 2] = view.rule ?? VIEW_RULE.footprint;
  views[o + 3] = view.pixelError ?? 1;
  put(4, view.position, 3);
  put(7, view.orientation, 4);
  put(11, view.fov, 4, [-45, 45, 45, -45]);
  put(15, view.extent, 4, [-10, 10, 10, -10]);
  put(19, view.viewport, 2);
}

export async function loadAcuity(factory, moduleOptions = {}) {
  const module = await factory(moduleOptions);
  return new Acuity(module);
}

export class Acuity {
  constructor(module) {
    this.m = module;
    if (module._acuity_web_eye_doubles() !== EYE_DOUBLES || module._acuity_web_view_doubles() !== VIEW_DOUBLES)
      throw new AcuityError(`acuity.js expects ${EYE_DOUBLES} doubles per eye and ${VIEW_DOUBLES} per view, the module ${module._acuity_web_eye_doubles()} and ${module._acuity_web_view_doubles()}`, 5);
    const v = module._acuity_version();
    this.version = `${Math.floor(v / 10000)}.${Math.floor(v / 100) % 100}.${v % 100}`;
  }

  lastError() { return this.m.UTF8ToString(this.m._acuity_last_error()); }

  check(status, call) {
    if (status !== 0) {
      const text = this.lastError();
      const message = text.startsWith(call + ':') ? text : `${call}: ${text || STATUS[status] || 'status ' + status}`;
      throw new AcuityError(message, status);
    }
  }

  // Heap memory; throws when the module cannot grow.
  alloc(bytes) {
    const p = this.m._malloc(Math.max(8, bytes));
    if (!p) throw new AcuityError(`out of memory allocating ${bytes} bytes in the wasm heap`, 4);
    return p;
  }

  // clusters: Uint32Array of 4 per cluster, groups: Uint8Array of 32 bytes per group (the records
  // of ACUITY_cluster_hierarchy, docs/lodgen.md), profile: Uint8Array of the object's .acuity file.
  // Throws an AcuityError naming the cluster or group of a broken hierarchy, or for a bad profile.
  createHierarchy(clusters, groups, profile) {
    const m = this.m;
    if (!(clusters instanceof Uint32Array) || clusters.length % 4 !== 0)
      throw new AcuityError('createHierarchy: clusters must be a Uint32Array of 4 values per cluster', 1);
    if (!(groups instanceof Uint8Array) || groups.length % 32 !== 0)
      throw new AcuityError('createHierarchy: groups must be a Uint8Array of 32 bytes per group', 1);
    if (!(profile instanceof Uint8Array)) throw new AcuityError('createHierarchy: profile must be a Uint8Array', 1);
    const pc = this.alloc(clusters.byteLength), pg = this.alloc(groups.byteLength), pp = this.alloc(profile.length),
          out = this.alloc(4);
    try {
      m.HEAPU8.set(new Uint8Array(clusters.buffer, clusters.byteOffset, clusters.byteLength), pc);
      m.HEAPU8.set(groups, pg);
      m.HEAPU8.set(profile, pp);
      this.check(m._acuity_hierarchy_create_from_profile(pc, clusters.length / 4, pg, groups.length / 32, pp,
                                                         profile.length, out),
                 'acuity_hierarchy_create_from_profile');
      return new Hierarchy(this, m.HEAPU32[out >> 2], clusters.length / 4, groups.length / 32);
    } finally {
      for (const p of [pc, pg, pp, out]) m._free(p);
    }
  }

  // options: acuity_config fields by name, e.g. { max_objects: 4096, quality: 1, rule: RULE.distance }.
  createScheduler(options = {}) {
    const m = this.m, cfg = this.alloc(m._acuity_web_config_size()), out = this.alloc(4);
    try {
      m._acuity_config_default(cfg);
      for (const [name, value] of Object.entries(options)) {
        const bytes = new TextEncoder().encode(name + '\0');
        const p = this.alloc(bytes.length);
        m.HEAPU8.set(bytes, p);
        const st = m._acuity_web_config_set(cfg, p, Number(value));
        m._free(p);
        if (st !== 0) throw new AcuityError(`createScheduler: '${name}' = ${value} is not a valid acuity_config field value`, st);
      }
      this.check(m._acuity_create(cfg, out), 'acuity_create');
      return new Scheduler(this, m.HEAPU32[out >> 2]);
    } finally {
      m._free(cfg);
      m._free(out);
    }
  }
}

// A cluster hierarchy in the module (acuity_hierarchy_create_from_profile): its records as
// ACUITY_cluster_hierarchy stores them, its per-group loss derived from the object's profile.
export class Hierarchy {
  constructor(acuity, handle, clusterCount, groupCount) {
    this.a = acuity;
    this.m = acuity.m;
    this.h = handle;
    this.clusterCount = clusterCount;
    this.groupCount = groupCount;
    this.memoryBytes = this.m._acuity_cut_memory_size(handle);
  }
  // One object's cut state in the wasm heap: its memory (hysteresis per group, zeroed) and room for
  // every cluster id; destroy() frees it.
  createCut() {
    const memory = this.a.alloc(this.memoryBytes), drawn = this.a.alloc(4 * this.clusterCount);
    this.m.HEAPU8.fill(0, memory, memory + this.memoryBytes);
    const m = this.m;
    return { memory, drawn, destroy() { m._free(memory); m._free(drawn); } };
  }
  destroy() {
    if (this.h) this.m._acuity_hierarchy_destroy(this.h);
    this.h = 0;
  }
}

// Typed-array arguments are copied into one reusable block of wasm memory per call.
export class Scheduler {
  constructor(acuity, handle) {
    this.a = acuity;
    this.m = acuity.m;
    this.s = handle;
    this.scratch = 0;
    this.scratchBytes = 0;
    this.objectSlots = 0;  // update range: every slot ever used
  }

  // Copies arrays into the scratch block (8-byte aligned each); returns their heap addresses.
  stage(arrays, outputs = []) {
    let total = 0;
    const sizes = [...arrays, ...outputs].map(a => { const b = (a.byteLength + 7) & ~7; total += b; return b; });
    if (total > this.scratchBytes) {
      const bytes = Math.max(total, 2 * this.scratchBytes, 4096);
      if (this.scratch) this.m._free(this.scratch);
      this.scratch = 0;
      this.scratchBytes = 0;
      this.scratch = this.a.alloc(bytes);
      this.scratchBytes = bytes;
    }
    const ptrs = [];
    let at = this.scratch;
    const heap = this.m.HEAPU8;
    arrays.forEach((a, i) => {
      heap.set(new Uint8Array(a.buffer, a.byteOffset, a.byteLength), at);
      ptrs.push(at);
      at += sizes[i];
    });
    outputs.forEach((a, i) => { ptrs.push(at); at += sizes[arrays.length + i]; });
    return ptrs;
  }

  need(array, type, length, what) {
    if (!(array instanceof type)) throw new AcuityError(`${what}: a ${type.name} expected`, 1);
    if (array.length < length) throw new AcuityError(`${what}: ${length} values expected, got ${array.length}`, 1);
  }

  // deferred: its tables are not built (quick whatever the profile), and its objects are decided
  // exactly until buildTables(index).
  loadProfile(bytes, { deferred = false } = {}) {
    this.need(bytes, Uint8Array, 0, 'loadProfile');
    const [data, index] = this.stage([bytes], [new Int32Array(1)]);
    if (deferred)
      this.a.check(this.m._acuity_load_profile_deferred(this.s, data, bytes.length, index), 'acuity_load_profile_deferred');
    else
      this.a.check(this.m._acuity_load_profile(this.s, data, bytes.length, index), 'acuity_load_profile');
    return this.m.HEAP32[index >> 2];
  }

  // Builds a deferred profile's tables and installs them, between frames: of every view (a tenth of
  // a second or more of this thread per profile: one per idle callback keeps a page responsive), or
  // of one view (about 1/(view count) of that: the views wantedTables() lists).
  buildTables(profile, view = -1) {
    const [out] = this.stage([], [new Uint32Array(1)]);
    if (view < 0) this.a.check(this.m._acuity_make_tables(this.s, profile, out), 'acuity_make_tables');
    else this.a.check(this.m._acuity_make_view_tables(this.s, profile, view, out), 'acuity_make_view_tables');
    const tables = this.m.HEAPU32[out >> 2];
    try {
      this.a.check(this.m._acuity_install_tables(this.s, profile, tables), 'acuity_install_tables');
    } catch (err) {
      this.m._acuity_tables_destroy(tables);
      throw err;
    }
  }

  // Between frames: the views objects were seen from without their tables since the last call, each
  // listed once: [{ profile, view }] (up to `capacity`; the rest at the next call).
  wantedTables(capacity = 256) {
    const [profiles, views, count] =
      this.stage([], [new Int32Array(capacity), new Uint32Array(capacity), new Uint32Array(1)]);
    this.a.check(this.m._acuity_wanted_tables(this.s, profiles, views, capacity, count), 'acuity_wanted_tables');
    const n = this.m.HEAPU32[count >> 2], out = [];
    for (let i = 0; i < n; ++i)
      out.push({ profile: this.m.HEAP32[(profiles >> 2) + i], view: this.m.HEAPU32[(views >> 2) + i] });
    return out;
  }

  // Between frames: frees the tables of the views no object has read in the last `frames` frames
  // (0: all); their objects decide exactly until wantedTables() lists them again. Returns the bytes
  // freed. Every few seconds, not every frame (it reallocates what it keeps).
  dropIdleTables(frames) {
    const [freed] = this.stage([], [new Uint32Array(1)]);
    this.a.check(this.m._acuity_drop_idle_tables(this.s, frames, freed), 'acuity_drop_idle_tables');
    return this.m.HEAPU32[freed >> 2];
  }

  // profiles: Int32Array n; positions: Float64Array 3n; rotations: Float32Array 4n (x y z w);
  // scales: Float32Array n or null (1). Returns the ids (Uint32Array n).
  addObjects(profiles, positions, rotations, scales = null) {
    const n = profiles.length;
    this.need(profiles, Int32Array, n, 'addObjects profiles');
    this.need(positions, Float64Array, 3 * n, 'addObjects positions');
    this.need(rotations, Float32Array, 4 * n, 'addObjects rotations');
    if (scales) this.need(scales, Float32Array, n, 'addObjects scales');
    const ins = [profiles, positions, rotations, ...(scales ? [scales] : [])];
    const ptrs = this.stage(ins, [new Uint32Array(n)]);
    const [pp, pos, rot] = ptrs, sc = scales ? ptrs[3] : 0, ids = ptrs[ptrs.length - 1];
    this.a.check(this.m._acuity_add_objects(this.s, n, pp, pos, 0, rot, 0, sc, ids), 'acuity_add_objects');
    const out = new Uint32Array(this.m.HEAPU8.buffer, ids, n).slice();
    for (const id of out) this.objectSlots = Math.max(this.objectSlots, id + 1);
    return out;
  }

  removeObjects(ids) {
    this.need(ids, Uint32Array, ids.length, 'removeObjects');
    const [p] = this.stage([ids]);
    this.a.check(this.m._acuity_remove_objects(this.s, ids.length, p), 'acuity_remove_objects');
  }

  setTransforms(ids, positions, rotations, scales = null) {
    const n = ids.length;
    this.need(ids, Uint32Array, n, 'setTransforms ids');
    this.need(positions, Float64Array, 3 * n, 'setTransforms positions');
    this.need(rotations, Float32Array, 4 * n, 'setTransforms rotations');
    if (scales) this.need(scales, Float32Array, n, 'setTransforms scales');
    const ptrs = this.stage([ids, positions, rotations, ...(scales ? [scales] : [])]);
    this.a.check(this.m._acuity_set_transforms(this.s, n, ptrs[0], ptrs[1], 0, ptrs[2], 0, scales ? ptrs[3] : 0),
                 'acuity_set_transforms');
  }

  setVelocities(ids, velocities) {
    this.need(ids, Uint32Array, ids.length, 'setVelocities ids');
    this.need(velocities, Float32Array, 3 * ids.length, 'setVelocities velocities');
    const [i, v] = this.stage([ids, velocities]);
    this.a.check(this.m._acuity_set_velocities(this.s, ids.length, i, v, 0), 'acuity_set_velocities');
  }

  // eyes: Float64Array of eyeCount x EYE_DOUBLES (see writeEye); dt in seconds; views: null, or a
  // Float64Array of viewCount x VIEW_DOUBLES (see writeView), at most MAX_VIEWS.
  beginFrame(eyes, eyeCount, dt, views = null, viewCount = 0) {
    this.need(eyes, Float64Array, EYE_DOUBLES * eyeCount, 'beginFrame eyes');
    if (!(Number.isInteger(viewCount) && viewCount >= 0 && viewCount <= MAX_VIEWS))
      throw new AcuityError(`beginFrame: viewCount ${viewCount} is not an integer 0..${MAX_VIEWS}`, 1);
    if (viewCount > 0) this.need(views, Float64Array, VIEW_DOUBLES * viewCount, 'beginFrame views');
    const [e, v] = this.stage(viewCount > 0 ? [eyes, views] : [eyes]);
    this.a.check(this.m._acuity_web_begin_frame(this.s, e, eyeCount, dt, viewCount > 0 ? v : 0, viewCount),
                 viewCount > 0 ? 'acuity_begin_frame_views' : 'acuity_begin_frame');
  }
  updateRange(first, count) { this.a.check(this.m._acuity_update_range(this.s, first, count), 'acuity_update_range'); }
  endFrame() { this.a.check(this.m._acuity_end_frame(this.s), 'acuity_end_frame'); }

  // begin, update every object, end.
  frame(eyes, eyeCount, dt, views = null, viewCount = 0) {
    this.beginFrame(eyes, eyeCount, dt, views, viewCount);
    this.updateRange(0, this.objectSlots);
    this.endFrame();
  }

  // levels, flags: Uint8Arrays of ids.length (flags may be null).
  getLevels(ids, levels, flags = null) {
    const n = ids.length;
    this.need(ids, Uint32Array, n, 'getLevels ids');
    this.need(levels, Uint8Array, n, 'getLevels levels');
    if (flags) this.need(flags, Uint8Array, n, 'getLevels flags');
    const [i, l, f] = this.stage([ids], [levels, levels]);
    this.a.check(this.m._acuity_get_levels(this.s, n, i, l, flags ? f : 0), 'acuity_get_levels');
    levels.set(new Uint8Array(this.m.HEAPU8.buffer, l, n));
    if (flags) flags.set(new Uint8Array(this.m.HEAPU8.buffer, f, n));
  }

  // levels: Uint8Array of ids.length, each id's level for view class viewClass (acuity_get_view_levels).
  getViewLevels(viewClass, ids, levels) {
    const n = ids.length;
    this.need(ids, Uint32Array, n, 'getViewLevels ids');
    this.need(levels, Uint8Array, n, 'getViewLevels levels');
    const [i, l] = this.stage([ids], [levels]);
    this.a.check(this.m._acuity_get_view_levels(this.s, viewClass, n, i, l), 'acuity_get_view_levels');
    levels.set(new Uint8Array(this.m.HEAPU8.buffer, l, n));
  }

  // One object's cut this frame (acuity_select_cut_budget; after frame() or beginFrame()): hierarchy
  // h, its cut state (h.createCut(), once per object), position [3] m, rotation [4] x y z w, scale,
  // velocity [3] m/s or null, triangleBudget: the most triangles the cut should draw (0: none; an
  // integer up to 2^53). Returns { status (0 ok, 1 invalid input: the finest cut), flags, clusters
  // (the drawn cluster ids, a Uint32Array copy), triangles, groupsEvaluated, held, budgetCoarsened
  // (visible groups the budget coarsened), budgetForced (... of them a visible loss) }.
  selectCut(h, cut, position, rotation, scale = 1, velocity = null, triangleBudget = 0) {
    if (!(Number.isSafeInteger(triangleBudget) && triangleBudget >= 0))
      throw new AcuityError(`selectCut: triangleBudget ${triangleBudget} is not an integer 0 .. 2^53`, 1);
    const p = Float64Array.from(position), q = Float32Array.from(rotation);
    const v = velocity ? Float32Array.from(velocity) : null;
    const result = new Uint32Array(CUT_RESULT_BYTES / 4);
    result[0] = CUT_RESULT_BYTES;  // struct_size: the version-9 acuity_cut_result
    const [pp, pq, pr, pv] = this.stage(v ? [p, q, result, v] : [p, q, result]);
    this.a.check(this.m._acuity_select_cut_budget(this.s, h.h, pp, pq, scale, v ? pv : 0, BigInt(triangleBudget),
                                                  cut.memory, h.memoryBytes, h.clusterCount, cut.drawn, pr),
                 'acuity_select_cut_budget');
    const r = new DataView(this.m.HEAPU8.buffer, pr, CUT_RESULT_BYTES);
    const count = r.getUint32(12, true);
    return {
      status: r.getUint32(4, true), flags: r.getUint32(8, true),
      clusters: new Uint32Array(this.m.HEAPU8.buffer, cut.drawn, count).slice(),
      triangles: Number(r.getBigUint64(16, true)), groupsEvaluated: r.getUint32(24, true), held: r.getUint32(28, true),
      budgetCoarsened: r.getUint32(32, true), budgetForced: r.getUint32(36, true),
    };
  }

  frameTriangles() { return Number(this.m._acuity_frame_triangles(this.s)); }

  // The last endFrame's counts over the live objects (acuity_frame_stats, version 5 layout).
  frameStats() {
    const bytes = 32;
    const head = new Uint32Array(bytes / 4);
    head[0] = bytes;  // struct_size
    const [p] = this.stage([head]);
    this.a.check(this.m._acuity_get_frame_stats(this.s, p), 'acuity_get_frame_stats');
    const v = new DataView(this.m.HEAPU8.buffer, p, bytes);
    return {
      changed: v.getUint32(4, true), triangles: Number(v.getBigUint64(8, true)),
      budgetForced: v.getUint32(16, true), invalid: v.getUint32(20, true), atRest: v.getUint32(24, true),
      gazeUsed: v.getUint8(28) !== 0,
    };
  }

  destroy() {
    if (this.scratch) this.m._free(this.scratch);
    this.scratch = 0;
    this.scratchBytes = 0;
    if (this.s) this.m._acuity_destroy(this.s);
    this.s = 0;
  }
}
