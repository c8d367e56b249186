// The microphone's samples, off the audio thread: the first channel is
// gathered into blocks of 2048 samples (about 43 ms at 48 kHz; posting every
// 128-sample render quantum would send the page 375 messages a second) and
// each block is posted with the AudioContext time of its first sample.
// AudioWorkletGlobalScope gives currentTime, sampleRate and registerProcessor.
const BLOCK = 2048;

class Capture extends AudioWorkletProcessor {
  constructor() {
    super();
    this.block = new Float32Array(BLOCK);
    this.filled = 0;
    this.blockTime = 0;
  }

  process(inputs) {
    const channel = inputs[0]?.[0];
    if (!channel) return true;
    for (let at = 0; at < channel.length;) {
      if (this.filled === 0) this.blockTime = currentTime + at / sampleRate;
      const n = Math.min(BLOCK - this.filled, channel.length - at);
      this.block.set(channel.subarray(at, at + n), this.filled);
      this.filled += n;
      at += n;
      if (this.filled === BLOCK) {
        this.port.postMessage({ samples: this.block, time: this.blockTime }, [this.block.buffer]);
        this.block = new Float32Array(BLOCK);
        this.filled = 0;
      }
    }
    return true;
  }
}
registerProcessor('facerig-capture', Capture);
