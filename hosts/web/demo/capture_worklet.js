// The microphone's samples, off the audio thread: each render quantum's first
// channel is posted (copied) to the page with the AudioContext time of its
// first sample. AudioWorkletGlobalScope gives currentTime and registerProcessor.
class Capture extends AudioWorkletProcessor {
  process(inputs) {
    const channel = inputs[0]?.[0];
    if (channel) this.port.postMessage({ samples: channel.slice(), time: currentTime });
    return true;
  }
}
registerProcessor('facerig-capture', Capture);
