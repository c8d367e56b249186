// The characters' clock: the audio being heard, whenever the AudioContext
// runs, so that the face follows the sound rather than the scheduler (which
// runs ahead of the speakers by the output latency: 41 ms in headless
// Chromium). A page's AudioContext starts suspended until the first click or
// key; meanwhile the clock runs on the performance clock, so that blinks,
// gaze and head motion go on, and when the audio starts it carries on from
// there (an offset), never jumping back.
export class FaceClock {
  constructor(audio) {
    this.audio = audio;
    this.offset = 0;       // characters' clock minus heard AudioContext time
    this.time = 0;
    this.previous = null;  // performance.now() of the previous reading
    this.onAudio = false;
  }

  // The AudioContext time being heard at performance time `now` (ms), or null when it is not running.
  heard(now) {
    if (this.audio.state !== 'running') return null;
    const stamp = this.audio.getOutputTimestamp?.();
    if (stamp && stamp.performanceTime > 0) return stamp.contextTime + (now - stamp.performanceTime) / 1000;
    return Math.max(0, this.audio.currentTime - (this.audio.outputLatency || 0));
  }

  /** The clock at performance time `now` (ms), in seconds; call once per frame, and before audioToClock. */
  read(now) {
    const heard = this.heard(now);
    if (heard === null) {
      this.time += this.previous === null ? 0 : Math.max(0, now - this.previous) / 1000;
      this.onAudio = false;
    } else {
      if (!this.onAudio) this.offset = this.time - heard;
      this.time = heard + this.offset;
      this.onAudio = true;
    }
    this.previous = now;
    return this.time;
  }

  /** An AudioContext time (a line's audio start) on this clock. */
  audioToClock(contextTime) {
    this.read(performance.now());
    return contextTime + this.offset;
  }
}
