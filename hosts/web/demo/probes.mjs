// What the browser tests measure on the page's own head besides its frames:
// a fresh character swapped in for a moment (the page's mesh and mapping,
// the character's own seed and time), and the real cost of a drawn frame.
import { aperture } from './lips.mjs';

function withCharacter(head, rig, options, use) {
  const saved = head.character;
  head.character = rig.createCharacter(options);
  try {
    return use(head.character);
  } finally {
    head.character.release();
    head.character = saved;
  }
}

/**
 * The weights the page gives the head's skin for a phoneme track spoken at time 0 by a fresh
 * character with `seed`, updated at `times`: {names, frames}, read back from the mesh's influences.
 */
export function replayWeights(facerig, head, rig, track, times, seed) {
  return withCharacter(head, rig, { seed }, (character) => {
    const speech = facerig.speechFromTrack(track);
    character.speak(speech, 0);
    speech.release();
    const face = head.face(), names = Object.keys(face.morphTargetDictionary);
    const frames = times.map((t) => {
      head.update(t, false);
      return names.map((name) => face.morphTargetInfluences[face.morphTargetDictionary[name]]);
    });
    return { names, frames };
  });
}

/** The lip aperture for `phonemes` spoken at 0 (no blinks or gaze) at each of `times`: what a frame should show. */
export function apertureCurve(head, rig, lips, phonemes, times) {
  return withCharacter(head, rig, { blinks: false, gaze: false }, (character) => {
    character.speakPhonemes(phonemes, 0);
    return times.map((t) => { head.update(t, false); return aperture(lips.face, lips.pair); });
  });
}

/**
 * Draws the scene `count` times, each frame waited for by reading one of its pixels back (a frame's
 * real cost: animation frames may come faster than software GL draws them); ms per frame.
 */
export function drawFrames(renderer, scene, camera, count) {
  const gl = renderer.getContext(), pixel = new Uint8Array(4);
  const began = performance.now();
  for (let i = 0; i < count; ++i) {
    renderer.render(scene, camera);
    gl.readPixels(0, 0, 1, 1, gl.RGBA, gl.UNSIGNED_BYTE, pixel);
  }
  return (performance.now() - began) / count;
}
