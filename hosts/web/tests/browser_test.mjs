// The demo page in headless Chromium (ctest, labels web and browser):
//   node browser_test.mjs --chromium /usr/bin/chromium --out DIR
// Speaks a fixed phoneme track and an espeak-ng line, samples the mouth each
// animation frame from the mesh's own morph influences, checks that it closes
// on every p/b/m and opens on vowels, and that the console has no errors.
import puppeteer from 'puppeteer-core';
import { mkdirSync } from 'node:fs';
import { serve } from './serve.mjs';

const args = Object.fromEntries(process.argv.slice(2).reduce((pairs, a, i, all) => (a.startsWith('--') ? [...pairs, [a.slice(2), all[i + 1]]] : pairs), []));
mkdirSync(args.out, { recursive: true });
let failures = 0;
function check(condition, what) {
  console.log(`${condition ? 'ok  ' : 'FAIL'} ${what}`);
  if (!condition) failures += 1;
}

const server = await serve();
const base = `http://127.0.0.1:${server.address().port}/hosts/web/demo/index.html`;
const browser = await puppeteer.launch({
  executablePath: args.chromium, headless: true,
  args: ['--no-sandbox', '--autoplay-policy=no-user-gesture-required', '--use-gl=angle', '--use-angle=swiftshader',
         '--enable-unsafe-swiftshader', '--window-size=640,640'],
});
const errors = [];
try {
  const page = await browser.newPage();
  await page.setViewport({ width: 640, height: 640 });
  page.on('console', (m) => { if (m.type() === 'error') errors.push(m.text()); });
  page.on('pageerror', (e) => errors.push(e.message));
  await page.goto(`${base}?render=off`);
  await page.waitForFunction('window.facerigDemo && (window.facerigDemo.ready || window.facerigDemo.error)', { timeout: 60000 });
  check(await page.evaluate('window.facerigDemo.error === null'), `page ready: ${await page.evaluate('window.facerigDemo.error')}`);

  // Closed on every bilabial (from 60 ms before it: a stop closes before its release), open on vowels.
  async function speakAndCheck(what, start) {
    const line = await page.evaluate(start);
    const seconds = line.phonemes.at(-1).start + line.phonemes.at(-1).duration + 0.3;
    await new Promise((r) => setTimeout(r, seconds * 1000));
    const frames = await page.evaluate('window.facerigDemo.frames.slice()');
    const widest = Math.max(...frames.map((f) => f.aperture));
    const bilabials = line.phonemes.filter((p) => /^[pbm]/.test(p.symbol));
    const closed = bilabials.map((p) => {
      const inside = frames.filter((f) => f.t >= p.start - 0.06 && f.t <= p.start + p.duration);
      return inside.length ? Math.min(...inside.map((f) => f.aperture)) : Infinity;
    });
    const fps = frames.length / seconds;
    console.log(`${what}: ${frames.length} frames (${fps.toFixed(0)} fps), widest ${widest.toFixed(3)}, on ${bilabials.map((p) => p.symbol).join(' ')}: ${closed.map((c) => c.toFixed(4)).join(' ')}`);
    check(widest > 0.5, `${what}: the mouth opens on vowels (${widest.toFixed(2)} cm)`);
    check(bilabials.length > 0 && closed.every((c) => c < 0.1 * widest),
          `${what}: closed on every p/b/m (${closed.filter((c) => c < 0.1 * widest).length} of ${bilabials.length})`);
  }
  await speakAndCheck('track "a pa ba ma"', `window.facerigDemo.speakTrack(${JSON.stringify({
    format: 'facerig-phoneme-track', version: 1, language: 'en-us',
    phonemes: [{ start: 0.00, duration: 0.10, symbol: '_:' }, { start: 0.10, duration: 0.12, symbol: 'a#' },
               { start: 0.22, duration: 0.04, symbol: 'p' }, { start: 0.26, duration: 0.12, symbol: 'A:' },
               { start: 0.38, duration: 0.03, symbol: 'b' }, { start: 0.41, duration: 0.12, symbol: 'A:' },
               { start: 0.53, duration: 0.05, symbol: 'm' }, { start: 0.58, duration: 0.15, symbol: 'A:' },
               { start: 0.73, duration: 0.20, symbol: '_:' }] })})`);
  await speakAndCheck('espeak-ng en-us "Peter picked a peck of pickled peppers."',
                      'window.facerigDemo.speakText("Peter picked a peck of pickled peppers.", "en-us")');
  // A frame drawn mid-line for the screenshot.
  await page.evaluate('window.facerigDemo.speakText("Peter picked a peck of pickled peppers.", "en-us")');
  await new Promise((r) => setTimeout(r, 700));
  await page.evaluate('window.facerigDemo.drawOnce = true');
  await new Promise((r) => setTimeout(r, 1500));
  await page.screenshot({ path: `${args.out}/web_demo.png` });
  await page.evaluate('window.facerigDemo.speakText("nope", "xx-nonexistent").catch((e) => { window.voiceError = e.message; })');
  await page.waitForFunction('window.voiceError !== undefined', { timeout: 10000 });
  check(/unknown voice/.test(await page.evaluate('window.voiceError')), 'unknown voice: a message, not an uncaught error');
  check(errors.length === 0, `no console errors${errors.length ? ': ' + errors.join(' | ') : ''}`);
} finally {
  await browser.close();
  server.close();
}
console.log(failures ? `${failures} check(s) failed` : 'all checks passed');
process.exit(failures ? 1 : 0);
