// The demo page: the built-in head (or ?head=URL, or a GLB opened or dropped)
// in three.js, ?heads=N copies of it, speaking typed text through espeak-ng
// (WebAssembly, GPL-3, loaded on the first Enter), a recording aligned to its
// transcript, a recording alone or the microphone (the rough mode), with
// facerig's runtime (WebAssembly, MIT) driving the morph targets from the
// AudioContext clock. window.facerigDemo is what the browser tests read.
import * as THREE from 'three';
import { loadFacerig } from '../dist/facerig.mjs';
import { createSpeaker } from './speech.mjs';
import { Head, layOut, readHead } from './heads.mjs';
import { aperture, findLips } from './lips.mjs';
import { apertureCurve, drawFrames, replayWeights } from './probes.mjs';
import { alignRecording, decodeMono, roughSpeech, startMicrophone } from './audio_input.mjs';
import { FaceClock } from './face_clock.mjs';
import { FrameStats } from './frame_stats.mjs';

const params = new URLSearchParams(location.search);
const headUrl = params.get('head') ?? '../../../build/data/default_head.glb';
const headCount = Math.min(100, Math.max(1, Number.parseInt(params.get('heads') ?? '1', 10) || 1));
// ?render=off: faces animate without drawing (the lip-sync tests sample every
// frame on software GL, where drawing a head takes most of a frame).
const drawing = params.get('render') !== 'off';
const headMotion = !params.has('still');
// The microphone's face runs this far behind its sound: the rough stream's
// phonemes become final about 0.3 s after their audio, which comes in 43 ms
// blocks, to a main thread that may be busy.
const MIC_DELAY = 0.5;

const message = document.getElementById('message');
const hud = document.getElementById('hud');
const demo = (window.facerigDemo = { ready: false, error: null, frames: [], recording: true, stats: {} });
function show(text) { message.textContent = text; }

const renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
renderer.setPixelRatio(window.devicePixelRatio);
document.getElementById('view').appendChild(renderer.domElement);
// Software GL can take so long over a frame that the browser resets the GPU process: say so.
renderer.domElement.addEventListener('webglcontextlost', () => {
  demo.contextLost = (demo.contextLost ?? 0) + 1;
  show('The WebGL context was lost (the browser reset its GPU process): the faces go on, the drawing stops ' +
       'until the context is restored. On software GL, fewer heads (?heads=N) help.');
});
renderer.domElement.addEventListener('webglcontextrestored', () => show(''));
const scene = new THREE.Scene();
scene.background = new THREE.Color(0x20242a);
scene.add(new THREE.HemisphereLight(0xffffff, 0x404040, 1.2));
const key = new THREE.DirectionalLight(0xffffff, 2.0);
key.position.set(1, 1.5, 2);
scene.add(key);
const camera = new THREE.PerspectiveCamera(30, 1, 0.01, 1000);
let framed = { width: 1, height: 1 };

function resize() {
  const { clientWidth: w, clientHeight: h } = renderer.domElement.parentElement;
  renderer.setSize(w, h);
  camera.aspect = w / h;
  // Fit the grid of heads: whichever of its width and height needs the camera farther.
  const halfFov = THREE.MathUtils.degToRad(camera.fov / 2);
  const zoom = Number(params.get('zoom') ?? 1);  // ?zoom=0.5: the camera twice as far
  const distance = (1.1 / zoom) * Math.max(framed.height / 2, framed.width / 2 / camera.aspect) / Math.tan(halfFov);
  camera.position.set(0, 0.03 * framed.height, distance);
  camera.near = distance / 100;
  camera.far = distance * 10;
  camera.lookAt(0, 0.03 * framed.height, 0);
  camera.updateProjectionMatrix();
}
window.addEventListener('resize', resize);

const audio = new AudioContext();
const clock = new FaceClock(audio);

let facerig = null, speaker = null, rig = null, heads = [], lips = null, line = null, microphone = null;

/** Puts `headCount` copies of the head in these GLB bytes on the page, replacing the current ones. */
async function setHead(bytes, name) {
  const head = await readHead(facerig, bytes, name);  // throws before anything on the page changes
  stopMicrophone();
  for (const h of heads) h.release();
  rig?.release();
  rig = head.rig;
  heads = Array.from({ length: headCount }, (_, i) => new Head(rig, head.template, i + 1));
  for (const h of heads) scene.add(h.root);
  framed = layOut(heads);
  resize();
  const face = heads[0].face(), pair = findLips(face);
  lips = pair && { face, pair };
  line = null;
  show(head.notes.join('\n'));
  demo.head = { name, shapes: rig.info.shapeCount, heads: heads.length };
  demo.heads = heads;
}

/** Every head says `speech` from AudioContext time `when` (a line replaces the microphone's). */
function speakAll(speech, when) {
  stopMicrophone();
  const start = clock.audioToClock(when);
  for (const h of heads) h.character.speak(speech, start);
  line = { phonemes: speech.phonemes(), start, audioStart: when };
  demo.frames.length = 0;
  demo.line = line;
  return line;
}

/** Plays mono samples from a moment just ahead; returns that AudioContext time. */
function play(samples, sampleRate) {
  const buffer = audio.createBuffer(1, Math.max(1, samples.length), sampleRate);
  buffer.copyToChannel(samples, 0);
  const source = audio.createBufferSource();
  source.buffer = buffer;
  source.connect(audio.destination);
  const when = audio.currentTime + 0.05;
  source.start(when);
  demo.playing = { samples, sampleRate, start: when };
  return when;
}

demo.speakTrack = (track) => {
  const speech = facerig.speechFromTrack(track);
  try {
    return speakAll(speech, audio.currentTime + 0.05);
  } finally {
    speech.release();
  }
};

demo.speakText = async (text, voice) => {
  const { phonemes, samples, sampleRate } = await speaker.render(text, voice);
  const speech = facerig.speechFromPhonemes(phonemes);
  try {
    return speakAll(speech, play(samples, sampleRate));
  } finally {
    speech.release();
  }
};

/** A recording's bytes: aligned to `transcript` in `voice`, or alone (rough mode) when transcript is null. */
demo.speakRecording = async (bytes, transcript, voice) => {
  const recording = await decodeMono(bytes);
  const speech = transcript === null ? roughSpeech(facerig, recording)
                                     : await alignRecording(facerig, speaker, recording, transcript, voice);
  if (speech.fit && !speech.fit.fits) {
    show(`the recording and the transcript do not seem to match (match confidence ${speech.fit.confidence.toFixed(2)}, ` +
         `speech ${speech.fit.tempo.toFixed(2)} times the transcript's): check the transcript; speaking it anyway`);
  }
  try {
    return speakAll(speech, play(recording.samples, recording.sampleRate));
  } finally {
    speech.release();
  }
};

function stopMicrophone() {
  if (!microphone) return;
  const { stop, begun } = microphone;
  microphone = null;
  stop();
  if (begun()) for (const h of heads) h.character.endLine();
  document.getElementById('mic').textContent = 'microphone';
}

demo.toggleMicrophone = async () => {
  if (microphone) {
    stopMicrophone();
    return false;
  }
  await audio.resume();
  let begun = false;
  const live = await startMicrophone(facerig, audio, (phonemes, streamStart) => {
    if (!begun) {
      // MIC_DELAY after the stream's first sample, or later if these phonemes came later than that
      // (a busy page): the face must not have passed them already.
      const now = clock.read(performance.now());
      const start = Math.max(clock.audioToClock(streamStart) + MIC_DELAY, now - phonemes[0].start + 0.1);
      for (const h of heads) h.character.beginLine(start);
      line = { phonemes: [], start, live: true };
      demo.frames.length = 0;
      demo.line = line;
      begun = true;
    }
    const shownUpTo = clock.read(performance.now()) - line.start;
    for (const p of phonemes) {
      for (const h of heads) h.character.pushPhoneme(p);
      line.phonemes.push(p);
      if (p.start < shownUpTo) line.late = (line.late ?? 0) + 1;  // arrived after the face reached it
    }
  }, (error) => { stopMicrophone(); show(error.message); });
  microphone = { stop: live.stop, begun: () => begun };
  return true;
};

// The tests' probes (probes.mjs) on the first head.
demo.replay = (track, times, seed) => replayWeights(facerig, heads[0], rig, track, times, seed);
demo.apertureCurve = (phonemes, times) => apertureCurve(heads[0], rig, lips, phonemes, times);
demo.drawFrames = (count) => drawFrames(renderer, scene, camera, count);

demo.setEmotion = (name, target) => { for (const h of heads) h.character.setEmotion(name, target); };

const stats = new FrameStats();
demo.resetStats = () => stats.reset();
function frame(now) {
  // demo.pinTime (tests, screenshots): hold the face at that time of the line.
  const t = demo.pinTime !== undefined && line ? line.start + demo.pinTime : clock.read(now);
  const began = performance.now();
  for (const head of heads) head.update(t, headMotion);
  const updated = performance.now();
  if (line && lips && demo.recording) {
    const state = heads[0].character.state();
    demo.frames.push({ t: t - line.start, aperture: aperture(lips.face, lips.pair), viseme: state.viseme, at: now });
  }
  demo.onFrame?.(t);  // the tests' probe
  if (drawing || demo.drawOnce) renderer.render(scene, camera);
  demo.drawOnce = false;
  stats.add(now, updated - began, performance.now() - updated);
  if (stats.due(now)) {
    demo.stats = { ...stats.summary(), heads: heads.length, espeakDataBytes: speaker.dataBytes };
    hud.textContent = stats.text(heads.length) +
      `\nclock ${t.toFixed(2)} s  ${heads[0]?.character.state().viseme ?? ''}` +
      (speaker.dataBytes ? `  espeak-ng data ${(speaker.dataBytes / 1024).toFixed(0)} kB` : '');
  }
}

async function readFile(file) {
  return new Uint8Array(await file.arrayBuffer());
}

function isGlb(bytes) { return bytes.length >= 4 && String.fromCharCode(...bytes.subarray(0, 4)) === 'glTF'; }
const AUDIO_NAME = /\.(wav|ogg|oga|flac|mp3|m4a|aac|opus|webm)$/i;

// A file opened or dropped: a head if it is a GLB (or neither audio nor
// GLB: facerig's reader then says what is wrong), else a recording.
async function openFile(file, as) {
  const bytes = await readFile(file);
  const audioFile = as === 'audio' || (as !== 'head' && !isGlb(bytes) && (file.type.startsWith('audio/') || AUDIO_NAME.test(file.name)));
  if (!audioFile) {
    await setHead(bytes, file.name);
    return;
  }
  await audio.resume();
  const rough = document.getElementById('audioMode').value === 'rough';
  const text = document.getElementById('text').value.trim();
  if (!rough && !text) throw new Error('type the recording\'s transcript first, or choose "audio alone: rough"');
  await demo.speakRecording(bytes.buffer, rough ? null : text, document.getElementById('voice').value);
}

// Any failure of a user action becomes the visible message, never an uncaught error.
function guarded(action) {
  return async (...args) => {
    try {
      show('');
      await action(...args);
    } catch (e) {
      show(e.message);
      demo.lastError = e.message;
    } finally {
      demo.actions = (demo.actions ?? 0) + 1;  // the tests wait on this
    }
  };
}

function wireControls() {
  const textBox = document.getElementById('text');
  const speakTyped = guarded(async (event) => {
    await audio.resume();
    const began = event.timeStamp;
    const spoken = await demo.speakText(textBox.value, document.getElementById('voice').value);
    // From the key press to the audio's first sample, on the page's clock.
    demo.firstSpeechMs = performance.now() - began + 1000 * (spoken.audioStart - audio.currentTime);
  });
  textBox.addEventListener('keydown', (event) => { if (event.key === 'Enter') speakTyped(event); });
  // Typing into the box, or choosing a voice, means speech is wanted: espeak-ng and the voice's data
  // start loading then (a failure shows when Enter is pressed).
  const voice = document.getElementById('voice');
  const prepare = () => speaker.prepare(voice.value).catch(() => {});
  textBox.addEventListener('input', prepare, { once: true });
  voice.addEventListener('change', prepare);
  for (const button of document.querySelectorAll('[data-emotion]')) {
    button.addEventListener('click', () => {
      for (const other of document.querySelectorAll('[data-emotion]')) demo.setEmotion(other.dataset.emotion, 0);
      demo.setEmotion(button.dataset.emotion, 0.8);
    });
  }
  const headFile = document.getElementById('headFile'), audioFile = document.getElementById('audioFile');
  headFile.addEventListener('change', guarded(async () => { if (headFile.files[0]) await openFile(headFile.files[0], 'head'); headFile.value = ''; }));
  audioFile.addEventListener('change', guarded(async () => { if (audioFile.files[0]) await openFile(audioFile.files[0], 'audio'); audioFile.value = ''; }));
  const micButton = document.getElementById('mic');
  micButton.addEventListener('click', guarded(async () => {
    micButton.textContent = (await demo.toggleMicrophone()) ? 'stop microphone' : 'microphone';
  }));
  window.addEventListener('dragover', (event) => { event.preventDefault(); document.body.classList.add('dragging'); });
  window.addEventListener('dragleave', () => document.body.classList.remove('dragging'));
  window.addEventListener('drop', guarded(async (event) => {
    event.preventDefault();
    document.body.classList.remove('dragging');
    const file = event.dataTransfer.files[0];
    if (file) await openFile(file);
  }));
  window.addEventListener('unhandledrejection', (event) => show(String(event.reason?.message ?? event.reason)));
}

async function loadDefaultHead() {
  const response = await fetch(headUrl);
  if (!response.ok) throw new Error(`${headUrl}: HTTP ${response.status}`);
  await setHead(new Uint8Array(await response.arrayBuffer()), decodeURIComponent(headUrl.split('/').pop()));
}

// The controls work even when the first head fails: another can be opened.
async function start() {
  facerig = await loadFacerig();
  speaker = createSpeaker(audio);
  Object.assign(demo, { facerig, speaker, audio });
  wireControls();
  renderer.setAnimationLoop(frame);
  try {
    await loadDefaultHead();
  } catch (e) {
    demo.error = e.message;
    show(e.message);
  }
  demo.ready = true;
}

start().catch((e) => {
  demo.error = e.message;
  show(e.message);
});
