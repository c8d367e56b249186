// Audio into phonemes in the page: a recording decoded by the browser and
// aligned to its transcript (the runtime's whole-recording aligner against
// espeak-ng's rendition of the transcript), a recording alone or the
// microphone through the rough streaming mode.

// The aligner reads the recording at the reference's rate (espeak-ng's 22050 Hz).
export const ALIGN_RATE = 22050;

/** A recording's bytes (WAV, Ogg, FLAC, MP3: what the browser decodes) as mono samples at `rate`. */
export async function decodeMono(bytes, rate = ALIGN_RATE) {
  const context = new OfflineAudioContext(1, 1, rate);
  let buffer;
  try {
    buffer = await context.decodeAudioData(bytes.slice(0));
  } catch (e) {
    throw new Error(`the browser cannot decode this audio (${e.message || e.name})`);
  }
  const samples = new Float32Array(buffer.length);
  for (let c = 0; c < buffer.numberOfChannels; ++c) {
    const channel = buffer.getChannelData(c);
    for (let i = 0; i < samples.length; ++i) samples[i] += channel[i] / buffer.numberOfChannels;
  }
  return { samples, sampleRate: buffer.sampleRate };
}

/**
 * The recording aligned to `transcript`: a facerig Speech holding the transcript's phonemes timed on
 * the recording (and the recording). `speaker` is the page's espeak-ng (speech.mjs).
 */
export async function alignRecording(facerig, speaker, recording, transcript, voice) {
  const rendition = await speaker.render(transcript, voice);
  if (!rendition.phonemes.length) throw new Error('the transcript gives no speech to align');
  const reference = facerig.speechFromPhonemes(rendition.phonemes, rendition.samples, rendition.sampleRate);
  try {
    return facerig.alignRecording(reference, recording.samples, recording.sampleRate);
  } finally {
    reference.release();
  }
}

/** A recording alone through the rough streaming mode: a facerig Speech (phonemes only). */
export function roughSpeech(facerig, recording) {
  return facerig.speechFromPhonemes(facerig.roughPhonemes(recording.samples, recording.sampleRate));
}

/**
 * The microphone, live: its samples go into a rough stream in 50 ms chunks and the phonemes it makes
 * final go to `onPhonemes(list, streamStartTime)`, where streamStartTime is the AudioContext time of
 * the stream's first sample; a failure inside goes to `onError(error)`. Returns {stop()}.
 */
export async function startMicrophone(facerig, audio, onPhonemes, onError) {
  const media = await navigator.mediaDevices.getUserMedia({ audio: { echoCancellation: false, noiseSuppression: false } });
  await audio.audioWorklet.addModule(new URL('capture_worklet.js', import.meta.url));
  const source = audio.createMediaStreamSource(media);
  const capture = new AudioWorkletNode(audio, 'facerig-capture', { numberOfInputs: 1, numberOfOutputs: 0 });
  const stream = facerig.createRoughStream(audio.sampleRate);
  const chunk = new Float32Array(Math.round(0.05 * audio.sampleRate));
  let filled = 0, startTime = null;
  capture.port.onmessage = ({ data }) => {
    try {
      take(data);
    } catch (e) {
      onError(e);
    }
  };
  const take = (data) => {
    startTime ??= data.time;
    for (let at = 0; at < data.samples.length;) {
      const n = Math.min(chunk.length - filled, data.samples.length - at);
      chunk.set(data.samples.subarray(at, at + n), filled);
      filled += n;
      at += n;
      if (filled === chunk.length) {
        filled = 0;
        const phonemes = stream.push(chunk);
        if (phonemes.length) onPhonemes(phonemes, startTime);
      }
    }
  };
  source.connect(capture);
  return {
    stop() {
      source.disconnect();
      capture.port.onmessage = null;
      for (const track of media.getTracks()) track.stop();
      const rest = stream.finish();
      if (rest.length && startTime !== null) onPhonemes(rest, startTime);
      stream.release();
    },
  };
}
