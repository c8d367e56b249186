// The demo page in headless Chromium (ctest, labels web and browser):
//   node browser_test.mjs --chromium /usr/bin/chromium --out DIR --head default_head.glb
//        --python python3 --library-dir build/lib
// Speaks a fixed track, espeak-ng lines in en-us, es and de, and samples the
// mouth each animation frame from the head mesh's own morph influences: closed
// on every p/b/m, open on vowels; the mouth against the sound from the page's
// own clocks; the page's weights against the native runtime's (a file the
// Python package over libfacerig writes); the page's espeak-ng symbols against
// native espeak-ng's; the espeak-ng bytes fetched for one language; heads with
// ARKit or Oculus names only; bad input (a truncated GLB, a file that is not a
// GLB, a GLB without face shapes, an unknown voice): a visible message and no
// uncaught exception. Screenshot: DIR/web_demo.png.
import { execFileSync } from 'node:child_process';
import { readFileSync, writeFileSync } from 'node:fs';
import { fileURLToPath } from 'node:url';
import { bilabialClosures, check, finish, framesUntil, median, openFile, parseArgs, sleep, startBrowser,
         visibleMessage } from './browser_common.mjs';
import { writeTestHeads } from './glb_variants.mjs';

const began = Date.now();
const args = parseArgs();
const here = fileURLToPath(new URL('.', import.meta.url));
const python = (command, ...rest) => execFileSync(args.python, [`${here}native_reference.py`, command, ...rest], {
  env: { ...process.env, FACERIG_LIBRARY_DIR: args['library-dir'], PYTHONPATH: `${here}../../python` } });

// "a pa ba ma" (hosts/c/tests/consumer.c's line).
const TRACK = {
  format: 'facerig-phoneme-track', version: 1, language: 'en-us',
  phonemes: [{ start: 0.00, duration: 0.10, symbol: '_:' }, { start: 0.10, duration: 0.12, symbol: 'a#' },
             { start: 0.22, duration: 0.04, symbol: 'p' }, { start: 0.26, duration: 0.12, symbol: 'A:' },
             { start: 0.38, duration: 0.03, symbol: 'b' }, { start: 0.41, duration: 0.12, symbol: 'A:' },
             { start: 0.53, duration: 0.05, symbol: 'm' }, { start: 0.58, duration: 0.15, symbol: 'A:' },
             { start: 0.73, duration: 0.20, symbol: '_:' }],
};
const LINES = [['Peter picked a peck of pickled peppers.', 'en-us'],
               ['Pablo bebe mucho vino en Barcelona.', 'es'],
               ['Peter und Paul backen Brot mit Butter.', 'de']];

async function speakAndCheck(page, what, start) {
  const line = await page.evaluate(start);
  const end = line.phonemes.at(-1).start + line.phonemes.at(-1).duration;
  const frames = await framesUntil(page, end + 0.2);
  const { widest, bilabials, closed, allClosed } = bilabialClosures(frames, line.phonemes);
  console.log(`${what}: ${frames.length} frames (${(frames.length / (end + 0.2)).toFixed(0)} fps), widest ${widest.toFixed(3)}, ` +
              `on ${bilabials.map((p) => p.symbol).join(' ')}: ${closed.map((c) => c.toFixed(4)).join(' ')}`);
  check(widest > 0.5, `${what}: the mouth opens on vowels (${widest.toFixed(2)} cm)`);
  check(allClosed, `${what}: closed on every p/b/m (${closed.filter((c) => c < 0.1 * widest).length} of ${bilabials.length})`);
  return { line, frames };
}

// The mouth against the sound from the page's own clocks: each frame's lip aperture, stamped with
// the line time the page took for it (the AudioContext output's timestamp moved to the frame's
// time), against the aperture the same line gives at exact line times (1 ms steps): the shift that
// fits best is how far the face runs behind the sound (> 0) or ahead of it.
async function mouthLag(page, line, frames) {
  const times = [];
  for (let t = -0.2; t <= frames.at(-1).t + 0.2; t += 0.001) times.push(t);
  const curve = await page.evaluate((phonemes, ts) => window.facerigDemo.apertureCurve(phonemes, ts), line.phonemes, times);
  const at = (t) => curve[Math.min(curve.length - 1, Math.max(0, Math.round((t + 0.2) * 1000)))];
  const shown = frames.filter((f) => f.t >= 0);
  let best = Infinity, lag = 0;
  for (let shift = -150; shift <= 150; ++shift) {  // frame f shows the mouth of line time f.t - shift
    const error = shown.reduce((sum, f) => sum + Math.abs(f.aperture - at(f.t - shift / 1000)), 0);
    if (error < best) { best = error; lag = shift; }
  }
  return { lag, meanError: best / shown.length };
}

async function lipsAndClock(page) {
  await speakAndCheck(page, 'track "a pa ba ma"', `window.facerigDemo.speakTrack(${JSON.stringify(TRACK)})`);
  const bytesBefore = () => pageBytes('espeak-ng.data');
  const results = [];
  for (const [text, voice] of LINES) {
    const fetchedBefore = bytesBefore();
    const result = await speakAndCheck(page, `espeak-ng ${voice} "${text}"`,
                                       `window.facerigDemo.speakText(${JSON.stringify(text)}, "${voice}")`);
    results.push({ ...result, fetched: bytesBefore() - fetchedBefore });
  }
  // The first line loaded espeak-ng with en-us only; es and de each added their dictionary.
  const [en, es, de] = results.map((r) => r.fetched);
  console.log(`espeak-ng.data fetched: en-us ${en} bytes, then es ${es}, de ${de} (the package: 24,014,553)`);
  check(en > 0 && en < 1.2e6, `espeak-ng for en-us alone fetches ${(en / 1e6).toFixed(2)} MB of its 24 MB of data`);
  check(es > 0 && es < 0.2e6 && de > 0 && de < 0.2e6, 'another language fetches only its dictionary');

  const latency = await page.evaluate('1000 * (window.facerigDemo.audio.currentTime - window.facerigDemo.audio.getOutputTimestamp().contextTime)');
  for (const [i, { line, frames }] of results.entries()) {
    const { lag, meanError } = await mouthLag(page, line, frames);
    check(Math.abs(lag) <= 20, `${LINES[i][1]}: the mouth against the sound from the page's clocks: ${lag} ms ` +
          `(mean aperture error there ${meanError.toFixed(3)} cm; the scheduler's clock runs ${latency.toFixed(0)} ms ` +
          'ahead of the heard one)');
  }

  // The page's symbols are native espeak-ng's (so they map to the same visemes).
  writeFileSync(`${args.out}/lines.json`, JSON.stringify(LINES));
  python('phonemes', `${args.out}/lines.json`, `${args.out}/native_phonemes.json`);
  const native = JSON.parse(readFileSync(`${args.out}/native_phonemes.json`));
  results.forEach(({ line }, i) => {
    const sounds = (list) => list.filter((s) => !s.startsWith('_'));
    const page = sounds(line.phonemes.map((p) => p.symbol)), reference = sounds(native[i]);
    const same = page.filter((s, k) => s === reference[k]).length;
    check(page.length === reference.length && same === page.length,
          `${LINES[i][1]}: the page's espeak-ng symbols equal native espeak-ng's (${same} of ${reference.length}: ${page.join(' ')})`);
  });
}

let pageBytes = () => 0;

async function weightsAgainstNative(page) {
  const frames = 300, fps = 60, seed = 7;
  writeFileSync(`${args.out}/track.json`, JSON.stringify(TRACK));
  python('weights', args.head, `${args.out}/track.json`, String(seed), String(frames), String(fps), `${args.out}/native_weights.json`);
  const native = JSON.parse(readFileSync(`${args.out}/native_weights.json`));
  const mine = await page.evaluate((track, times, s) => window.facerigDemo.replay(track, times, s), TRACK, native.times, seed);
  let worst = 0, compared = 0, moving = 0;
  for (const [k, name] of mine.names.entries()) {
    const column = native.names.indexOf(name);
    if (column < 0) continue;
    compared += 1;
    native.frames.forEach((row, f) => {
      worst = Math.max(worst, Math.abs(row[column] - mine.frames[f][k]));
      if (row[column] > 0.05) moving += 1;
    });
  }
  check(compared === native.names.length && moving > 100 && worst <= 1e-5,
        `weights on the page's mesh equal native libfacerig's: ${compared} shapes x ${frames} frames (5 s, blinks and ` +
        `gaze on, seed ${seed}), max difference ${worst.toExponential(1)}`);
}

// Without speech: each head blinks (eyeBlinkLeft near 1 at least once), its eyes move (eyeLook*
// influences change) and it turns (the pivot's rotation changes), each in its own way. Watched for
// at least 6 s and until every head has done all three, at most 25 s: blinks are random with gaps up
// to about 8 s (seeds 1 and 2), and a busy machine starts the watch late in the head's timeline.
async function idle(open) {
  const page = await open('?heads=2&render=off');
  await page.evaluate(() => {
    const demo = window.facerigDemo;
    demo.idle = [];
    demo.onFrame = () => demo.idle.push(demo.heads.map((head) => {
      const face = head.face(), d = face.morphTargetDictionary, w = face.morphTargetInfluences;
      return { blink: w[d.eyeBlinkLeft], look: w[d.eyeLookOutLeft] + w[d.eyeLookInLeft] + w[d.eyeLookUpLeft] + w[d.eyeLookDownLeft],
               yaw: head.pivot.rotation.y };
    }));
  });
  const range = (v) => Math.max(...v) - Math.min(...v);
  const lively = (samples, h) => {
    const of = (key) => samples.map((s) => s[h][key]);
    const degrees = (180 / Math.PI) * range(of('yaw'));
    return { blink: Math.max(...of('blink')), look: range(of('look')), degrees,
             all: Math.max(...of('blink')) > 0.8 && range(of('look')) > 0.05 && degrees > 0.1 };
  };
  const start = Date.now();
  let samples = [];
  for (;;) {
    await sleep(1000);
    samples = await page.evaluate('window.facerigDemo.idle');
    const seconds = (Date.now() - start) / 1000;
    if ((seconds >= 6 && [0, 1].every((h) => lively(samples, h).all)) || seconds >= 25) break;
  }
  const seconds = ((Date.now() - start) / 1000).toFixed(0);
  for (const h of [0, 1]) {
    const { blink, look, degrees, all } = lively(samples, h);
    check(all, `idle head ${h + 1} of 2, ${seconds} s: blinks (lid up to ${blink.toFixed(2)}), gaze moves ` +
          `(eyeLook range ${look.toFixed(2)}), the head turns (yaw range ${degrees.toFixed(2)} degrees)`);
  }
  const differ = samples.some((s) => Math.abs(s[0].yaw - s[1].yaw) > 1e-3 || Math.abs(s[0].blink - s[1].blink) > 0.1);
  check(differ && page.errors.length === 0, `the two heads move each in their own way (${samples.length} frames)`);
  await page.close();
}

// A GLB dropped on the page (a drag-and-drop event carrying the file) replaces the head.
async function drop(page, path, name) {
  const before = await page.evaluate('window.facerigDemo.actions ?? 0');
  const bytes = readFileSync(path).toString('base64');
  await page.evaluate((b64, fileName) => {
    const data = Uint8Array.from(atob(b64), (c) => c.charCodeAt(0));
    const transfer = new DataTransfer();
    transfer.items.add(new File([data], fileName, { type: 'model/gltf-binary' }));
    window.dispatchEvent(new DragEvent('drop', { dataTransfer: transfer, cancelable: true }));
  }, bytes, name);
  await page.waitForFunction(`(window.facerigDemo.actions ?? 0) > ${before}`, { timeout: 30000 });
}

async function headsAndBadInput(page, heads) {
  await drop(page, heads.arkit, 'dropped_arkit.glb');
  check((await page.evaluate('window.facerigDemo.head.name')) === 'dropped_arkit.glb', 'a GLB dropped on the page becomes the head');
  for (const [kind, names] of [['arkit', 'ARKit names only'], ['oculus', 'Oculus visemes only']]) {
    await openFile(page, 'headFile', heads[kind]);
    const head = await page.evaluate('window.facerigDemo.head');
    const note = await visibleMessage(page);  // the Oculus visemes have no blinks: said, not refused
    check(head?.name.endsWith(`${kind}_only.glb`) && (note === '' || /no blink shapes/.test(note)),
          `a head with ${names} opens (${head?.shapes} shapes)${note ? `; note: "${note}"` : ''}`);
    await speakAndCheck(page, `${names}, track "a pa ba ma"`, `window.facerigDemo.speakTrack(${JSON.stringify(TRACK)})`);
  }
  const expected = {
    truncated: /truncated|unexpected end|too short|size|length/i, notGlb: /glb|gltf|magic|format/i,
    faceless: /lacks both the ARKit mouth shapes .* and the Oculus visemes .*; its 67 blend shapes \(Key 1, Key 2/,
    shapeless: /lacks both the ARKit mouth shapes .* and the Oculus visemes .*; it has no blend shapes/,
  };
  for (const [kind, pattern] of Object.entries(expected)) {
    await openFile(page, 'headFile', heads[kind]);
    const shown = await visibleMessage(page);
    check(pattern.test(shown), `${heads[kind].split('/').pop()}: a visible message: "${shown}"`);
  }
  check((await page.evaluate('window.facerigDemo.head.name')).endsWith('oculus_only.glb'), 'the last good head stays after bad files');
  await page.evaluate(() => {
    const voice = document.getElementById('voice');
    voice.add(new Option('xx-nonexistent'));
    voice.value = 'xx-nonexistent';
  });
  const before = await page.evaluate('window.facerigDemo.actions ?? 0');
  await page.focus('#text');
  await page.keyboard.press('Enter');
  await page.waitForFunction(`(window.facerigDemo.actions ?? 0) > ${before}`, { timeout: 30000 });
  const shown = await visibleMessage(page);
  check(/unknown voice 'xx-nonexistent'/.test(shown), `unknown voice: a visible message: "${shown}"`);
}

const { server, open, close } = await startBrowser(args);
pageBytes = (suffix) => [...server.sent].filter(([path]) => path.endsWith(suffix)).reduce((n, [, b]) => n + b, 0);
try {
  const page = await open('?render=off&still');
  check(await page.evaluate('window.facerigDemo.error === null'), `page ready: ${await page.evaluate('window.facerigDemo.error')}`);
  await lipsAndClock(page);
  await weightsAgainstNative(page);
  await headsAndBadInput(page, writeTestHeads(args.head, args.out));
  await idle(open);
  check(page.errors.length === 0, `no console errors or uncaught exceptions${page.errors.length ? ': ' + page.errors.join(' | ') : ''}`);

  // The screenshot: the drawn page held at the line's widest mouth.
  const drawn = await open('');
  await drawn.evaluate('window.facerigDemo.speakText("Peter picked a peck of pickled peppers.", "en-us")');
  const frames = await framesUntil(drawn, 1.0);
  const widest = frames.reduce((a, b) => (b.aperture > a.aperture ? b : a));
  await drawn.evaluate(`window.facerigDemo.pinTime = ${widest.t}`);
  await sleep(1000);
  await drawn.screenshot({ path: `${args.out}/web_demo.png` });
  check(drawn.errors.length === 0, `drawn page: no console errors${drawn.errors.length ? ': ' + drawn.errors.join(' | ') : ''}`);
} finally {
  await close();
}
finish(began);
