// 16-bit PCM WAV files for the browser tests: read (mono or the first
// channel) and write (mono).
import { readFileSync, writeFileSync } from 'node:fs';

/** {samples: Float32Array in [-1, 1], sampleRate} of a 16-bit PCM WAV file. */
export function readWav(path) {
  const bytes = readFileSync(path);
  if (bytes.toString('latin1', 0, 4) !== 'RIFF' || bytes.toString('latin1', 8, 12) !== 'WAVE') throw new Error(`${path}: not a WAV file`);
  let at = 12, format = null;
  while (at + 8 <= bytes.length) {
    const id = bytes.toString('latin1', at, at + 4), size = bytes.readUInt32LE(at + 4);
    if (id === 'fmt ') {
      format = { tag: bytes.readUInt16LE(at + 8), channels: bytes.readUInt16LE(at + 10), rate: bytes.readUInt32LE(at + 12),
                 bits: bytes.readUInt16LE(at + 22) };
    } else if (id === 'data') {
      if (!format || format.tag !== 1 || format.bits !== 16) throw new Error(`${path}: not 16-bit PCM`);
      const count = Math.floor(size / (2 * format.channels));
      const samples = new Float32Array(count);
      for (let i = 0; i < count; ++i) samples[i] = bytes.readInt16LE(at + 8 + 2 * i * format.channels) / 32768;
      return { samples, sampleRate: format.rate };
    }
    at += 8 + size + (size & 1);
  }
  throw new Error(`${path}: no data chunk`);
}

/** Writes mono samples in [-1, 1] as a 16-bit PCM WAV file. */
export function writeWav(path, samples, sampleRate) {
  const bytes = Buffer.alloc(44 + 2 * samples.length);
  bytes.write('RIFF', 0, 'latin1');
  bytes.writeUInt32LE(36 + 2 * samples.length, 4);
  bytes.write('WAVEfmt ', 8, 'latin1');
  bytes.writeUInt32LE(16, 16);
  bytes.writeUInt16LE(1, 20);
  bytes.writeUInt16LE(1, 22);
  bytes.writeUInt32LE(sampleRate, 24);
  bytes.writeUInt32LE(2 * sampleRate, 28);
  bytes.writeUInt16LE(2, 32);
  bytes.writeUInt16LE(16, 34);
  bytes.write('data', 36, 'latin1');
  bytes.writeUInt32LE(2 * samples.length, 40);
  samples.forEach((s, i) => bytes.writeInt16LE(Math.max(-32768, Math.min(32767, Math.round(s * 32768))), 44 + 2 * i));
  writeFileSync(path, bytes);
}
