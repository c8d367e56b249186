// The demo page: the built-in head (or ?head=URL) in three.js, speaking typed
// text through espeak-ng (WebAssembly, GPL-3, loaded on the first Enter) with
// facerig's runtime (WebAssembly, MIT) driving the morph targets from the
// AudioContext clock. window.facerigDemo is what the browser test reads.
import * as THREE from 'three';
import { GLTFLoader } from 'three/addons/loaders/GLTFLoader.js';
import { loadFacerig } from '../dist/facerig.mjs';
import { createSpeaker } from './speech.mjs';

const params = new URLSearchParams(location.search);
const headUrl = params.get('head') ?? '../../../build/data/default_head.glb';
// ?render=off: faces animate without drawing (the lip-sync test samples every
// frame on software GL, where drawing the head takes most of a frame).
const drawing = params.get('render') !== 'off';
const message = document.getElementById('message');
const hud = document.getElementById('hud');
const demo = (window.facerigDemo = { ready: false, frames: [], error: null });

function show(text) { message.textContent = text; }

const renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
renderer.setPixelRatio(window.devicePixelRatio);
document.getElementById('view').appendChild(renderer.domElement);
const scene = new THREE.Scene();
scene.background = new THREE.Color(0x20242a);
scene.add(new THREE.HemisphereLight(0xffffff, 0x404040, 1.2));
const key = new THREE.DirectionalLight(0xffffff, 2.0);
key.position.set(1, 1.5, 2);
scene.add(key);
const camera = new THREE.PerspectiveCamera(30, 1, 0.01, 100);

function resize() {
  const { clientWidth: w, clientHeight: h } = renderer.domElement.parentElement;
  renderer.setSize(w, h);
  camera.aspect = w / h;
  camera.updateProjectionMatrix();
}
window.addEventListener('resize', resize);

// consumer.c's lip pair, from the mesh's own jawOpen target: the midline pair
// nearest at rest of a vertex jawOpen carries and one it leaves.
function findLips(mesh) {
  const jaw = mesh.morphTargetDictionary.jawOpen;
  const base = mesh.geometry.attributes.position, delta = mesh.geometry.morphAttributes.position[jaw];
  mesh.geometry.computeBoundingBox();
  const limit = 0.01 * mesh.geometry.boundingBox.getSize(new THREE.Vector3()).length();
  let most = 0;
  for (let i = 0; i < base.count; ++i) most = Math.max(most, Math.hypot(delta.getX(i), delta.getY(i), delta.getZ(i)));
  const lower = [], upper = [];
  for (let i = 0; i < base.count; ++i) {
    if (Math.abs(base.getX(i)) > limit) continue;
    const moved = Math.hypot(delta.getX(i), delta.getY(i), delta.getZ(i));
    if (moved >= 0.5 * most) lower.push(i); else if (moved <= 0.1 * most) upper.push(i);
  }
  let best = Infinity, lips = null;
  for (const i of lower) for (const j of upper) {
    const d = (base.getX(i) - base.getX(j)) ** 2 + (base.getY(i) - base.getY(j)) ** 2 + (base.getZ(i) - base.getZ(j)) ** 2;
    if (d < best) { best = d; lips = [j, i]; }
  }
  return lips;
}

// A vertex as three.js deforms it: base + sum of influence * relative morph delta.
function morphed(mesh, vertex) {
  const base = mesh.geometry.attributes.position, targets = mesh.geometry.morphAttributes.position;
  const p = [base.getX(vertex), base.getY(vertex), base.getZ(vertex)];
  mesh.morphTargetInfluences.forEach((w, k) => {
    if (w !== 0) { p[0] += w * targets[k].getX(vertex); p[1] += w * targets[k].getY(vertex); p[2] += w * targets[k].getZ(vertex); }
  });
  return p;
}

async function start() {
  const [facerig, gltf, bytes] = await Promise.all([
    loadFacerig(),
    new GLTFLoader().loadAsync(headUrl),
    fetch(headUrl).then((r) => (r.ok ? r.arrayBuffer() : Promise.reject(new Error(`${headUrl}: HTTP ${r.status}`)))),
  ]);
  const rig = facerig.loadRig(bytes, headUrl.split('/').pop());
  const character = rig.createCharacter({ seed: 1 });
  // Each mesh with morph targets gets the rig's weights in its own target order.
  const meshes = [];
  gltf.scene.traverse((o) => {
    if (o.isMesh && o.morphTargetDictionary) {
      const names = Object.keys(o.morphTargetDictionary);
      const order = new Int32Array(o.morphTargetInfluences.length).fill(-1);
      for (const name of names) order[o.morphTargetDictionary[name]] = rig.findShape(name);
      meshes.push({ mesh: o, order });
    }
  });
  if (!meshes.length || rig.findShape('jawOpen') < 0) throw new Error(`${headUrl} has no ARKit or Oculus face shapes (no jawOpen)`);
  scene.add(gltf.scene);
  const box = new THREE.Box3().setFromObject(gltf.scene), size = box.getSize(new THREE.Vector3());
  const centre = box.getCenter(new THREE.Vector3());
  camera.position.set(centre.x, centre.y + 0.05 * size.y, centre.z + 2.2 * size.y);
  camera.lookAt(centre.x, centre.y + 0.05 * size.y, centre.z);
  resize();

  const face = meshes.reduce((a, b) => (a.mesh.geometry.attributes.position.count >= b.mesh.geometry.attributes.position.count ? a : b)).mesh;
  const lips = findLips(face);
  const audio = new AudioContext();
  let lineStart = 0, line = null;
  const speaker = createSpeaker(audio);

  demo.speakTrack = (track) => {
    const speech = facerig.speechFromTrack(track);
    lineStart = audio.currentTime + 0.05;
    character.speak(speech, 0);
    line = { phonemes: speech.phonemes(), start: lineStart };
    speech.release();
    demo.frames.length = 0;
    return line;
  };
  demo.speakText = async (text, voice) => {
    const { phonemes, play } = await speaker.synthesize(text, voice);
    lineStart = play();  // the AudioContext time at which the audio starts
    character.speakPhonemes(phonemes, 0);
    line = { phonemes, start: lineStart };
    demo.frames.length = 0;
    return line;
  };
  demo.setEmotion = (name, target) => character.setEmotion(name, target);

  let average = 0;
  renderer.setAnimationLoop(() => {
    const t = audio.currentTime - lineStart;
    const began = performance.now();
    const weights = character.update(t);
    const cost = performance.now() - began;
    average = average ? 0.95 * average + 0.05 * cost : cost;
    for (const { mesh, order } of meshes) {
      const influences = mesh.morphTargetInfluences;
      for (let i = 0; i < order.length; ++i) influences[i] = order[i] >= 0 ? weights[order[i]] : 0;
    }
    if (line) {
      const [a, b] = [morphed(face, lips[0]), morphed(face, lips[1])];
      demo.frames.push({ t, aperture: Math.hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]), viseme: character.state().viseme });
    }
    hud.textContent = `update ${(average * 1000).toFixed(1)} us/frame\nclock ${t.toFixed(2)} s  ${character.state().viseme}`;
    if (drawing || demo.drawOnce) renderer.render(scene, camera);
    demo.drawOnce = false;
  });

  const textBox = document.getElementById('text');
  textBox.addEventListener('keydown', async (event) => {
    if (event.key !== 'Enter') return;
    try {
      await audio.resume();
      show('');
      await demo.speakText(textBox.value, document.getElementById('voice').value);
    } catch (e) {
      show(e.message);
    }
  });
  for (const button of document.querySelectorAll('[data-emotion]')) {
    button.addEventListener('click', () => {
      for (const other of document.querySelectorAll('[data-emotion]')) character.setEmotion(other.dataset.emotion, 0);
      character.setEmotion(button.dataset.emotion, 0.8);
    });
  }
  demo.lips = lips;
  demo.ready = true;
}

start().catch((e) => {
  demo.error = e.message;
  show(e.message);
});
