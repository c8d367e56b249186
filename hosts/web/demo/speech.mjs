// Text to audio and timed phonemes in the page: espeak-ng compiled with
// emscripten (@echogarden/espeak-ng-emscripten, GPL-3), imported only when
// text is first spoken, so a page that never uses it never loads it.
// Phoneme events carry espeak-ng's own symbols, the ones facerig's native
// espeak source gives, so they map to the same visemes.
export function createSpeaker(audio) {
  let engine = null;
  async function load() {
    if (!engine) {
      const { default: createESpeak } = await import('../node_modules/@echogarden/espeak-ng-emscripten/espeak-ng.js');
      const module = await createESpeak({
        locateFile: (file) => new URL(`../node_modules/@echogarden/espeak-ng-emscripten/${file}`, import.meta.url).href,
      });
      engine = new module.eSpeakNGWorker();
    }
    return engine;
  }

  return {
    /** {phonemes, play}: play() starts the audio and returns its AudioContext start time. */
    async synthesize(text, voice = 'en-us') {
      const worker = await load();
      if (worker.set_voice(voice) !== 0) throw new Error(`unknown voice '${voice}'`);
      const rate = worker.get_samplerate();
      const chunks = [], events = [];
      worker.synthesize(text, (samples, chunkEvents) => {
        if (samples) chunks.push(samples);
        events.push(...chunkEvents);
        return false;
      });
      const length = chunks.reduce((n, c) => n + c.length, 0);
      const buffer = audio.createBuffer(1, Math.max(1, length), rate);
      const data = buffer.getChannelData(0);
      let at = 0;
      for (const chunk of chunks) for (let i = 0; i < chunk.length; ++i) data[at++] = chunk[i] / 32768;
      const marks = events.filter((e) => e.type === 'phoneme' && e.id);
      const duration = length / rate;
      const phonemes = marks.map((e, i) => {
        const start = e.audio_position / 1000;
        const end = i + 1 < marks.length ? marks[i + 1].audio_position / 1000 : duration;
        return { start, duration: Math.max(0, end - start), symbol: e.id, language: voice };
      });
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
