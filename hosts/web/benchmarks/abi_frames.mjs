// Per-frame cost through the WebAssembly module in node, for `facerig-bench web`
// (the same protocol as hosts/python/benchmarks/abi_frames.py):
//   node --no-experimental-fetch abi_frames.mjs HEAD TRACK FRAMES REPEATS [DIST]
// A character speaks TRACK (a phoneme-track JSON) on HEAD (.glb or .frig);
// FRAMES frames of character.update (and a tenth as many of update +
// rig.blend), the fastest of REPEATS runs; prints {"update_us", "update_blend_us"}
// per frame as JSON, with the bytes a page loads (facerig.wasm and facerig.mjs,
// raw and gzip -9). DIST holds them (default ../dist).
import { readFileSync } from 'node:fs';
import { createRequire } from 'node:module';
import { basename, resolve } from 'node:path';
import { performance } from 'node:perf_hooks';
import { setFlagsFromString } from 'node:v8';
import { fileURLToPath, pathToFileURL } from 'node:url';
import { gzipSync } from 'node:zlib';

const [head, track, framesText, repeatsText, distArgument] = process.argv.slice(2);
const frames = Number(framesText), repeats = Number(repeatsText);
if (!track || !(frames >= 1) || !(repeats >= 1)) {
  console.error('usage: node --no-experimental-fetch abi_frames.mjs HEAD TRACK FRAMES REPEATS [DIST]');
  process.exit(2);
}
const dist = distArgument ? resolve(distArgument) : fileURLToPath(new URL('../dist', import.meta.url));

// V8 first runs WebAssembly as baseline code and optimises it in the background
// over the next seconds; the steady state is measured, so optimise from the start.
setFlagsFromString('--no-liftoff');
// Emscripten 3.1.6's ES module looks for CommonJS's require and __dirname in node.
globalThis.require = createRequire(import.meta.url);
globalThis.__dirname = dist;
const { loadFacerig } = await import(pathToFileURL(`${dist}/facerig.mjs`).href);
const facerig = await loadFacerig({ wasmBinary: readFileSync(`${dist}/facerig.wasm`) });

const rig = facerig.loadRig(readFileSync(head), basename(head));
const character = rig.createCharacter();
const speech = facerig.speechFromTrack(readFileSync(track, 'utf8'));
character.speak(speech, 0);
speech.release();
const period = 840;  // 14 s of frames, the track's length

function bestPerFrame(count, frame) {
  let best = Infinity;
  for (let r = 0; r < repeats; ++r) {
    const start = performance.now();
    for (let i = 0; i < count; ++i) frame(i);
    best = Math.min(best, (performance.now() - start) / count);
  }
  return best * 1000;
}
const update = (i) => character.update((i % period) / 60);
const updateBlend = (i) => rig.blend(character.update((i % period) / 60));
bestPerFrame(Math.min(frames, 1000), update);  // JavaScript's JIT warms up first
const costs = { update_us: bestPerFrame(frames, update),
                update_blend_us: bestPerFrame(Math.max(Math.floor(frames / 10), 1), updateBlend) };
const sizes = {};
for (const [key, file] of [['wasm', 'facerig.wasm'], ['mjs', 'facerig.mjs']]) {
  const bytes = readFileSync(`${dist}/${file}`);
  sizes[`${key}_bytes`] = bytes.length;
  sizes[`${key}_gzip_bytes`] = gzipSync(bytes, { level: 9 }).length;
}
console.log(JSON.stringify({ ...costs, ...sizes }));
character.release();
rig.release();
