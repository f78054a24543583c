// lod_scene.js — lodgen's MSFT_lod glTF as THREE.LOD objects. three's GLTFLoader does not know
// MSFT_lod: it loads the scene's nodes (each instance's finest level), and the coarser levels are the
// nodes named by the extension's "ids", fetched here from the parser. Levels are set by acuity, so
// every LOD has autoUpdate = false.
import * as THREE from 'three';
import { GLTFLoader } from 'three/addons/loaders/GLTFLoader.js';

export class ContentError extends Error {
  constructor(message) { super(message); this.name = 'ContentError'; }
}

// Bytes of a URL; a missing file is a ContentError naming it.
export async function fetchBytes(url, what) {
  let response;
  try {
    response = await fetch(url);
  } catch (e) {
    throw new ContentError(`${what} ${url}: cannot be fetched (${e.message})`);
  }
  if (!response.ok) throw new ContentError(`${what} ${url}: ${response.status} ${response.statusText || 'not found'}`);
  return new Uint8Array(await response.arrayBuffer());
}

function fileSafe(name) {  // as acuity::bake::file_safe (bake/src/scene.cpp) names <mesh>.acuity
  const s = (name || '').replace(/[^A-Za-z0-9_-]/g, '_');
  return s || 'object';
}

function triangles(object) {
  let n = 0;
  object.traverse(o => {
    if (!o.isMesh) return;
    const g = o.geometry;
    n += (g.index ? g.index.count : g.attributes.position.count) / 3;
  });
  return n;
}

// { scene, lods: [{ lod, profile, triangles: [per level], sphere (local) }], profiles: [names] }
async function parseGltf(bytes, url) {
  const loader = new GLTFLoader();
  try {
    return await loader.parseAsync(bytes.buffer.slice(bytes.byteOffset, bytes.byteOffset + bytes.byteLength),
                                   url.slice(0, url.lastIndexOf('/') + 1));
  } catch (e) {
    throw new ContentError(`${url}: not a glTF scene three.js can read (${String(e.message || e).replace(/[^\x20-\x7e]/g, '?')})`);
  }
}

export async function loadLodScene(bytes, url) {
  const gltf = await parseGltf(bytes, url);
  const parser = gltf.parser, json = parser.json;
  const profiles = [], profileOfMesh = new Map(), seen = new Map();
  const lods = [];
  const roots = [...gltf.scene.children];
  for (const root of roots) {
    const assoc = parser.associations.get(root);
    const index = assoc && assoc.nodes;
    const node = index === undefined ? null : json.nodes[index];
    const ids = node && node.extensions && node.extensions.MSFT_lod && node.extensions.MSFT_lod.ids;
    if (!Array.isArray(ids) || node.mesh === undefined) continue;  // drawn as it is, not driven
    if (!profileOfMesh.has(node.mesh)) {
      const base = fileSafe(json.meshes[node.mesh] && json.meshes[node.mesh].name);
      const k = seen.get(base) || 0;
      seen.set(base, k + 1);
      profileOfMesh.set(node.mesh, profiles.length);
      profiles.push(k ? `${base}_${k}` : base);
    }
    const lod = new THREE.LOD();
    lod.autoUpdate = false;
    lod.name = root.name;
    root.updateMatrix();
    lod.matrix.copy(root.matrix);
    lod.matrix.decompose(lod.position, lod.quaternion, lod.scale);
    const toLod = root.matrix.clone().invert();
    const levels = [root];
    for (const id of ids) {
      if (!Number.isInteger(id) || id < 0 || id >= json.nodes.length)
        throw new ContentError(`${url}: MSFT_lod of node ${index} names node ${id}, which does not exist`);
      levels.push(await parser.getDependency('node', id));
    }
    gltf.scene.remove(root);
    levels.forEach((object, k) => {
      object.updateMatrix();
      object.matrix.premultiply(toLod).decompose(object.position, object.quaternion, object.scale);
      lod.addLevel(object, k);
    });
    const box = new THREE.Box3();  // the finest level in the LOD's frame (root's own matrix is identity now)
    root.traverse(o => {
      if (!o.isMesh) return;
      o.geometry.computeBoundingBox();
      box.union(o.geometry.boundingBox.clone().applyMatrix4(o === root ? new THREE.Matrix4() : o.matrix));
    });
    const sphere = box.getBoundingSphere(new THREE.Sphere());
    lods.push({ lod, profile: profileOfMesh.get(node.mesh), triangles: levels.map(triangles), sphere });
    gltf.scene.add(lod);
  }
  if (lods.length === 0)
    throw new ContentError(`${url}: not a scene from acuity lodgen (no node has MSFT_lod levels)`);
  return { scene: gltf.scene, lods, profiles };
}

// What THREE.LOD shows: only level k is visible.
export function showLevel(lod, k) {
  const levels = lod.levels;
  for (let j = 0; j < levels.length; ++j) levels[j].object.visible = j === k;
  lod._currentLevel = k;  // what lod.getCurrentLevel() reports; update() is never called
}

// lodgen --clusters' glTF (docs/lodgen.md, ACUITY_cluster_hierarchy): the first node whose mesh has
// a primitive with the extension, as { object (the node, three's), mesh (its THREE.Mesh), indices
// (Uint32Array: every cluster's triangles), clusters (Uint32Array, 4 per cluster), groups (Uint8Array,
// 32 bytes per group), sphere (the finest mesh's, in the node's frame) }. The mesh draws what
// showCut() gives it (the finest mesh until then).
export async function loadClusterObject(bytes, url) {
  const gltf = await parseGltf(bytes, url);
  const parser = gltf.parser, json = parser.json;
  for (const [index, node] of (json.nodes || []).entries()) {
    const mesh = node.mesh === undefined ? null : json.meshes[node.mesh];
    const prim = mesh && mesh.primitives.find(p => p.extensions && p.extensions.ACUITY_cluster_hierarchy);
    if (!prim) continue;
    const ext = prim.extensions.ACUITY_cluster_hierarchy;
    const counts = [ext.clusterCount, ext.groupCount];
    if (!counts.every(n => Number.isInteger(n) && n >= 0) || ext.clusterCount === 0)
      throw new ContentError(`${url}: ACUITY_cluster_hierarchy of node ${index} has bad counts`);
    const indexAttribute = await parser.getDependency('accessor', ext.indices);
    const clusterBytes = await parser.getDependency('bufferView', ext.clusters);
    const groupBytes = await parser.getDependency('bufferView', ext.groups);
    if (clusterBytes.byteLength < 16 * ext.clusterCount || groupBytes.byteLength < 32 * ext.groupCount)
      throw new ContentError(`${url}: ACUITY_cluster_hierarchy's records are shorter than its counts`);
    let object = null;
    gltf.scene.traverse(o => { const a = parser.associations.get(o); if (a && a.nodes === index && !object) object = o; });
    let drawn = null;
    object.traverse(o => { if (o.isMesh && !drawn) drawn = o; });
    if (!drawn) throw new ContentError(`${url}: node ${index} draws no mesh`);
    drawn.geometry.computeBoundingSphere();
    return {
      scene: gltf.scene, object, mesh: drawn, indices: Uint32Array.from(indexAttribute.array),
      clusters: new Uint32Array(clusterBytes.slice(0, 16 * ext.clusterCount)),
      groups: new Uint8Array(groupBytes.slice(0, 32 * ext.groupCount)), sphere: drawn.geometry.boundingSphere.clone(),
    };
  }
  throw new ContentError(`${url}: no mesh with ACUITY_cluster_hierarchy (make one with acuity lodgen MESH --clusters)`);
}

// Draws the cut: the mesh's index buffer becomes the triangles of clusters `ids` (rebuilt here; call it
// when the cut changes). Returns the triangles drawn.
export function showCut(cut, ids) {
  let n = 0;
  for (const c of ids) n += cut.clusters[4 * c + 1];
  const out = new Uint32Array(3 * n);
  let at = 0;
  for (const c of ids) {
    const first = 3 * cut.clusters[4 * c], count = 3 * cut.clusters[4 * c + 1];
    out.set(cut.indices.subarray(first, first + count), at);
    at += count;
  }
  cut.mesh.geometry.setIndex(new THREE.BufferAttribute(out, 1));
  return n;
}
