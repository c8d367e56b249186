// Recorded audio in the demo page, headless Chromium (ctest, labels web and browser):
//   node browser_audio_test.mjs --chromium /usr/bin/chromium --out DIR --facerig build/bin/facerig
//        --recordings /usr/share/pocketsphinx/test/data/librivox
// Each librivox recording of Debian's pocketsphinx-testdata is opened in the
// page with its transcript (the audio file input, mode "aligned") and aligned
// there; its phonemes must be native `facerig align`'s (run here on the same
// files), their starts within 20 ms (median over all boundaries). A recording
// with pauses of 160, 250 and 400 ms cut into its speech is opened alone
// (mode "rough") and, in a second browser, heard through the microphone
// (Chromium's fake capture device playing the file): the mouth is closed
// over every pause.
import { execFileSync } from 'node:child_process';
import { copyFileSync, readFileSync } from 'node:fs';
import { check, finish, framesUntil, median, openFile, parseArgs, quantile, sleep, startBrowser,
         visibleMessage } from './browser_common.mjs';
import { readWav, writeWav } from './wav.mjs';

const began = Date.now();
const args = parseArgs();

/** [{wav, text}] of the librivox folder's transcription file ("<s> words </s> (id)"). */
function recordings(folder) {
  return readFileSync(`${folder}/transcription`, 'utf8').split('\n').filter(Boolean).map((line) => {
    const [, text, id] = /^<s>\s*(.*?)\s*<\/s>\s*\((.*)\)/.exec(line);
    return { wav: `${folder}/${id}.wav`, text, id };
  });
}

async function alignedAgainstNative(page) {
  await page.select('#audioMode', 'align');
  await page.select('#voice', 'en-us');
  const errors = [];
  for (const { wav, text, id } of recordings(args.recordings)) {
    const copy = `${args.out}/${id}.wav`, track = `${args.out}/${id}.json`;
    copyFileSync(wav, copy);  // the track names its audio inside its own folder
    execFileSync(args.facerig, ['align', copy, '--text', text, '-o', track], { stdio: 'pipe' });
    const native = JSON.parse(readFileSync(track, 'utf8')).phonemes;
    await page.$eval('#text', (box, value) => { box.value = value; }, text);
    await openFile(page, 'audioFile', copy);
    const shown = await visibleMessage(page);
    const mine = await page.evaluate('window.facerigDemo.line.phonemes');
    const sounds = (list) => list.map((p) => p.symbol).filter((s) => !s.startsWith('_')).join(' ');
    const same = mine.length === native.length && sounds(mine) === sounds(native);
    const here = native.map((p, i) => 1000 * Math.abs(p.start - (mine[i]?.start ?? Infinity)));
    errors.push(...here);
    check(same && shown === '', `${id}: aligned in the page, ${mine.length} phonemes as native's ${native.length}; ` +
          `start difference median ${median(here).toFixed(1)} ms, p90 ${quantile(here, 0.9).toFixed(0)} ms${shown ? `; "${shown}"` : ''}`);
  }
  check(median(errors) <= 20 && quantile(errors, 0.9) <= 40,
        `aligned in the page against native facerig align: median ${median(errors).toFixed(1)} ms, ` +
        `p90 ${quantile(errors, 0.9).toFixed(0)} ms over ${errors.length} phoneme starts (at most 20 and 40)`);
}

// A recording opened with another recording's transcript, one that native facerig align refuses
// (exit 1: they do not seem to match): the page says so, and still speaks it.
async function mismatchSaid(page) {
  const list = recordings(args.recordings);
  for (let i = 0; i < list.length; ++i) {
    const { wav, id } = list[i], { text } = list[(i + 1) % list.length];
    const copy = `${args.out}/${id}.wav`;
    copyFileSync(wav, copy);
    try {
      execFileSync(args.facerig, ['align', copy, '--text', text, '-o', `${args.out}/mismatch.json`], { stdio: 'pipe' });
      continue;  // native takes this pair: try the next
    } catch (e) {
      if (e.status !== 1) throw e;
    }
    await page.$eval('#text', (box, value) => { box.value = value; }, text);
    await openFile(page, 'audioFile', copy);
    const shown = await visibleMessage(page);
    check(shown.includes('do not seem to match'), `${id} with another line's transcript (native refuses it): the page ` +
          `says "${shown}"`);
    return;
  }
  check(false, 'no recording with another line\'s transcript is refused by native facerig align');
}

// librivox's first recording with digital silence of 160, 250 and 400 ms cut into its speech (at
// the loudest 10 ms near 1.5, 3.5 and 5.5 s): {path, pauses: [[start, length]], seconds}.
function pausedRecording(folder) {
  const { samples, sampleRate: rate } = readWav(`${folder}/${recordings(folder)[0].id}.wav`);
  const loudest = (t) => {
    let best = -1, at = 0;
    for (let c = Math.round((t - 0.3) * rate); c < (t + 0.3) * rate; c += rate / 100) {
      let e = 0;
      for (let i = c; i < c + rate / 100; ++i) e += samples[i] ** 2;
      if (e > best) { best = e; at = c; }
    }
    return at;
  };
  const parts = [], pauses = [];
  let from = 0, length = 0;
  for (const [t, seconds] of [[1.5, 0.16], [3.5, 0.25], [5.5, 0.4]]) {
    const cut = loudest(t), gap = new Float32Array(Math.round(seconds * rate));
    parts.push(samples.subarray(from, cut), gap);
    length += cut - from;
    pauses.push([length / rate, seconds]);
    length += gap.length;
    from = cut;
  }
  parts.push(samples.subarray(from));
  const joined = new Float32Array(parts.reduce((n, p) => n + p.length, 0));
  parts.reduce((at, p) => { joined.set(p, at); return at + p.length; }, 0);
  const path = `${args.out}/paused.wav`;
  writeWav(path, joined, rate);
  return { path, pauses, seconds: joined.length / rate };
}

// Every phoneme over a pause's inside (30 ms in from each edge) is a pause or a lip closure.
const closedOver = (phonemes, [start, length], slack = 0.03) => phonemes
  .filter((p) => p.start + p.duration > start + slack && p.start < start + length - slack)
  .every((p) => /^(_|p|b|m)/.test(p.symbol));

async function roughFile(page, paused) {
  await page.select('#audioMode', 'rough');
  await openFile(page, 'audioFile', paused.path);
  const line = await page.evaluate('window.facerigDemo.line');
  const frames = await framesUntil(page, paused.pauses.at(-1)[0] + paused.pauses.at(-1)[1] + 0.2);
  const widest = Math.max(...frames.map((f) => f.aperture));
  for (const pause of paused.pauses) {
    const [start, length] = pause, centre = start + length / 2;
    const middle = frames.filter((f) => Math.abs(f.t - centre) <= 0.025).map((f) => f.aperture);
    const before = frames.filter((f) => f.t > start - 0.2 && f.t < start).map((f) => f.aperture);
    check(closedOver(line.phonemes, pause) && middle.length > 0 && Math.max(...middle) < 0.1 * widest && Math.max(...before) > 0.3 * widest,
          `rough mode, a recording alone: the mouth is closed over the ${length * 1000} ms pause at ${start.toFixed(2)} s ` +
          `(${Math.max(...middle).toFixed(3)} cm in its middle, open to ${Math.max(...before).toFixed(2)} cm before; widest ${widest.toFixed(2)})`);
  }
}

async function roughMicrophone(paused) {
  const browser = await startBrowser(args, ['--use-fake-device-for-media-stream', '--use-fake-ui-for-media-stream',
                                            `--use-file-for-fake-audio-capture=${paused.path}%noloop`]);
  try {
    const page = await browser.open('?render=off&still');
    await page.click('#mic');
    await page.waitForFunction(`window.facerigDemo.line?.live && window.facerigDemo.line.phonemes.length > 0 &&
      window.facerigDemo.line.phonemes.at(-1).start > ${paused.pauses.at(-1)[0] + paused.pauses.at(-1)[1] + 0.3}`,
                               { timeout: 30000, polling: 200 });
    await sleep(500);
    await page.click('#mic');
    const line = await page.evaluate('window.facerigDemo.line');
    const frames = await page.evaluate('window.facerigDemo.frames.slice()');
    // The fake device plays the file from when it opens, before the stream's first sample: the
    // file's place in the stream is found (one shift for all three pauses, within 1.5 s), where
    // every pause has no open mouth and speech before it opens it.
    const opens = (start) => line.phonemes.some((p) => p.start < start && p.start + p.duration > start - 0.3 && !/^(_|p|b|m)/.test(p.symbol));
    const fits = (shift) => paused.pauses.every(([start, length]) => closedOver(line.phonemes, [start + shift, length], 0.04) && opens(start + shift));
    const shifts = [];
    for (let shift = -1.5; shift <= 0.2; shift += 0.01) if (fits(shift)) shifts.push(shift);
    check(shifts.length > 0, `rough mode, the microphone: the 160, 250 and 400 ms pauses get no open mouth, speech before each ` +
          `opens it (the file found ${shifts.length ? (1000 * -median(shifts)).toFixed(0) : '?'} ms before the stream's start)`);
    const widest = Math.max(...frames.map((f) => f.aperture)), late = line.late ?? 0;
    check(widest > 0.5 && late <= 0.1 * line.phonemes.length && page.errors.length === 0,
          `the microphone's face moves (widest ${widest.toFixed(2)} cm), ${line.phonemes.length} phonemes, ${late} arrived ` +
          `after the face had passed them (at most 10 %: the face runs 0.5 s behind the voice)${page.errors.length ? '; ' + page.errors.join(' | ') : ''}`);
  } finally {
    await browser.close();
  }
}

const { open, close } = await startBrowser(args);
try {
  const page = await open('?render=off&still');
  await alignedAgainstNative(page);
  await mismatchSaid(page);
  const paused = pausedRecording(args.recordings);
  await roughFile(page, paused);
  check(page.errors.length === 0, `no console errors or uncaught exceptions${page.errors.length ? ': ' + page.errors.join(' | ') : ''}`);
  await roughMicrophone(paused);
} finally {
  await close();
}
finish(began);
