// Runs in headless Chromium (check_glb.mjs): loads one GLB with three.js's
// GLTFLoader, renders it from the front and answers what a web avatar player
// would see: each mesh's morph-target dictionary, the materials and textures,
// the GPU bytes three.js uploaded, and which pixels a shape changes.
import * as THREE from 'three';
import { GLTFLoader } from 'three/addons/loaders/GLTFLoader.js';

const SIZE = 512;

// Bytes three.js asks WebGL for, counted at the API: morph targets live in
// array (3D) textures, images in 2D textures, vertices and indices in buffers.
const uploaded = { arrayTextureBytes: 0, textureBytes: 0, bufferBytes: 0 };
function sizedFormatBytes(gl, internalFormat) {
  return { [gl.RGBA32F]: 16, [gl.RGBA16F]: 8, [gl.RG32F]: 8, [gl.R32F]: 4, [gl.RGB32F]: 12, [gl.RGB8]: 3 }[internalFormat] ?? 4;
}
function levelTexels(levels, width, height) {
  let texels = 0;
  for (let level = 0; level < levels; ++level) texels += Math.max(1, width >> level) * Math.max(1, height >> level);
  return texels;
}
const gl2 = WebGL2RenderingContext.prototype;
const texStorage3D = gl2.texStorage3D;
gl2.texStorage3D = function (target, levels, internalFormat, width, height, depth) {
  uploaded.arrayTextureBytes += levelTexels(levels, width, height) * depth * sizedFormatBytes(this, internalFormat);
  return texStorage3D.call(this, target, levels, internalFormat, width, height, depth);
};
const texImage3D = gl2.texImage3D;
gl2.texImage3D = function (target, level, internalFormat, width, height, depth, ...rest) {
  uploaded.arrayTextureBytes += width * height * depth * sizedFormatBytes(this, internalFormat);
  return texImage3D.call(this, target, level, internalFormat, width, height, depth, ...rest);
};
const texStorage2D = gl2.texStorage2D;
gl2.texStorage2D = function (target, levels, internalFormat, width, height) {
  uploaded.textureBytes += levelTexels(levels, width, height) * sizedFormatBytes(this, internalFormat);
  return texStorage2D.call(this, target, levels, internalFormat, width, height);
};
const bufferData = gl2.bufferData;
gl2.bufferData = function (target, data, ...rest) {
  uploaded.bufferBytes += typeof data === 'number' ? data : data.byteLength;
  return bufferData.call(this, target, data, ...rest);
};

const renderer = new THREE.WebGLRenderer({ antialias: false, preserveDrawingBuffer: true });
renderer.setPixelRatio(1);
renderer.setSize(SIZE, SIZE);
renderer.outputColorSpace = THREE.SRGBColorSpace;
document.body.appendChild(renderer.domElement);

const scene = new THREE.Scene();
scene.background = new THREE.Color(0x203040);
scene.add(new THREE.HemisphereLight(0xffffff, 0x404040, 2.0));
const key = new THREE.DirectionalLight(0xffffff, 2.0);
key.position.set(0.3, 0.5, 1.0);
scene.add(key);

function meshesOf(root) {
  const meshes = [];
  root.traverse((object) => { if (object.isMesh) meshes.push(object); });
  return meshes;
}

// The camera in front of the model (+Z, glTF's forward), framing its box;
// returns the box's rectangle on the screen in [0, 1] (y down).
function frame(camera, root) {
  const box = new THREE.Box3().setFromObject(root);
  const centre = box.getCenter(new THREE.Vector3());
  const size = box.getSize(new THREE.Vector3());
  const half = Math.max(size.x, size.y) * 0.55;
  camera.position.set(centre.x, centre.y, box.max.z + half / Math.tan(THREE.MathUtils.degToRad(camera.fov / 2)));
  camera.near = half * 0.05;
  camera.far = camera.position.z - box.min.z + half;
  camera.lookAt(centre);
  camera.updateProjectionMatrix();
  camera.updateMatrixWorld();
  let x0 = 1, y0 = 1, x1 = 0, y1 = 0;
  for (const x of [box.min.x, box.max.x]) for (const y of [box.min.y, box.max.y]) for (const z of [box.min.z, box.max.z]) {
    const p = new THREE.Vector3(x, y, z).project(camera);
    const sx = (p.x + 1) / 2, sy = (1 - p.y) / 2;
    x0 = Math.min(x0, sx); x1 = Math.max(x1, sx); y0 = Math.min(y0, sy); y1 = Math.max(y1, sy);
  }
  return { x0, y0, x1, y1 };
}

function pixels() {
  const gl = renderer.getContext();
  const data = new Uint8Array(SIZE * SIZE * 4);
  gl.readPixels(0, 0, SIZE, SIZE, gl.RGBA, gl.UNSIGNED_BYTE, data);
  return data;
}

let state = null;

// Sets every mesh's influences: 1 for the named shapes it has, else 0.
window.pose = (names) => {
  for (const mesh of state.meshes) {
    if (!mesh.morphTargetInfluences) continue;
    mesh.morphTargetInfluences.fill(0);
    for (const name of names) {
      const index = mesh.morphTargetDictionary?.[name];
      if (index !== undefined) mesh.morphTargetInfluences[index] = 1;
    }
  }
  renderer.render(scene, state.camera);
  return true;
};

// Where the current picture differs from the rest pose: the share of the
// model's screen box that changed, and the changed pixels' centroid in that
// box (0,0 top left; 1,1 bottom right; the viewer's right is the face's left).
window.changeFromRest = () => {
  const now = pixels();
  const rest = state.rest;
  const { x0, y0, x1, y1 } = state.screenBox;
  let changed = 0, sx = 0, sy = 0, inside = 0;
  for (let row = 0; row < SIZE; ++row) {
    for (let col = 0; col < SIZE; ++col) {
      const i = (row * SIZE + col) * 4;
      const d = Math.max(Math.abs(now[i] - rest[i]), Math.abs(now[i + 1] - rest[i + 1]), Math.abs(now[i + 2] - rest[i + 2]));
      if (d <= 24) continue;
      const x = (col + 0.5) / SIZE, y = 1 - (row + 0.5) / SIZE;  // readPixels rows start at the bottom
      ++changed;
      const bx = (x - x0) / (x1 - x0), by = (y - y0) / (y1 - y0);
      sx += bx; sy += by;
      if (bx >= 0 && bx <= 1 && by >= 0 && by <= 1) ++inside;
    }
  }
  const boxPixels = (x1 - x0) * (y1 - y0) * SIZE * SIZE;
  return {
    changedPixels: changed,
    changedShareOfBox: changed / boxPixels,
    insideShare: changed ? inside / changed : 0,
    centroid: changed ? [sx / changed, sy / changed] : null,
  };
};

// The current pose rendered `zoom` times closer about the screen point
// (x, y) in [0, 1] (y down), for a close look at the mouth; pose() renders
// the whole model again.
window.closeUp = (x, y, zoom) => {
  const side = SIZE / zoom;
  const left = Math.min(Math.max(x * SIZE - side / 2, 0), SIZE - side);
  const top = Math.min(Math.max(y * SIZE - side / 2, 0), SIZE - side);
  state.camera.setViewOffset(SIZE, SIZE, left, top, side, side);
  renderer.render(scene, state.camera);
  state.camera.clearViewOffset();
  return true;
};

window.load = async (url) => {
  const gltf = await new GLTFLoader().loadAsync(url);
  scene.add(gltf.scene);
  const camera = new THREE.PerspectiveCamera(30, 1, 0.01, 100);
  const screenBox = frame(camera, gltf.scene);
  const meshes = meshesOf(gltf.scene);
  state = { meshes, camera, screenBox };
  window.pose([]);
  state.rest = pixels();
  let background = 0;
  for (let i = 0; i < state.rest.length; i += 4) {
    if (state.rest[i] === 0x20 && state.rest[i + 1] === 0x30 && state.rest[i + 2] === 0x40) ++background;
  }
  const materials = new Map();
  for (const mesh of meshes) {
    for (const material of [mesh.material].flat()) materials.set(material.uuid, material);
  }
  const info = renderer.info;
  return {
    meshes: meshes.map((mesh) => ({
      name: mesh.name,
      vertices: mesh.geometry.attributes.position.count,
      morphTargets: mesh.geometry.morphAttributes.position?.length ?? 0,
      morphNormals: (mesh.geometry.morphAttributes.normal?.length ?? 0) > 0,
      dictionary: Object.keys(mesh.morphTargetDictionary ?? {}),
      material: [mesh.material].flat()[0].name,
    })),
    materials: [...materials.values()].map((m) => ({
      name: m.name,
      texture: m.map ? { width: m.map.image?.width ?? 0, height: m.map.image?.height ?? 0 } : null,
      normalTexture: m.normalMap ? { width: m.normalMap.image?.width ?? 0 } : null,
    })),
    renderer: { geometries: info.memory.geometries, textures: info.memory.textures, triangles: info.render.triangles },
    uploaded: { ...uploaded },
    screenBox,
    modelShareOfPicture: 1 - background / (SIZE * SIZE),
  };
};

window.ready = true;
