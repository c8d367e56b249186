// Heads in the page: a GLB read twice from the same bytes, by facerig (the
// rig the runtime animates, through the native bounded reader, which also
// gives the message for a truncated or foreign file) and by three.js (what is
// drawn); each copy of the head gets its own character, and every mesh with
// morph targets the rig's weights in its own target order.
import * as THREE from 'three';
import { GLTFLoader } from 'three/addons/loaders/GLTFLoader.js';

const ARKIT_MOUTH = ['jawOpen', 'mouthClose', 'mouthFunnel', 'mouthPucker', 'mouthPressLeft', 'mouthStretchLeft',
                     'mouthLowerDownLeft', 'mouthUpperUpLeft', 'mouthRollLower', 'mouthRollUpper'];
const OCULUS_VISEMES = ['viseme_aa', 'viseme_PP', 'viseme_O', 'viseme_E', 'viseme_FF', 'viseme_I', 'viseme_U',
                        'viseme_CH', 'viseme_DD', 'viseme_kk', 'viseme_nn', 'viseme_RR', 'viseme_SS', 'viseme_TH', 'viseme_sil'];
const BLINKS = ['eyeBlinkLeft', 'eyeBlinkRight'];

// "a pa" said by a throwaway character without blinks or gaze: the weights
// move only if the runtime found shapes to speak with (its own mapping).
const PROBE_LINE = [{ start: 0, duration: 0.1, symbol: '_:' }, { start: 0.1, duration: 0.2, symbol: 'a#' },
                    { start: 0.3, duration: 0.08, symbol: 'p' }, { start: 0.38, duration: 0.2, symbol: 'A:' }];
function runtimeCanSpeak(rig) {
  const character = rig.createCharacter({ blinks: false, gaze: false });
  try {
    character.speakPhonemes(PROBE_LINE.map((p) => ({ ...p, language: 'en-us' })), 0);
    for (const t of [0.2, 0.34, 0.48]) if (character.update(t).some((w) => w > 0.01)) return true;
    return false;
  } finally {
    character.release();
  }
}

const list = (names) => names.slice(0, 6).join(', ') + (names.length > 6 ? ', …' : '');

/** What a rig lacks to talk, as a message naming both conventions; null when it can talk. */
export function missingFaceShapes(rig, name) {
  if (rig.info.shapeCount > 0 && runtimeCanSpeak(rig)) return null;
  const found = rig.info.shapeCount
    ? `its ${rig.info.shapeCount} blend shapes (${list(rig.shapeNames)}) include none of them`
    : 'it has no blend shapes (morph targets) at all';
  return `${name} has no face shapes facerig can animate: it lacks both the ARKit mouth shapes (${list(ARKIT_MOUTH)}) ` +
         `and the Oculus visemes (${list(OCULUS_VISEMES)}); ${found}.`;
}

/** A note for a head that talks but cannot blink; null otherwise. */
export function missingBlinks(rig, name) {
  const has = BLINKS.some((b) => rig.mapTargets([b]).unmatched.length === 0);
  return has ? null : `${name} has no blink shapes (${BLINKS.join(', ')}): it talks, but its eyes stay open.`;
}

/**
 * Reads a head from GLB bytes: {rig, template (three.js scene), notes}. Throws with the native
 * reader's message for a file that is not a valid GLB, or with what the head lacks.
 */
export async function readHead(facerig, bytes, name) {
  const rig = facerig.loadRig(bytes, name);
  try {
    const missing = missingFaceShapes(rig, name);
    if (missing) throw new Error(missing);
    const gltf = await new GLTFLoader().parseAsync(bytes.slice().buffer, '');
    return { rig, template: gltf.scene, notes: [missingBlinks(rig, name)].filter(Boolean) };
  } catch (e) {
    rig.release();
    throw e;
  }
}

/** One copy of a head on the page: its own character, meshes driven from its weights, idle head motion. */
export class Head {
  constructor(rig, template, seed) {
    this.character = rig.createCharacter({ seed });
    this.model = template.clone(true);
    const box = new THREE.Box3().setFromObject(this.model);
    this.size = box.getSize(new THREE.Vector3());
    const centre = box.getCenter(new THREE.Vector3());
    // Turn about the neck (low and behind the face's centre), as the native player does.
    this.pivot = new THREE.Group();
    this.pivot.position.set(centre.x, box.min.y + 0.15 * this.size.y, centre.z - 0.2 * this.size.z);
    this.model.position.sub(this.pivot.position);
    this.pivot.add(this.model);
    this.root = new THREE.Group();
    this.root.add(this.pivot);
    this.centreOffset = centre.clone();
    this.meshes = [];
    this.model.traverse((o) => {
      if (o.isMesh && o.morphTargetDictionary) this.meshes.push({ mesh: o, order: rig.mapTargets(o.morphTargetDictionary).order });
    });
    this.phase = 17.3 * seed;  // each head moves on its own
  }

  /** The weights at `time` (the character's clock: heard audio time) onto the meshes; the head's sway. */
  update(time, headMotion) {
    const weights = this.character.update(time);
    for (const { mesh, order } of this.meshes) {
      const influences = mesh.morphTargetInfluences;
      for (let i = 0; i < order.length; ++i) influences[i] = order[i] >= 0 ? weights[order[i]] : 0;
    }
    if (headMotion) this.sway(time + this.phase);
    return weights;
  }

  // Incommensurate slow sines (demo/face_animator.cpp): never repeats visibly, degrees.
  sway(t) {
    const deg = 2.5, rad = Math.PI / 180;
    const pitch = deg * 0.6 * (Math.sin(0.31 * t) + 0.5 * Math.sin(0.83 * t));
    const yaw = deg * (Math.sin(0.23 * t) + 0.4 * Math.sin(0.61 * t));
    const roll = deg * 0.35 * Math.sin(0.17 * t);
    this.pivot.rotation.set(pitch * rad, yaw * rad, roll * rad, 'YXZ');
  }

  /** The mesh with the most vertices that has morph targets (the skin). */
  face() {
    return this.meshes.map((m) => m.mesh)
      .reduce((a, b) => (a.geometry.attributes.position.count >= b.geometry.attributes.position.count ? a : b));
  }

  release() {
    this.character.release();
    this.root.removeFromParent();
  }
}

/** Places the heads' centres in a grid around the origin; returns the grid's width and height. */
export function layOut(heads) {
  const columns = Math.ceil(Math.sqrt(heads.length)), rows = Math.ceil(heads.length / columns);
  const { x: w, y: h } = heads[0].size;
  const dx = 1.15 * w, dy = 1.1 * h;
  heads.forEach((head, i) => {
    const column = i % columns, row = Math.floor(i / columns);
    const c = head.centreOffset;
    head.root.position.set((column - (columns - 1) / 2) * dx - c.x, ((rows - 1) / 2 - row) * dy - c.y, -c.z);
  });
  return { width: columns * dx, height: rows * dy };
}
