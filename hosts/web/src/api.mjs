
// ---- facerig's JavaScript API (hosts/web/src/api.mjs) ----------------------
// Appended to emscripten's ES module (the `createFacerigWasm` above), so that a
// page imports one file. Every call goes through the C ABI of hosts/c
// (facerig.h); nothing here re-implements the runtime. Documented in
// docs/web.md.

/** A failed facerig call: `status` is the fr_status name, the message facerig's. */
export class FacerigError extends Error {
  constructor(status, message) {
    super(message);
    this.name = 'FacerigError';
    this.status = status;
  }
}

/** fr_emotion, by name. */
export const EMOTIONS = Object.freeze({ joy: 0, sadness: 1, fear: 2, anger: 3, surprise: 4, disgust: 5 });
const VISEMES = ['sil', 'PP', 'FF', 'TH', 'DD', 'kk', 'CH', 'SS', 'nn', 'RR', 'aa', 'E', 'ih', 'oh', 'ou'];

// Sizes and offsets of the ABI's structs on wasm32 (facerig.h).
const PHONEME_SIZE = 56;       // fr_phoneme: start, duration, symbol[16], language[16], word_start, reserved
const RIG_INFO_SIZE = 36;      // fr_rig_info: 8 uint32 + float
const OPTIONS_SIZE = 32;       // fr_character_options: uint64 seed, 2 floats, 3 uint32 (+ padding)
const STATE_SIZE = 44;         // fr_character_state: 3 int32, 4 floats, phoneme[16]
const NAME_CAPACITY = 16;

/** Loads the WebAssembly module; resolves to a Facerig. `options` go to emscripten (e.g. locateFile, wasmBinary). */
export async function loadFacerig(options = {}) {
  return new Facerig(await createFacerigWasm(options));
}

/** The library: rigs and speech lines. One per page is enough. */
export class Facerig {
  constructor(wasm) {
    this.wasm = wasm;
    this.scratch = wasm._malloc(256);  // out-parameters of every call (one thread: no overlap)
    this.phoneme = wasm._malloc(PHONEME_SIZE);
    this.heapBuffer = null;
    this.refreshViews();
  }

  /** The ABI version (major << 16 | minor). */
  get abiVersion() { return this.wasm._fr_abi_version() >>> 0; }

  /** Typed-array views of the WASM memory, re-made when it has grown. */
  refreshViews() {
    const buffer = this.wasm.HEAPU8.buffer;
    if (buffer !== this.heapBuffer) {
      this.heapBuffer = buffer;
      this.u8 = new Uint8Array(buffer);
      this.u32 = new Uint32Array(buffer);
      this.i32 = new Int32Array(buffer);
      this.f32 = new Float32Array(buffer);
      this.f64 = new Float64Array(buffer);
    }
  }

  check(status) {
    if (status === 0) return;
    const name = this.wasm.UTF8ToString(this.wasm._fr_status_name(status));
    throw new FacerigError(name, this.wasm.UTF8ToString(this.wasm._fr_last_error()));
  }

  // Runs fn(pointer) with `bytes` copied into WASM memory, then frees them.
  withBytes(bytes, fn) {
    const view = bytes instanceof Uint8Array ? bytes : new Uint8Array(bytes.buffer ?? bytes, bytes.byteOffset ?? 0,
                                                                        bytes.byteLength);
    const pointer = this.wasm._malloc(Math.max(1, view.length));
    try {
      this.refreshViews();
      this.u8.set(view, pointer);
      return fn(pointer, view.length);
    } finally {
      this.wasm._free(pointer);
    }
  }

  withString(text, fn) {
    return this.withBytes(new TextEncoder().encode(text + '\0'), (pointer, size) => fn(pointer, size - 1));
  }

  /** A rig from the bytes of a .glb or .frig (ArrayBuffer or typed array); `name` is for messages. */
  loadRig(bytes, name = 'rig.glb') {
    const handle = this.withBytes(bytes, (pointer, size) => this.withString(name, (namePointer) => {
      this.check(this.wasm._fr_rig_load_bytes(pointer, size, namePointer, this.scratch));
      this.refreshViews();
      return this.u32[this.scratch >> 2];
    }));
    return new Rig(this, handle);
  }

  /** A speech line from a facerig phoneme-track JSON (text or object). */
  speechFromTrack(track) {
    const text = typeof track === 'string' ? track : JSON.stringify(track);
    return this.withString(text, (pointer, size) => {
      this.check(this.wasm._fr_speech_load_track_bytes(pointer, size, this.scratch));
      this.refreshViews();
      return new Speech(this, this.u32[this.scratch >> 2]);
    });
  }

  /**
   * A speech line from timed phonemes [{start, duration, symbol, language?, wordStart?}] (seconds,
   * espeak-ng symbols) and, optionally, its mono audio (Float32Array in [-1, 1]) at `sampleRate`.
   */
  speechFromPhonemes(phonemes, samples = null, sampleRate = 0) {
    const array = this.wasm._malloc(Math.max(1, phonemes.length) * PHONEME_SIZE);
    try {
      phonemes.forEach((p, i) => this.writePhoneme(array + i * PHONEME_SIZE, p));
      const run = (samplePointer, sampleCount) => {
        this.check(this.wasm._fr_speech_create(array, phonemes.length, samplePointer, sampleCount,
                                               samples ? sampleRate : 0, this.scratch));
        this.refreshViews();
        return new Speech(this, this.u32[this.scratch >> 2]);
      };
      if (!samples) return run(0, 0);
      return this.withBytes(new Uint8Array(samples.buffer, samples.byteOffset, samples.byteLength),
                            (pointer) => run(pointer, samples.length));
    } finally {
      this.wasm._free(array);
    }
  }

  /** The rough mode: a coarse mouth from mono audio alone (no transcript). */
  speechFromAudio(samples, sampleRate) {
    return this.withBytes(new Uint8Array(samples.buffer, samples.byteOffset, samples.byteLength), (pointer) => {
      this.check(this.wasm._fr_speech_from_audio(pointer, samples.length, sampleRate, this.scratch));
      this.refreshViews();
      return new Speech(this, this.u32[this.scratch >> 2]);
    });
  }

  /**
   * Phonemes from audio that arrives in chunks, to push into a character as they become final
   * (fr_audio_stream). The rough mode: no transcript, any mono audio at `sampleRate` (4-384 kHz).
   */
  createRoughStream(sampleRate) {
    this.check(this.wasm._fr_audio_stream_create_rough(sampleRate, this.scratch));
    this.refreshViews();
    return new AudioStream(this, this.u32[this.scratch >> 2], sampleRate);
  }

  /**
   * Streaming alignment to a transcript: `reference` is a Speech holding the transcript spoken by a
   * synthesiser (its audio and exact phonemes, e.g. espeak-ng's in the page). The recording pushed
   * must have the reference's sample rate; the phonemes come out with the reference's symbols.
   */
  createAlignedStream(reference) {
    this.check(this.wasm._fr_audio_stream_create_aligned(reference.handle, this.scratch));
    this.refreshViews();
    return new AudioStream(this, this.u32[this.scratch >> 2], reference.audio().sampleRate);
  }

  /**
   * A whole recording (mono Float32Array at the reference's sample rate) aligned to the reference's
   * transcript at once, as native `facerig align` does (fr_speech_align): a Speech with the
   * reference's phonemes timed on the recording, and the recording. Its `fit` says whether the two
   * seem to match: {confidence, tempo, fits} (fits under facerig align's rule; the line is returned
   * either way).
   */
  alignRecording(reference, samples, sampleRate) {
    const fitSize = 24;  // fr_alignment_fit: 2 doubles, 2 int32
    const fit = this.wasm._malloc(fitSize);
    try {
      const speech = this.withBytes(new Uint8Array(samples.buffer, samples.byteOffset, samples.byteLength),
                                    (pointer) => {
        this.check(this.wasm._fr_speech_align(reference.handle, pointer, samples.length, sampleRate, fit,
                                              this.scratch));
        this.refreshViews();
        return new Speech(this, this.u32[this.scratch >> 2]);
      });
      speech.fit = { confidence: this.f64[fit >> 3], tempo: this.f64[(fit >> 3) + 1],
                     fits: this.i32[(fit + 16) >> 2] === 1 };
      return speech;
    } finally {
      this.wasm._free(fit);
    }
  }

  /** The rough mode over a whole recording, through the stream (the same phonemes as a live one). */
  roughPhonemes(samples, sampleRate) {
    const stream = this.createRoughStream(sampleRate);
    try {
      return stream.pushAll(samples);
    } finally {
      stream.release();
    }
  }

  writePhoneme(at, p) {
    this.refreshViews();
    if (!(Number.isFinite(p.start) && Number.isFinite(p.duration ?? 0))) {
      throw new FacerigError('FR_ERROR_INVALID_ARGUMENT', `phoneme '${p.symbol}': start and duration must be numbers`);
    }
    this.u8.fill(0, at, at + PHONEME_SIZE);
    this.f64[at >> 3] = p.start;
    this.f64[(at >> 3) + 1] = p.duration ?? 0;
    this.writeName(at + 16, p.symbol ?? '', 'symbol');
    this.writeName(at + 32, p.language ?? '', 'language');
    this.i32[(at + 48) >> 2] = p.wordStart ? 1 : 0;
  }

  writeName(at, text, what) {
    const bytes = new TextEncoder().encode(text);
    if (bytes.length >= NAME_CAPACITY) {
      throw new FacerigError('FR_ERROR_INVALID_ARGUMENT', `phoneme ${what} '${text}' is longer than ${NAME_CAPACITY - 1} bytes`);
    }
    this.u8.set(bytes, at);
  }

  readPhoneme(at) {
    return { start: this.f64[at >> 3], duration: this.f64[(at >> 3) + 1], symbol: this.readName(at + 16),
             language: this.readName(at + 32), wordStart: this.i32[(at + 48) >> 2] === 1 };
  }

  readName(at) {
    const end = this.u8.indexOf(0, at);
    return new TextDecoder().decode(this.u8.subarray(at, Math.min(end < 0 ? at + NAME_CAPACITY : end, at + NAME_CAPACITY)));
  }
}

/** A loaded rig (fr_rig): shape names and info; makes characters. */
export class Rig {
  constructor(facerig, handle) {
    this.facerig = facerig;
    this.handle = handle;
    const { wasm } = facerig;
    facerig.check(wasm._fr_rig_get_info(handle, facerig.scratch));
    facerig.refreshViews();
    const u = facerig.u32, at = facerig.scratch >> 2;
    this.info = {
      vertexCount: u[at], triangleCount: u[at + 1], shapeCount: u[at + 2], partCount: u[at + 3],
      hasUvs: u[at + 4] === 1, hasNormalDeltas: u[at + 5] === 1, units: u[at + 6], upAxis: u[at + 7],
      boundingDiagonal: facerig.f32[at + 8],
    };
    const nameBuffer = wasm._malloc(1024);
    try {
      this.shapeNames = [];
      for (let i = 0; i < this.info.shapeCount; ++i) {
        facerig.check(wasm._fr_rig_shape_name(handle, i, nameBuffer, 1024, 0));
        this.shapeNames.push(wasm.UTF8ToString(nameBuffer));
      }
    } finally {
      wasm._free(nameBuffer);
    }
  }

  /** The index of the shape with exactly this name, or -1. */
  findShape(name) {
    const { facerig } = this;
    return facerig.withString(name, (pointer) => {
      const status = facerig.wasm._fr_rig_find_shape(this.handle, pointer, facerig.scratch);
      if (status === 3) return -1;  // FR_ERROR_NOT_FOUND
      facerig.check(status);
      facerig.refreshViews();
      return facerig.u32[facerig.scratch >> 2];
    });
  }

  /**
   * For a mesh's morph targets (a three.js morphTargetDictionary, name -> index, or an array of
   * names): {order, unmatched}, order[i] the rig shape of target i (-1: none), matched exactly or
   * in another spelling (ARKit "mouthSmileLeft", ICT "mouthSmile_L", Oculus "viseme_PP", namespaces
   * such as "blendShape1."), and the target names no rig shape answers. For a page that drives
   * several meshes (a head's skin, eyes, teeth) from one character's update().
   */
  mapTargets(targets) {
    const names = Array.isArray(targets) ? targets : dictionaryToNames(targets);
    if (!this.canonical) {
      this.canonical = new Map();
      this.shapeNames.forEach((name, index) => {
        const key = canonicalShapeName(name);
        if (!this.canonical.has(key)) this.canonical.set(key, index);
      });
    }
    const order = new Int32Array(names.length);
    const unmatched = [];
    names.forEach((name, i) => {
      let index = this.findShape(name);
      if (index < 0) index = this.canonical.get(canonicalShapeName(name)) ?? -1;
      if (index < 0) unmatched.push(name);
      order[i] = index;
    });
    return { order, unmatched };
  }

  /**
   * A character on this rig. options: {seed, jawIntensity, lipIntensity, keyCapacity, blinks, gaze}
   * (facerig.h's fr_character_options; defaults from the library).
   */
  createCharacter(options = {}) {
    const { facerig } = this, { wasm } = facerig;
    const at = facerig.scratch;
    facerig.check(wasm._fr_character_default_options(at));
    facerig.refreshViews();
    const seed = BigInt(options.seed ?? 0);
    facerig.u32[at >> 2] = Number(seed & 0xffffffffn);
    facerig.u32[(at >> 2) + 1] = Number(seed >> 32n);
    if (options.jawIntensity !== undefined) facerig.f32[(at >> 2) + 2] = options.jawIntensity;
    if (options.lipIntensity !== undefined) facerig.f32[(at >> 2) + 3] = options.lipIntensity;
    if (options.keyCapacity !== undefined) facerig.u32[(at >> 2) + 4] = options.keyCapacity;
    if (options.blinks !== undefined) facerig.u32[(at >> 2) + 5] = options.blinks ? 1 : 0;
    if (options.gaze !== undefined) facerig.u32[(at >> 2) + 6] = options.gaze ? 1 : 0;
    const out = wasm._malloc(OPTIONS_SIZE);
    try {
      wasm.HEAPU8.copyWithin(out, at, at + OPTIONS_SIZE);
      facerig.check(wasm._fr_character_create(this.handle, out, facerig.scratch));
      facerig.refreshViews();
      return new Character(this, facerig.u32[facerig.scratch >> 2]);
    } finally {
      wasm._free(out);
    }
  }

  /** The neutral mesh's positions (3 floats per vertex), a new Float32Array. */
  neutral() {
    const { facerig } = this, count = this.info.vertexCount;
    const pointer = facerig.wasm._malloc(Math.max(1, count) * 12);
    try {
      facerig.check(facerig.wasm._fr_rig_neutral(this.handle, pointer, 0, count, 0));
      facerig.refreshViews();
      return facerig.f32.slice(pointer >> 2, (pointer >> 2) + 3 * count);
    } finally {
      facerig.wasm._free(pointer);
    }
  }

  /**
   * Positions = neutral + sum of weight * shape (fr_rig_blend), for pages that deform on the CPU.
   * `weights` in the rig's order (shapeCount floats); returns the same Float32Array every call.
   */
  blend(weights) {
    const { facerig } = this, { wasm } = facerig, count = this.info.vertexCount;
    if (!this.blendPointer) {
      this.blendPointer = wasm._malloc(Math.max(1, count) * 12);
      this.blendWeights = wasm._malloc(Math.max(1, this.info.shapeCount) * 4);
      this.positions = new Float32Array(3 * count);
    }
    facerig.refreshViews();
    facerig.f32.set(weights.subarray(0, this.info.shapeCount), this.blendWeights >> 2);
    facerig.check(wasm._fr_rig_blend(this.handle, this.blendWeights, this.info.shapeCount, 0, this.blendPointer, 0, count));
    facerig.refreshViews();
    this.positions.set(facerig.f32.subarray(this.blendPointer >> 2, (this.blendPointer >> 2) + 3 * count));
    return this.positions;
  }

  /** Frees the rig (characters made from it keep it alive until released). */
  release() {
    if (!this.handle) return;
    this.facerig.wasm._fr_rig_release(this.handle);
    if (this.blendPointer) {
      this.facerig.wasm._free(this.blendPointer);
      this.facerig.wasm._free(this.blendWeights);
    }
    this.handle = 0;
  }
}

/** An immutable speech line (fr_speech). */
export class Speech {
  constructor(facerig, handle) {
    this.facerig = facerig;
    this.handle = handle;
  }

  /** Its phonemes, as [{start, duration, symbol, language, wordStart}]. */
  phonemes() {
    const { facerig } = this, { wasm } = facerig;
    const sizing = wasm._fr_speech_phonemes(this.handle, 0, 0, facerig.scratch);
    if (sizing !== 2) facerig.check(sizing);  // FR_ERROR_BUFFER_TOO_SMALL tells the count
    facerig.refreshViews();
    const count = facerig.u32[facerig.scratch >> 2];
    const array = wasm._malloc(Math.max(1, count) * PHONEME_SIZE);
    try {
      facerig.check(wasm._fr_speech_phonemes(this.handle, array, count, 0));
      facerig.refreshViews();
      const list = [];
      for (let i = 0; i < count; ++i) list.push(facerig.readPhoneme(array + i * PHONEME_SIZE));
      return list;
    } finally {
      wasm._free(array);
    }
  }

  /** Its audio: {samples: Float32Array (mono, [-1, 1]), sampleRate} (0 samples and rate 0 without). */
  audio() {
    const { facerig } = this, { wasm } = facerig;
    const rate = facerig.scratch + 8;
    const sizing = wasm._fr_speech_audio(this.handle, 0, 0, facerig.scratch, rate);
    if (sizing !== 0 && sizing !== 2) facerig.check(sizing);
    facerig.refreshViews();
    const count = facerig.u32[facerig.scratch >> 2], sampleRate = facerig.i32[rate >> 2];
    if (count === 0) return { samples: new Float32Array(0), sampleRate };
    const pointer = wasm._malloc(count * 4);
    try {
      facerig.check(wasm._fr_speech_audio(this.handle, pointer, count, 0, 0));
      facerig.refreshViews();
      return { samples: facerig.f32.slice(pointer >> 2, (pointer >> 2) + count), sampleRate };
    } finally {
      wasm._free(pointer);
    }
  }

  release() {
    if (this.handle) this.facerig.wasm._fr_speech_release(this.handle);
    this.handle = 0;
  }
}

const STREAM_READ_CAPACITY = 64;  // phonemes taken per fr_audio_stream_read

/**
 * An audio stream (fr_audio_stream): push mono chunks as they arrive, read the phonemes made final so
 * far (times from the stream's first sample), finish at the end of the audio. Not for a real-time
 * thread: pushing may allocate inside the module.
 */
export class AudioStream {
  constructor(facerig, handle, sampleRate) {
    this.facerig = facerig;
    this.handle = handle;
    this.sampleRate = sampleRate;
    this.chunkPointer = 0;
    this.chunkCapacity = 0;
    this.readPointer = facerig.wasm._malloc(STREAM_READ_CAPACITY * PHONEME_SIZE);
  }

  /** Mono samples in [-1, 1] (a Float32Array); returns the phonemes that became final. */
  push(samples) {
    const { facerig } = this, { wasm } = facerig;
    if (samples.length > this.chunkCapacity) {
      if (this.chunkPointer) wasm._free(this.chunkPointer);
      this.chunkCapacity = samples.length;
      this.chunkPointer = wasm._malloc(this.chunkCapacity * 4);
    }
    facerig.refreshViews();
    facerig.f32.set(samples, this.chunkPointer >> 2);
    facerig.check(wasm._fr_audio_stream_push(this.handle, this.chunkPointer, samples.length));
    return this.read();
  }

  /** The end of the audio: returns the remaining phonemes. */
  finish() {
    this.facerig.check(this.facerig.wasm._fr_audio_stream_finish(this.handle));
    return this.read();
  }

  /** The phonemes made final since the last read, [{start, duration, symbol, language, wordStart}]. */
  read() {
    const { facerig } = this, { wasm } = facerig, list = [];
    for (;;) {
      facerig.check(wasm._fr_audio_stream_read(this.handle, this.readPointer, STREAM_READ_CAPACITY, facerig.scratch));
      facerig.refreshViews();
      const written = facerig.u32[facerig.scratch >> 2];
      for (let i = 0; i < written; ++i) list.push(facerig.readPhoneme(this.readPointer + i * PHONEME_SIZE));
      if (written < STREAM_READ_CAPACITY) return list;
    }
  }

  /** Pushes a whole recording in 50 ms chunks (as it would arrive), finishes; all its phonemes. */
  pushAll(samples) {
    const chunk = Math.max(1, Math.round(0.05 * this.sampleRate));
    const phonemes = [];
    for (let at = 0; at < samples.length; at += chunk) phonemes.push(...this.push(samples.subarray(at, at + chunk)));
    phonemes.push(...this.finish());
    return phonemes;
  }

  release() {
    const { wasm } = this.facerig;
    if (!this.handle) return;
    wasm._fr_audio_stream_release(this.handle);
    if (this.chunkPointer) wasm._free(this.chunkPointer);
    wasm._free(this.readPointer);
    this.handle = 0;
  }
}

// facerig's spelling-insensitive shape-name key (runtime/src/shape_names.cpp,
// CanonicalShapeNameOf): lower case, side suffix normalised, namespace dropped.
function canonicalShapeName(name) {
  let s = name.toLowerCase();
  let side = '';
  for (const [suffix, which] of [['left', 'l'], ['right', 'r'], ['_l', 'l'], ['_r', 'r'], ['.l', 'l'], ['.r', 'r']]) {
    if (s.length > suffix.length && s.endsWith(suffix)) {
      s = s.slice(0, -suffix.length).replace(/[_.]+$/, '');
      side = which;
      break;
    }
  }
  const prefix = Math.max(s.lastIndexOf('.'), s.lastIndexOf(':'), s.lastIndexOf('|'));
  if (prefix >= 0) s = s.slice(prefix + 1);
  return side ? `${s}_${side}` : s;
}

/** A talking character (fr_character), driven by the caller's clock (the AudioContext's). */
export class Character {
  constructor(rig, handle) {
    this.rig = rig;
    this.facerig = rig.facerig;
    this.handle = handle;
    const count = rig.info.shapeCount;
    this.weightPointer = this.facerig.wasm._malloc(Math.max(1, count) * 4);
    this.weightView = null;  // over WASM memory: re-made when it grows
    this.weightBuffer = null;
    this.order = null;       // mesh target i <- rig shape order[i] (-1: none)
    this.output = new Float32Array(count);
    this.statePointer = this.facerig.wasm._malloc(STATE_SIZE);
  }

  /**
   * Gives update() the weights in a mesh's own morph-target order. `targets` is the mesh's
   * morphTargetDictionary (three.js: name -> index) or an array of names. Names match the rig's
   * exactly or in another spelling (ARKit "mouthSmileLeft", ICT "mouthSmile_L", Oculus "viseme_PP",
   * namespaces such as "blendShape1."). Returns the target names no rig shape answers.
   */
  attach(targets) {
    const { order, unmatched } = this.rig.mapTargets(targets);
    this.order = order;
    this.output = new Float32Array(order.length);
    return unmatched;
  }

  /** Says a whole line (a Speech) whose time 0 is `startTime` on the character's clock. */
  speak(speech, startTime) {
    this.facerig.check(this.facerig.wasm._fr_character_speak(this.handle, speech.handle, startTime));
  }

  /** Says timed phonemes ([{start, duration, symbol, language?, wordStart?}]) from `startTime`. */
  speakPhonemes(phonemes, startTime) {
    const speech = this.facerig.speechFromPhonemes(phonemes);
    try {
      this.speak(speech, startTime);
    } finally {
      speech.release();
    }
  }

  /** Streaming: begin a line at `startTime`, push phonemes as they arrive (times from the line's start), end it. */
  beginLine(startTime) { this.facerig.check(this.facerig.wasm._fr_character_begin_line(this.handle, startTime)); }
  pushPhoneme(phoneme) {
    this.facerig.writePhoneme(this.facerig.phoneme, phoneme);
    this.facerig.check(this.facerig.wasm._fr_character_push_phoneme(this.handle, this.facerig.phoneme));
  }
  endLine() { this.facerig.check(this.facerig.wasm._fr_character_end_line(this.handle)); }

  /** Stops speaking; the mouth relaxes over the next frames. */
  stop() { this.facerig.check(this.facerig.wasm._fr_character_stop(this.handle)); }

  /** Emotion ('joy', 'sadness', 'fear', 'anger', 'surprise', 'disgust') towards `target` in [0, 1]. */
  setEmotion(emotion, target) {
    const code = EMOTIONS[emotion];
    if (code === undefined) throw new FacerigError('FR_ERROR_INVALID_ARGUMENT', `unknown emotion '${emotion}'`);
    this.facerig.check(this.facerig.wasm._fr_character_set_emotion(this.handle, code, target));
  }

  /** Blinks and idle gaze on or off. */
  setBehaviour({ blinks = true, gaze = true } = {}) {
    this.facerig.check(this.facerig.wasm._fr_character_set_behaviour(this.handle, blinks ? 1 : 0, gaze ? 1 : 0));
  }

  /**
   * Per frame: the weights at `time` (seconds on the character's clock, e.g. AudioContext.currentTime
   * minus the line's start). Returns the same Float32Array every call, in the attached mesh's target
   * order (the rig's order if none): a JS array, so it stays valid when WASM memory grows. Allocates
   * nothing.
   */
  update(time) {
    const { facerig } = this;
    const count = this.rig.info.shapeCount;
    facerig.check(facerig.wasm._fr_character_update(this.handle, time, this.weightPointer, count));
    const buffer = facerig.wasm.HEAPU8.buffer;
    if (buffer !== this.weightBuffer) {
      this.weightBuffer = buffer;
      this.weightView = new Float32Array(buffer, this.weightPointer, count);
    }
    const weights = this.weightView, output = this.output, order = this.order;
    if (order === null) {
      output.set(weights);
    } else {
      for (let i = 0; i < order.length; ++i) output[i] = order[i] >= 0 ? weights[order[i]] : 0;
    }
    return output;
  }

  /** What the last update found: {talking, atPause, viseme, blinkLeft, blinkRight, gazeX, gazeY, phoneme}. */
  state() {
    const { facerig } = this, at = this.statePointer;
    facerig.check(facerig.wasm._fr_character_get_state(this.handle, at));
    facerig.refreshViews();
    const i = at >> 2;
    return {
      talking: facerig.i32[i] === 1, atPause: facerig.i32[i + 1] === 1, viseme: VISEMES[facerig.i32[i + 2]] ?? 'sil',
      blinkLeft: facerig.f32[i + 3], blinkRight: facerig.f32[i + 4], gazeX: facerig.f32[i + 5], gazeY: facerig.f32[i + 6],
      phoneme: facerig.readName(at + 28),
    };
  }

  release() {
    const { wasm } = this.facerig;
    if (!this.handle) return;
    wasm._fr_character_release(this.handle);
    wasm._free(this.weightPointer);
    wasm._free(this.statePointer);
    this.handle = 0;
  }
}

function dictionaryToNames(dictionary) {
  const names = [];
  for (const [name, index] of Object.entries(dictionary)) names[index] = name;
  return Array.from(names, (name) => name ?? '');
}
