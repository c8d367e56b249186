// Frame timing for the HUD and the tests, means over the last 120 frames: the
// interval between animation frames (what the viewer gets), the characters'
// update time and the time spent issuing the draw (performance.now() is
// coarsened to 0.1 ms in a page that is not cross-origin isolated).
const WINDOW = 120;

function mean(values, count) {
  let sum = 0;
  for (let i = 0; i < count; ++i) sum += values[i];
  return count ? sum / count : 0;
}

export class FrameStats {
  constructor() {
    this.interval = new Float64Array(WINDOW);
    this.update = new Float64Array(WINDOW);
    this.draw = new Float64Array(WINDOW);
    this.count = 0;
    this.last = null;
    this.shown = 0;
  }

  /** Forgets the frames so far (the tests measure after the page has settled). */
  reset() {
    this.count = 0;
    this.last = null;
  }

  /** One frame: its rAF time, the update and draw times (ms). */
  add(now, updateMs, drawMs) {
    const i = this.count % WINDOW;
    this.interval[i] = this.last === null ? 0 : now - this.last;
    this.update[i] = updateMs;
    this.draw[i] = drawMs;
    this.last = now;
    this.count += 1;
  }

  /** True four times a second: the HUD need not be rewritten every frame. */
  due(now) {
    if (now - this.shown < 250) return false;
    this.shown = now;
    return true;
  }

  summary() {
    const n = Math.min(this.count, WINDOW);
    // The first interval after a reset is 0: not a frame.
    const frameMs = this.count > WINDOW ? mean(this.interval, n) : mean(this.interval.subarray(1), n - 1);
    return { frameMs, fps: frameMs ? 1000 / frameMs : 0, updateMs: mean(this.update, n), drawMs: mean(this.draw, n),
             slowestMs: Math.max(...this.interval.subarray(0, n)), frames: this.count };
  }

  text(heads) {
    const { frameMs, fps, updateMs, drawMs } = this.summary();
    return `${heads} head${heads === 1 ? '' : 's'}  update ${(updateMs * 1000).toFixed(0)} µs/frame` +
           (heads > 1 ? ` (${(updateMs * 1000 / heads).toFixed(1)} per head)` : '') +
           `  draw ${drawMs.toFixed(1)} ms\nframe ${frameMs.toFixed(1)} ms (${fps.toFixed(0)} fps)`;
  }
}
