// Text to audio and timed phonemes in the page: espeak-ng compiled with
// emscripten (@echogarden/espeak-ng-emscripten, GPL-3), imported only when
// text is first spoken, so a page that never uses it never loads it; only
// the data of the voices used is fetched (espeak_data.mjs).
// Its phoneme events carry IPA; each is given espeak-ng's mnemonic instead
// (espeak_symbols.mjs), the symbol facerig's native espeak source gives, and
// they are read as that source reads them (runtime/espeak/src/
// espeak_phoneme_source.cpp): "(en)" switches the language of the phonemes
// after it, a word's first sound (not a pause) starts the word, the last
// phoneme runs to the end.
import { EspeakData } from './espeak_data.mjs';
import { mnemonicPhonemes, mnemonicsForEvents } from './espeak_symbols.mjs';

const zip = (a, b) => a.map((x, i) => [x, b[i]]);

const PACKAGE = new URL('../node_modules/@echogarden/espeak-ng-emscripten/', import.meta.url);

const isSwitch = (e) => e.id.startsWith('(');

// espeak-ng's events -> facerig phonemes [{start, duration, symbol, language, wordStart}];
// `mnemonics`: text_to_phonemes' output for the same text (espeak_symbols.mjs).
export function phonemesFromEvents(events, duration, voice, mnemonics) {
  const marks = events.filter((e) => e.type === 'phoneme' || e.type === 'word');
  const sounds = marks.filter((e) => e.type === 'phoneme' && !isSwitch(e));
  const names = new Map(zip(sounds, mnemonicsForEvents(sounds.map((e) => e.id), mnemonicPhonemes(mnemonics))));
  const phonemes = [];
  let language = voice, wordPending = false;
  for (const e of marks) {
    if (e.type === 'word') {
      wordPending = true;
    } else if (isSwitch(e)) {
      const close = e.id.indexOf(')');
      language = e.id.slice(1, close < 0 ? undefined : close) || voice;
    } else {
      const start = Math.max(e.audio_position / 1000, phonemes.at(-1)?.start ?? 0);
      const last = phonemes.at(-1);
      if (last) last.duration = start - last.start;
      const symbol = names.get(e);
      const pause = symbol.startsWith('_') || symbol === '||';
      phonemes.push({ start, duration: 0, symbol, language, wordStart: wordPending && !pause });
      if (!pause) wordPending = false;
    }
  }
  const last = phonemes.at(-1);
  if (last) last.duration = Math.max(0, duration - last.start);
  return phonemes;
}

// A NUL-terminated UTF-8 string in the espeak-ng module's memory.
function readString(module, pointer) {
  const end = module.HEAPU8.indexOf(0, pointer);
  return new TextDecoder().decode(module.HEAPU8.subarray(pointer, end));
}

export function createSpeaker(audio) {
  let engine = null, module = null, data = null, starting = null;
  const stats = { loadSeconds: 0 };

  async function start(voice) {
    const began = performance.now();
    const { default: createESpeak } = await import(new URL('espeak-ng.js', PACKAGE).href);
    data = new EspeakData(createESpeak, new URL('espeak-ng.data', PACKAGE).href);
    const options = await data.moduleOptions(voice);
    module = await createESpeak({ ...options, locateFile: (file) => new URL(file, PACKAGE).href });
    data.prune(module);
    engine = new module.eSpeakNGWorker();
    stats.loadSeconds = (performance.now() - began) / 1000;
  }

  // One start, however many callers wait for it; a failed start may be tried again.
  async function load(voice) {
    if (!engine) {
      starting ??= start(voice).finally(() => { starting = null; });
      await starting;
    }
    await data.ensureVoice(module, voice);
    return engine;
  }

  /** espeak-ng's rendition of `text`: {phonemes, samples (Float32Array), sampleRate}. */
  async function render(text, voice = 'en-us') {
    const worker = await load(voice);
    if (worker.set_voice(voice) !== 0) throw new Error(`unknown voice '${voice}'`);
    const sampleRate = worker.get_samplerate();
    const chunks = [], events = [];
    worker.synthesize(text, (samples, chunkEvents) => {
      if (samples) chunks.push(samples);
      events.push(...chunkEvents);
      return false;
    });
    const samples = new Float32Array(chunks.reduce((n, c) => n + c.length, 0));
    let at = 0;
    for (const chunk of chunks) for (let i = 0; i < chunk.length; ++i) samples[at++] = chunk[i] / 32768;
    const result = worker.text_to_phonemes(text, 0);
    const mnemonics = readString(module, result.ptr);
    delete module.getCache(module.VoidPtr)[result.ptr];  // the bindings keep every wrapper they made
    return { phonemes: phonemesFromEvents(events, samples.length / sampleRate, voice, mnemonics), samples, sampleRate };
  }

  return {
    render,
    stats,
    /** Starts loading espeak-ng and `voice`'s data (the page calls it when the text box is used). */
    prepare(voice) { return load(voice); },
    /** Bytes of espeak-ng data fetched so far. */
    get dataBytes() { return data?.fetched ?? 0; },
    /** The espeak-ng module's WebAssembly memory, bytes (0 before it is loaded). */
    get memoryBytes() { return module?.HEAPU8.length ?? 0; },

    /** {phonemes, play}: play() starts the audio and returns its AudioContext start time. */
    async synthesize(text, voice = 'en-us') {
      const { phonemes, samples, sampleRate } = await render(text, voice);
      const buffer = audio.createBuffer(1, Math.max(1, samples.length), sampleRate);
      buffer.copyToChannel(samples, 0);
      return {
        phonemes,
        play() {
          const source = audio.createBufferSource();
          source.buffer = buffer;
          source.connect(audio.destination);
          const when = audio.currentTime + 0.05;
          source.start(when);
          return when;
        },
      };
    },
  };
}
