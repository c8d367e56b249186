// The WebAssembly module in node, without a browser (ctest, label web):
//   node --no-experimental-fetch node_test.mjs HEAD.frig REFERENCE_FRAME.bin [HEAD.glb]
// REFERENCE_FRAME.bin is what the native C consumer (hosts/c/tests/consumer.c)
// writes: the weights and positions of frame 20 of the same track. HEAD.glb,
// the same head as a GLB, is read through tinygltf and must give the same.
import { readFileSync } from 'node:fs';
import { createRequire } from 'node:module';
import { dirname } from 'node:path';
import { performance } from 'node:perf_hooks';
import { fileURLToPath } from 'node:url';

// Emscripten 3.1.6's ES module reads the .wasm in node through CommonJS's
// require and __dirname, which an ES module lacks: give them, then import.
globalThis.require = createRequire(import.meta.url);
globalThis.__dirname = dirname(fileURLToPath(new URL('../dist/facerig.mjs', import.meta.url)));
const { loadFacerig, FacerigError } = await import('../dist/facerig.mjs');

const [headPath, referencePath, glbPath] = process.argv.slice(2);
let failures = 0;
function check(condition, what) {
  console.log(`${condition ? 'ok  ' : 'FAIL'} ${what}`);
  if (!condition) failures += 1;
}

// The track of consumer.c: "a pa ba ma", bilabials at 0.22, 0.38, 0.53 s.
const track = {
  format: 'facerig-phoneme-track', version: 1, text: 'a pa ba ma', language: 'en-us',
  phonemes: [
    { start: 0.00, duration: 0.10, symbol: '_:' }, { start: 0.10, duration: 0.12, symbol: 'a#', word_start: true },
    { start: 0.22, duration: 0.04, symbol: 'p', word_start: true }, { start: 0.26, duration: 0.12, symbol: 'A:' },
    { start: 0.38, duration: 0.03, symbol: 'b', word_start: true }, { start: 0.41, duration: 0.12, symbol: 'A:' },
    { start: 0.53, duration: 0.05, symbol: 'm', word_start: true }, { start: 0.58, duration: 0.15, symbol: 'A:' },
    { start: 0.73, duration: 0.20, symbol: '_:' }],
};
const bilabials = [[0.22, 0.26], [0.38, 0.41], [0.53, 0.58]];

// consumer.c's FindLips: the midline pair nearest at rest of a vertex jawOpen
// carries (lower lip) and one it leaves (upper lip), on the skin (part 0).
function findLips(rig, neutral) {
  const jaw = new Float32Array(rig.info.shapeCount);
  jaw[rig.findShape('jawOpen')] = 1;
  const open = rig.blend(jaw).slice();
  const n = rig.info.vertexCount, limit = 0.01 * rig.info.boundingDiagonal;
  const moved = new Float32Array(n);
  let most = 0;
  for (let i = 0; i < n; ++i) {
    moved[i] = Math.hypot(open[3 * i] - neutral[3 * i], open[3 * i + 1] - neutral[3 * i + 1], open[3 * i + 2] - neutral[3 * i + 2]);
    most = Math.max(most, moved[i]);
  }
  const skin = rig.skinVertices ?? [0, n];
  let best = Infinity, lips = null;
  for (let i = skin[0]; i < skin[1]; ++i) {
    if (Math.abs(neutral[3 * i]) > limit || moved[i] < 0.5 * most) continue;
    for (let j = skin[0]; j < skin[1]; ++j) {
      if (Math.abs(neutral[3 * j]) > limit || moved[j] > 0.1 * most) continue;
      const d = (neutral[3 * i] - neutral[3 * j]) ** 2 + (neutral[3 * i + 1] - neutral[3 * j + 1]) ** 2 +
                (neutral[3 * i + 2] - neutral[3 * j + 2]) ** 2;
      if (d < best) { best = d; lips = { upper: j, lower: i }; }
    }
  }
  return lips;
}
const distance = (p, a, b) => Math.hypot(p[3 * a] - p[3 * b], p[3 * a + 1] - p[3 * b + 1], p[3 * a + 2] - p[3 * b + 2]);

// and the bytes of the .wasm (its file: URL is not a path to node's fs).
const facerig = await loadFacerig({ wasmBinary: readFileSync(new URL('../dist/facerig.wasm', import.meta.url)) });
check(facerig.abiVersion >>> 16 === 0, `ABI version ${facerig.abiVersion >>> 16}.${facerig.abiVersion & 0xffff}`);
const headBytes = readFileSync(headPath);
const rig = facerig.loadRig(headBytes, 'default_head.glb');
check(rig.info.shapeCount >= 52 && rig.findShape('jawOpen') >= 0,
      `built-in head from bytes: ${rig.info.vertexCount} vertices, ${rig.info.shapeCount} shapes`);

// Speak the track at 60 fps; the lips close on every bilabial, open between.
const neutral = rig.neutral();
const lips = findLips(rig, neutral);
const speech = facerig.speechFromTrack(track);
check(speech.phonemes().length === 9 && speech.phonemes()[2].symbol === 'p', 'phoneme track read back');
const character = rig.createCharacter();
character.speak(speech, 0);
speech.release();
let widest = 0, sawPP = false, frame20 = null, positions20 = null;
const lowest = [Infinity, Infinity, Infinity];
for (let frame = 0; frame < 60; ++frame) {
  const t = frame / 60;
  const weights = character.update(t);
  const positions = rig.blend(weights);
  sawPP ||= character.state().viseme === 'PP';
  const aperture = distance(positions, lips.upper, lips.lower);
  widest = Math.max(widest, aperture);
  bilabials.forEach(([start, end], k) => {
    if (t >= start - 0.06 && t <= end) lowest[k] = Math.min(lowest[k], aperture);
  });
  if (frame === 20) { frame20 = weights.slice(); positions20 = positions.slice(); }
}
console.log(`aperture: widest ${widest.toFixed(3)}, on p ${lowest[0].toFixed(4)}, b ${lowest[1].toFixed(4)}, m ${lowest[2].toFixed(4)}`);
check(widest > 0.5, 'the mouth opens on the vowels (> 0.5 cm)');
check(lowest.every((l) => l < 0.1 * widest), 'the lips close on p, b and m (< 10 % of the widest)');
check(sawPP, 'the state reports viseme PP');

// The same numbers as native: frame 20 of the C consumer, same track and seed.
const reference = new Float32Array(new Uint8Array(readFileSync(referencePath)).buffer);
const nativeWeights = reference.subarray(0, rig.info.shapeCount);
const nativePositions = reference.subarray(rig.info.shapeCount);
const maxDiff = (a, b) => a.reduce((m, v, i) => Math.max(m, Math.abs(v - b[i])), 0);
const weightDiff = maxDiff(frame20, nativeWeights), positionDiff = maxDiff(positions20, nativePositions);
console.log(`native vs wasm at frame 20: weights ${weightDiff.toExponential(2)}, positions ${positionDiff.toExponential(2)}`);
check(nativePositions.length === 3 * rig.info.vertexCount && weightDiff <= 1e-5, 'weights within 1e-5 of native');
check(positionDiff <= 1e-5 * rig.info.boundingDiagonal, 'blended positions within 1e-5 (relative) of native');

// Streaming: the same line pushed phoneme by phoneme gives the same weights.
const streamed = rig.createCharacter();
streamed.beginLine(0);
for (const p of track.phonemes) streamed.pushPhoneme({ ...p, language: 'en-us', wordStart: p.word_start });
streamed.endLine();
let streamDiff = 0;
const again = rig.createCharacter();
const againSpeech = facerig.speechFromTrack(track);
again.speak(againSpeech, 0);
againSpeech.release();
for (let frame = 0; frame < 60; ++frame) {
  const a = again.update(frame / 60).slice();
  streamDiff = Math.max(streamDiff, maxDiff(streamed.update(frame / 60), a));
}
check(streamDiff <= 1e-6, `streamed phonemes equal the whole line (max difference ${streamDiff})`);

// Attach by a mesh's target names in another order and spellings.
const meshNames = ['mouthSmileLeft', 'viseme_PP_unknown', 'JAWOPEN', 'blendShape1.eyeBlink_L'];
const target = rig.createCharacter({ seed: 7 });
const plain = rig.createCharacter({ seed: 7 });
const unmatched = target.attach(meshNames);
check(unmatched.length === 1 && unmatched[0] === 'viseme_PP_unknown', `unmatched target names: ${unmatched}`);
target.setEmotion('joy', 1); plain.setEmotion('joy', 1);
let attachOk = true;
for (let frame = 0; frame < 90; ++frame) {
  const rigOrder = plain.update(frame / 60), meshOrder = target.update(frame / 60);
  const expect = [rig.findShape('mouthSmile_L') >= 0 ? rigOrder[rig.findShape('mouthSmile_L')] : rigOrder[rig.findShape('mouthSmileLeft')],
                  0, rigOrder[rig.findShape('jawOpen')], rigOrder[rig.findShape('eyeBlink_L')] ?? rigOrder[rig.findShape('eyeBlinkLeft')]];
  attachOk &&= expect.every((v, i) => Math.abs(v - meshOrder[i]) <= 0) && meshOrder.length === 4;
}
check(attachOk, 'attached weights come in the mesh\'s order, by ARKit/ICT spellings and namespaces');

// Views stay valid when the WASM memory grows.
const before = character.update(0.33).slice();
const buffer = facerig.wasm.HEAPU8.buffer;
const big = facerig.wasm._malloc(256 << 20);
check(facerig.wasm.HEAPU8.buffer !== buffer, `memory grew to ${facerig.wasm.HEAPU8.length >> 20} MB`);
check(maxDiff(character.update(0.33), before) === 0, 'update after growth gives the same weights');
facerig.wasm._free(big);

// Bad input: errors with status and message, no crash.
function expectError(fn, status, what) {
  try {
    fn();
    check(false, `${what}: no error`);
  } catch (e) {
    check(e instanceof FacerigError && e.status === status, `${what}: ${e.status}: ${e.message}`);
  }
}
expectError(() => facerig.loadRig(headBytes.subarray(0, 1000), 'truncated.glb'), 'FR_ERROR_FORMAT', 'truncated GLB');
expectError(() => facerig.loadRig(new TextEncoder().encode('not a glb at all'), 'text.glb'), 'FR_ERROR_FORMAT', 'not a GLB');
expectError(() => facerig.speechFromTrack('{"format": "x"}'), 'FR_ERROR_FORMAT', 'bad phoneme track');
expectError(() => character.setEmotion('boredom', 1), 'FR_ERROR_INVALID_ARGUMENT', 'unknown emotion');
expectError(() => character.update(NaN), 'FR_ERROR_INVALID_ARGUMENT', 'non-finite time');
expectError(() => rig.createCharacter().pushPhoneme({ start: 0, duration: 0.1, symbol: 'p' }), 'FR_ERROR_STATE',
            'a push with no line begun');

// The same head as a GLB (tinygltf, then the runtime's glTF reader): the same
// shapes and the same weights at frame 20.
if (glbPath) {
  const glb = readFileSync(glbPath);
  const glbRig = facerig.loadRig(glb, 'default_head.glb');
  check(glbRig.info.vertexCount === rig.info.vertexCount &&
        glbRig.shapeNames.join() === rig.shapeNames.join(), `GLB head: ${glbRig.info.shapeCount} shapes, as the .frig`);
  const glbCharacter = glbRig.createCharacter();
  const glbSpeech = facerig.speechFromTrack(track);
  glbCharacter.speak(glbSpeech, 0);
  glbSpeech.release();
  let glbFrame20 = null;
  for (let frame = 0; frame <= 20; ++frame) glbFrame20 = glbCharacter.update(frame / 60);
  const glbDiff = maxDiff(glbFrame20, nativeWeights);
  check(glbDiff <= 1e-5, `GLB head: frame 20 within 1e-5 of native (max difference ${glbDiff})`);
  glbCharacter.release();
  glbRig.release();

  // tinygltf's own messages, built in this module without std::stringstream
  // (hosts/web/src/tiny_gltf.cpp): text and numbers as a stream writes them.
  const withJson = (edit) => {
    const view = new DataView(glb.buffer, glb.byteOffset, glb.byteLength);
    const jsonLength = view.getUint32(12, true);
    const json = JSON.parse(new TextDecoder().decode(glb.subarray(20, 20 + jsonLength)));
    edit(json);
    const text = new TextEncoder().encode(JSON.stringify(json));
    const padded = new Uint8Array((text.length + 3) & ~3).fill(0x20);
    padded.set(text);
    const rest = glb.subarray(20 + jsonLength);
    const out = new Uint8Array(20 + padded.length + rest.length);
    out.set(glb.subarray(0, 20));
    out.set(padded, 20);
    out.set(rest, 20 + padded.length);
    new DataView(out.buffer).setUint32(8, out.length, true);
    new DataView(out.buffer).setUint32(12, padded.length, true);
    return out;
  };
  const tinygltfMessage = (edit) => {
    try {
      facerig.loadRig(withJson(edit), 'bad.glb');
      return 'no error';
    } catch (e) {
      return `${e.status}: ${e.message}`;
    }
  };
  const badType = tinygltfMessage((json) => { json.accessors[0].componentType = 9999; });
  check(badType === 'FR_ERROR_FORMAT: bad.glb: tinygltf: Invalid `componentType` in accessor. Got 9999', badType);
  const badLength = tinygltfMessage((json) => { json.buffers[0].byteLength = 1e9; });
  check(badLength.startsWith('FR_ERROR_FORMAT: bad.glb: tinygltf: Invalid `byteLength\'. Must be equal or less than ' +
                             'binary size: `byteLength\' = 1000000000, binary size = ') &&
        /binary size = \d+$/.test(badLength), badLength);
}

// Per-frame cost of update() (the page's cost per character per frame).
const frames = 20000;
let t0 = performance.now();
for (let i = 0; i < frames; ++i) character.update(0.2 + (i % 60) / 60);
const updateMicroseconds = ((performance.now() - t0) * 1000) / frames;
console.log(`update: ${updateMicroseconds.toFixed(2)} us per call (wasm in node)`);

for (const c of [character, streamed, again, target, plain]) c.release();
rig.release();
console.log(failures ? `${failures} check(s) failed` : 'all checks passed');
process.exit(failures ? 1 : 0);
