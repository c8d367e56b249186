// Numbers of the demo page in headless Chromium, software GL (ctest, labels
// web and browser): frame time with 1, 10 and 50 heads drawn (--heads), time to first
// speech after Enter, the bytes espeak-ng fetches for en-us alone, and a run
// that speaks line after line while the WebAssembly memories and the JS heap
// (after a forced garbage collection; its JavaScript values from heap
// snapshots, without the code V8 compiles meanwhile) are sampled: they must
// stay flat.
//   node browser_perf_test.mjs --chromium /usr/bin/chromium --out DIR [--heads 1,10,50] [--heap-seconds 120]
// ctest runs the heap part for 15 s; docs/web.md gives a 2-minute run.
// Writes DIR/web_page_numbers.json.
import { readdirSync, readFileSync, writeFileSync } from 'node:fs';
import { gzipSync } from 'node:zlib';
import { fileURLToPath } from 'node:url';
import { check, finish, parseArgs, sleep, startBrowser } from './browser_common.mjs';

const began = Date.now();
const args = parseArgs();
const heapSeconds = Number(args['heap-seconds'] ?? 15);
const root = fileURLToPath(new URL('../../../', import.meta.url));
const numbers = {};
const LINE = 'Peter picked a peck of pickled peppers.';

// CPU seconds used so far by this browser's GPU process and page renderers (/proc, utime + stime):
// what a frame costs whatever else the machine runs.
function browserCpuSeconds(browser) {
  const profile = browser.process().spawnargs.find((a) => a.startsWith('--user-data-dir='));
  let ticks = 0;
  for (const pid of readdirSync('/proc').filter((name) => /^\d+$/.test(name))) {
    try {
      const command = readFileSync(`/proc/${pid}/cmdline`, 'utf8');
      if (!command.includes(profile) || !/--type=(gpu-process|renderer)/.test(command)) continue;
      const fields = readFileSync(`/proc/${pid}/stat`, 'utf8').split(') ')[1].split(' ');
      ticks += Number(fields[11]) + Number(fields[12]);  // utime, stime (fields 14 and 15 of stat)
    } catch {
      // the process ended meanwhile
    }
  }
  return ticks / 100;  // USER_HZ
}

async function frameTimes(open, browser) {
  numbers.frames = {};
  // A fresh browser's GPU process starts and compiles (SwiftShader) during its first page: not measured.
  const warmUp = await open('?heads=1&render=off');
  await warmUp.evaluate('window.facerigDemo.drawFrames(2)');
  await warmUp.close();
  for (const heads of (args.heads ?? '1,10,50').split(',').map(Number)) {
    // Undrawn between the measured frames, so that nothing else queues work for the GPU process.
    const page = await open(`?heads=${heads}&render=off`);
    await page.evaluate(`window.facerigDemo.speakText(${JSON.stringify(LINE)}, 'en-us')`);
    await page.evaluate('window.facerigDemo.drawFrames(1)');  // this page's first frame compiles
    const count = heads >= 50 ? 1 : heads >= 10 ? 2 : 4;
    const cpuBefore = browserCpuSeconds(browser);
    const wallMs = await page.evaluate(`window.facerigDemo.drawFrames(${count})`);
    const cpuMs = (1000 * (browserCpuSeconds(browser) - cpuBefore)) / count;
    const updateMs = await page.evaluate('window.facerigDemo.stats.updateMs');
    numbers.frames[heads] = { wallMs, cpuMs, updateMs, frames: count };
    // Reported, not judged: on 2 shared cores the GPU process (SwiftShader) gets what the load leaves.
    check(wallMs > 0, `${heads} head(s) drawn at 640x640 (${count} frames, each read back): ${wallMs.toFixed(0)} ms a frame ` +
          `here, ${cpuMs.toFixed(0)} ms of CPU in the GPU process and page; the runtime's update ` +
          `${(1000 * updateMs).toFixed(0)} µs of it for all heads`);
    await page.close();
  }
}

async function firstSpeech(open, server) {
  const logged = server.log.length;  // this page's requests only
  // Not drawn: on software GL, slow frames would delay the key press itself.
  const page = await open('?render=off');
  const times = [];
  for (const attempt of ['first (loads espeak-ng and en-us)', 'second']) {
    await page.evaluate('window.facerigDemo.firstSpeechMs = undefined');
    await page.focus('#text');
    await page.keyboard.press('Enter');
    await page.waitForFunction('window.facerigDemo.firstSpeechMs !== undefined', { timeout: 30000 });
    const ms = await page.evaluate('window.facerigDemo.firstSpeechMs');
    times.push(ms);
    check(ms > 0 && ms < 10000, `time from Enter to the first sound, ${attempt}: ${ms.toFixed(0)} ms`);
    await sleep(300);
  }
  numbers.firstSpeechMs = { cold: times[0], warm: times[1] };
  // What the page fetched for espeak-ng: its module and the byte ranges of its data.
  const espeak = 'hosts/web/node_modules/@echogarden/espeak-ng-emscripten/';
  const js = readFileSync(`${root}${espeak}espeak-ng.js`), data = readFileSync(`${root}${espeak}espeak-ng.data`);
  const ranges = server.log.slice(logged).filter((r) => r.path.endsWith('espeak-ng.data'));
  const fetched = Buffer.concat(ranges.map((r) => data.subarray(r.start, r.end)));
  numbers.espeakEnUs = { js: js.length, jsGzip: gzipSync(js, { level: 9 }).length, data: fetched.length,
                         dataGzip: gzipSync(fetched, { level: 9 }).length, requests: ranges.length, package: data.length };
  const e = numbers.espeakEnUs;
  check(e.data < 1.2e6, `espeak-ng for en-us alone: ${e.js + e.data} bytes (${e.jsGzip + e.dataGzip} gzipped): the module ` +
        `${e.js} (${e.jsGzip}) and ${e.data} (${e.dataGzip}) of its ${e.package} bytes of data in ${e.requests} range requests`);
  await page.close();
}

// The page's JavaScript values after a garbage collection (objects, arrays, strings, closures...;
// not V8's compiled code and its bookkeeping, which grow for minutes as V8 optimises the page's
// functions and the WebAssembly), bytes, from a heap snapshot.
async function heapObjects(cdp) {
  await cdp.send('HeapProfiler.collectGarbage');
  const chunks = [];
  const take = (event) => chunks.push(event.chunk);
  cdp.on('HeapProfiler.addHeapSnapshotChunk', take);
  await cdp.send('HeapProfiler.takeHeapSnapshot', { reportProgress: false });
  cdp.off('HeapProfiler.addHeapSnapshotChunk', take);
  const { snapshot: { meta }, nodes } = JSON.parse(chunks.join(''));
  const fields = meta.node_fields.length, type = meta.node_fields.indexOf('type'), size = meta.node_fields.indexOf('self_size');
  const values = new Set(['object', 'array', 'string', 'closure', 'regexp', 'number', 'concatenated string',
                          'sliced string', 'bigint', 'symbol'].map((name) => meta.node_types[0].indexOf(name)));
  let bytes = 0;
  for (let i = 0; i < nodes.length; i += fields) if (values.has(nodes[i + type])) bytes += nodes[i + size];
  return bytes;
}

// Line after line (espeak-ng in en-us and de, a track, emotions) for `seconds`; samples every few
// seconds after a forced garbage collection.
async function heapRun(open, seconds) {
  const page = await open('?render=off');
  const cdp = await page.createCDPSession();
  const samples = [];
  const sample = async () => {
    await cdp.send('HeapProfiler.collectGarbage');
    const { usedSize } = await cdp.send('Runtime.getHeapUsage');
    const wasm = await page.evaluate('[window.facerigDemo.facerig.wasm.HEAPU8.length, window.facerigDemo.speaker.memoryBytes]');
    samples.push({ t: (Date.now() - start) / 1000, js: usedSize, facerig: wasm[0], espeak: wasm[1] });
  };
  const start = Date.now();
  let objectsFirst = null;
  for (let i = 0; Date.now() - start < seconds * 1000; ++i) {
    await page.evaluate((k) => {
      const demo = window.facerigDemo;
      demo.setEmotion(['joy', 'sadness', 'anger', 'surprise'][k % 4], 0.6);
      return k % 3 === 2 ? demo.speakTrack({ format: 'facerig-phoneme-track', version: 1, language: 'en-us',
                                             phonemes: [{ start: 0, duration: 0.2, symbol: 'a#' }, { start: 0.2, duration: 0.05, symbol: 'p' },
                                                        { start: 0.25, duration: 0.3, symbol: 'A:' }] })
                         : demo.speakText(k % 3 === 0 ? 'Peter picked a peck of pickled peppers.' : 'Peter und Paul backen Brot.',
                                          k % 3 === 0 ? 'en-us' : 'de');
    }, i);
    await sleep(1500);
    if (i >= 1) await sample();  // from the second line: espeak-ng is loaded with both languages
    if (i === 1) objectsFirst = await heapObjects(cdp);
  }
  const objectsLast = await heapObjects(cdp);
  const [first, last] = [samples[0], samples.at(-1)];
  numbers.heap = { seconds, samples, objectsFirst, objectsLast };
  const mb = (b) => (b / 1048576).toFixed(2);
  console.log(samples.filter((_, k) => k % 4 === 0 || k === samples.length - 1)
    .map((s) => `${s.t.toFixed(0)} s: JS ${mb(s.js)} MB, facerig ${mb(s.facerig)} MB, espeak-ng ${mb(s.espeak)} MB`).join('\n'));
  check(samples.length >= 2 && last.facerig === first.facerig && last.espeak === first.espeak,
        `${seconds} s of speech: the WebAssembly memories stay at ${mb(last.facerig)} MB (facerig) and ${mb(last.espeak)} MB (espeak-ng)`);
  check(objectsLast <= objectsFirst + 65536,
        `${seconds} s of speech: the page's JavaScript values (a heap snapshot after garbage collection) go ${mb(objectsFirst)} -> ` +
        `${mb(objectsLast)} MB (at most +64 kB); the whole heap, with V8's compiled code, ${mb(first.js)} -> ${mb(last.js)} MB`);
  check(page.errors.length === 0, `no console errors${page.errors.length ? ': ' + page.errors.join(' | ') : ''}`);
  await page.close();
}

numbers.loadAverage = readFileSync('/proc/loadavg', 'utf8').split(' ').slice(0, 3).map(Number);
console.log(`load average ${numbers.loadAverage.join(' ')} (2 shared cores: frame times depend on it)`);
const { server, browser, open, close } = await startBrowser(args, ['--enable-precise-memory-info']);
const timed = async (what, run) => {
  const at = Date.now();
  await run();
  console.log(`(${what}: ${((Date.now() - at) / 1000).toFixed(1)} s)`);
};
try {
  await timed('frame times', () => frameTimes(open, browser));
  await timed('first speech', () => firstSpeech(open, server));
  await timed('heap run', () => heapRun(open, heapSeconds));
  writeFileSync(`${args.out}/web_page_numbers.json`, JSON.stringify(numbers, null, 1));
} finally {
  await close();
}
finish(began);
