// Types of 'acuity-web/wasm': the emscripten module factory (dist/acuity.mjs) that loadAcuity takes.
import type { ModuleFactory } from './acuity.js';
declare const createAcuityModule: ModuleFactory;
export default createAcuityModule;
