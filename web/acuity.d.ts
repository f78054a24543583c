// Types of acuity.js (the package's main export, 'acuity-web'). Units as in acuity.h: metres,
// degrees, degrees per second, pixels, seconds; an eye looks along its local -Z with +Y up.

/** Selection rules (acuity_config.rule). */
export const RULE: Readonly<{ perceptual: 0; reddy: 1; distance: 2; screenSize: 3 }>;
/** Per-object flags getLevels() writes (ACUITY_FLAG_*). */
export const FLAG: Readonly<{ invalidInput: 1; eyeInside: 2; noGaze: 4; budgetForced: 8; changed: 16; held: 32 }>;
/** acuity_status text by value: 'ok', 'invalid argument', 'bad profile', 'full', 'out of memory', 'internal error'. */
export const STATUS: readonly string[];

/** Every failing call throws one: the message is acuity_last_error()'s text, status the acuity_status. */
export class AcuityError extends Error {
  constructor(message: string, status: number);
  readonly status: number;
}

export interface GazeInput {
  direction?: ArrayLike<number>;        // 3, unit, eye space (default 0 0 -1)
  confidence?: number;                  // 0..1 (default 1)
  angularVelocity?: ArrayLike<number>;  // 3, deg/s; absent: the pursuit model
}
export interface EyeInput {
  position: ArrayLike<number>;          // 3, world [m]
  orientation: ArrayLike<number>;       // 4, x y z w, eye to world
  fov: ArrayLike<number>;               // 4, left (< 0), right, up, down (< 0) [deg]
  viewport: ArrayLike<number>;          // 2, [px]
  velocity?: ArrayLike<number>;         // 3, [m/s] (default 0)
  angularVelocity?: ArrayLike<number>;  // 3, [deg/s] (default 0)
  gaze?: GazeInput | null;              // null or absent: no eye tracker
}
/** Doubles per eye in the Float64Array that beginFrame/frame take. */
export const EYE_DOUBLES: 28;
/** Writes `eye` at eyes[i * EYE_DOUBLES]. */
export function writeEye(eyes: Float64Array, i: number, eye: EyeInput): void;

/** A view's projection and rule (acuity_view; acuity::View in scheduler.hpp is the contract). */
export const PROJECTION: Readonly<{ perspective: 0; orthographic: 1 }>;
export const VIEW_RULE: Readonly<{ footprint: 0; asEye: 1 }>;
/** A view beyond the eyes: a shadow map's light view or a secondary camera. */
export interface ViewInput {
  viewClass?: number;                   // < max_view_classes (default 0)
  projection?: number;                  // PROJECTION (default perspective)
  rule?: number;                        // VIEW_RULE (default footprint)
  pixelError?: number;                  // footprint: allowed projected error [texels] (default 1)
  position: ArrayLike<number>;          // 3, world [m]
  orientation: ArrayLike<number>;       // 4, x y z w, view to world (looks along -Z)
  fov?: ArrayLike<number>;              // 4, perspective half-angles [deg]
  extent?: ArrayLike<number>;           // 4, orthographic left, right, top, bottom [m]
  viewport: ArrayLike<number>;          // 2, [texels or px]
}
/** Doubles per view in the Float64Array that beginFrame/frame take; at most MAX_VIEWS views a frame. */
export const VIEW_DOUBLES: 21;
export const MAX_VIEWS: 64;
/** Writes `view` at views[i * VIEW_DOUBLES]. */
export function writeView(views: Float64Array, i: number, view: ViewInput): void;

/** The module the 'acuity-web/wasm' factory makes (emscripten); opaque to callers. */
export interface AcuityModule { readonly HEAPU8: Uint8Array }
export interface ModuleOptions {
  /** The bytes of 'acuity-web/acuity.wasm'; needed in node (the module is built for the web). */
  wasmBinary?: ArrayBuffer | Uint8Array;
  /** Where the browser fetches acuity.wasm from (default: next to acuity.mjs). */
  locateFile?: (path: string, prefix: string) => string;
}
export type ModuleFactory = (options?: ModuleOptions) => Promise<AcuityModule>;

/** Instantiates the module: `loadAcuity(createAcuityModule)` with the default export of 'acuity-web/wasm'. */
export function loadAcuity(factory: ModuleFactory, moduleOptions?: ModuleOptions): Promise<Acuity>;

export class Acuity {
  /** The library's version, "major.minor.patch" (acuity_version). */
  readonly version: string;
  lastError(): string;
  /** acuity_config fields by name, e.g. { max_objects: 4096, quality: 1, rule: RULE.distance }. */
  createScheduler(options?: Record<string, number | boolean>): Scheduler;
  /** A cluster hierarchy (ACUITY_cluster_hierarchy's records: 4 uint32 per cluster, 32 bytes per
   *  group) with its per-group loss derived from the object's .acuity profile. */
  createHierarchy(clusters: Uint32Array, groups: Uint8Array, profile: Uint8Array): Hierarchy;
}

/** One object's cut state in the wasm heap (hysteresis memory per group, the drawn ids). */
export interface CutState { readonly memory: number; readonly drawn: number; destroy(): void; }
export class Hierarchy {
  readonly clusterCount: number;
  readonly groupCount: number;
  readonly memoryBytes: number;
  createCut(): CutState;
  destroy(): void;
}
export interface CutResult {
  /** 0: the perceptual cut; 1: invalid input, the finest cut. */
  status: number; flags: number;
  /** The drawn cluster ids. */
  clusters: Uint32Array;
  triangles: number; groupsEvaluated: number; held: number;
  /** Visible groups the triangle budget coarsened, and of them those whose loss is visible (FLAG.budgetForced). */
  budgetCoarsened: number; budgetForced: number;
}

export interface FrameStats {
  changed: number; triangles: number; budgetForced: number; invalid: number; atRest: number; gazeUsed: boolean;
}

export class Scheduler {
  /** A .acuity file's bytes (copied, validated); returns the profile index. deferred: no tables yet
   *  (quick; its objects are decided exactly until buildTables). */
  loadProfile(bytes: Uint8Array, options?: { deferred?: boolean }): number;
  /** Builds and installs a deferred profile's tables, between frames: of every view (a tenth of a
   *  second or more), or of one view (about 1/(view count) of that). */
  buildTables(profile: number, view?: number): void;
  /** Between frames: the views objects were seen from without their tables, each listed once until dropped. */
  wantedTables(capacity?: number): { profile: number; view: number }[];
  /** Between frames: frees the tables of views no object read in the last `frames` frames (0: all); returns the bytes freed. */
  dropIdleTables(frames: number): number;
  /** profiles n, positions 3n [m], rotations 4n (x y z w), scales n or null (1); returns the ids. */
  addObjects(profiles: Int32Array, positions: Float64Array, rotations: Float32Array, scales?: Float32Array | null): Uint32Array;
  removeObjects(ids: Uint32Array): void;
  setTransforms(ids: Uint32Array, positions: Float64Array, rotations: Float32Array, scales?: Float32Array | null): void;
  /** velocities 3n [m/s]. */
  setVelocities(ids: Uint32Array, velocities: Float32Array): void;
  /** eyes: eyeCount x EYE_DOUBLES (writeEye); dt [s]; views: viewCount x VIEW_DOUBLES (writeView). */
  beginFrame(eyes: Float64Array, eyeCount: number, dt: number, views?: Float64Array | null, viewCount?: number): void;
  updateRange(first: number, count: number): void;
  endFrame(): void;
  /** beginFrame, updateRange over every object, endFrame. */
  frame(eyes: Float64Array, eyeCount: number, dt: number, views?: Float64Array | null, viewCount?: number): void;
  /** Writes each id's level (0 finest) and, when given, its FLAG bits. */
  getLevels(ids: Uint32Array, levels: Uint8Array, flags?: Uint8Array | null): void;
  /** Writes each id's level for a view class (after frame/endFrame). */
  getViewLevels(viewClass: number, ids: Uint32Array, levels: Uint8Array): void;
  /** One object's cut this frame (after frame/beginFrame): position [m], rotation x y z w, scale, velocity [m/s],
   *  triangleBudget: the most triangles the cut should draw (0: none; an integer up to 2^53). */
  selectCut(h: Hierarchy, cut: CutState, position: ArrayLike<number>, rotation: ArrayLike<number>, scale?: number,
            velocity?: ArrayLike<number> | null, triangleBudget?: number): CutResult;
  frameTriangles(): number;
  frameStats(): FrameStats;
  destroy(): void;
}
