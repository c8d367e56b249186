// Loads GLBs written by facerig in headless Chromium with three.js, as a web
// avatar player would, and checks what it sees (page.mjs does the rendering):
//   - every mesh has the file's morph targets, by name (extras.targetNames);
//   - jawOpen, the left eye blink (eyeBlinkLeft or eyeBlink_L) and, when the
//     rig has them, viseme_aa (opens) and viseme_PP (lips closed, near rest)
//     are there and change the pixels where the mouth
//     and the left eye are;
//   - three.js made every material of the file and decoded every texture.
// Writes LABEL-rest.png, LABEL-jawOpen.png, ... and LABEL.json (what three.js
// reported, with the bytes it asked WebGL for) into the output folder.
//
//   node check_glb.mjs --out DIR [--chromium PATH] LABEL=FILE.glb ...
//
// Exit codes: 0 every check passed, 1 a check failed, 2 usage or setup error.
// Set up with: npm ci --prefix tests/browser (and Debian's chromium).
import fs from 'node:fs/promises';
import http from 'node:http';
import path from 'node:path';
import { fileURLToPath } from 'node:url';

const here = path.dirname(fileURLToPath(import.meta.url));
const BLINK_NAMES = ['eyeBlinkLeft', 'eyeBlink_L'];

function parseArguments(argv) {
  const options = { chromium: '/usr/bin/chromium', out: null, glbs: [] };
  for (let i = 0; i < argv.length; ++i) {
    if (argv[i] === '--out') options.out = argv[++i];
    else if (argv[i] === '--chromium') options.chromium = argv[++i];
    else if (argv[i].includes('=') && !argv[i].startsWith('-')) {
      const [label, file] = [argv[i].slice(0, argv[i].indexOf('=')), argv[i].slice(argv[i].indexOf('=') + 1)];
      options.glbs.push({ label, file: path.resolve(file) });
    } else return null;
  }
  return options.out && options.glbs.length ? options : null;
}

// The JSON chunk of a .glb.
async function glbDocument(file) {
  const bytes = await fs.readFile(file);
  if (bytes.readUInt32LE(0) !== 0x46546c67) throw new Error(`${file}: not a .glb`);
  return JSON.parse(bytes.subarray(20, 20 + bytes.readUInt32LE(12)).toString('utf8'));
}

// Serves the page, three.js and the GLBs on loopback only.
function serve(glbs) {
  const page = `<!doctype html><html><head><meta charset="utf-8"><script type="importmap">
{"imports": {"three": "/three/build/three.module.js", "three/addons/": "/three/examples/jsm/"}}
</script></head><body style="margin:0"><script type="module" src="/page.mjs"></script></body></html>`;
  const types = { '.js': 'text/javascript', '.mjs': 'text/javascript', '.glb': 'model/gltf-binary' };
  const threeRoot = path.join(here, 'node_modules', 'three');
  const server = http.createServer(async (request, response) => {
    const url = decodeURIComponent(new URL(request.url, 'http://localhost').pathname);
    let file = null;
    if (url === '/' || url === '/favicon.ico') {
      response.writeHead(url === '/' ? 200 : 204, { 'Content-Type': 'text/html' });
      response.end(url === '/' ? page : undefined);
      return;
    }
    if (url === '/page.mjs') file = path.join(here, 'page.mjs');
    else if (url.startsWith('/glb/')) file = glbs[Number(url.slice(5))]?.file ?? null;
    else if (url.startsWith('/three/')) {
      const resolved = path.resolve(threeRoot, '.' + url.slice(6));
      if (resolved.startsWith(threeRoot + path.sep)) file = resolved;
    }
    try {
      if (!file) throw new Error('not served');
      const body = await fs.readFile(file);
      response.writeHead(200, { 'Content-Type': types[path.extname(file)] ?? 'application/octet-stream' });
      response.end(body);
    } catch {
      response.writeHead(404);
      response.end();
    }
  });
  return new Promise((resolve) => server.listen(0, '127.0.0.1', () => resolve(server)));
}

// The rig's morph targets as dense vec3 arrays, every vertex once.
function denseMorphBytes(document) {
  let bytes = 0;
  const seen = new Set();
  for (const primitive of document.meshes?.[0]?.primitives ?? []) {
    const position = primitive.attributes.POSITION;
    if (seen.has(position)) continue;
    seen.add(position);
    const perVertex = (primitive.targets ?? []).reduce((n, t) => n + 12 * Object.keys(t).length, 0);
    bytes += document.accessors[position].count * perVertex;
  }
  return bytes;
}

// The checks on one GLB; returns the failures (empty when all pass).
function check(label, document, report, changes) {
  const failures = [];
  const expect = (condition, message) => { if (!condition) failures.push(`${label}: ${message}`); };
  const targetNames = document.meshes?.[0]?.extras?.targetNames ?? [];
  expect(report.meshes.length > 0, 'three.js made no mesh');
  for (const mesh of report.meshes) {
    expect(JSON.stringify(mesh.dictionary) === JSON.stringify(targetNames),
           `mesh '${mesh.name}': morphTargetDictionary differs from extras.targetNames`);
  }
  expect(targetNames.includes('jawOpen'), 'no jawOpen shape');
  expect(BLINK_NAMES.some((name) => targetNames.includes(name)), `no left eye blink (${BLINK_NAMES.join(' or ')})`);

  const fileMaterials = document.materials ?? [];
  const textured = fileMaterials.filter((m) => m.pbrMetallicRoughness?.baseColorTexture !== undefined).length;
  if (fileMaterials.length) expect(report.materials.length === fileMaterials.length,
                                   `${report.materials.length} materials in three.js, ${fileMaterials.length} in the file`);
  const decoded = report.materials.filter((m) => m.texture && m.texture.width > 0).length;
  expect(decoded === textured, `${decoded} base colour textures decoded, ${textured} in the file`);
  // Morph targets on the GPU: three.js packs each geometry's targets densely
  // (RGBA float texels) into one array texture; that should cost at most
  // twice the rig's dense deltas (a vec3 per vertex and target, two with
  // normal deltas), not a copy per primitive.
  const denseBytes = denseMorphBytes(document);
  expect(report.uploaded.arrayTextureBytes <= 2 * denseBytes,
         `morph textures take ${report.uploaded.arrayTextureBytes} bytes, over twice the dense deltas (${denseBytes})`);
  expect(report.modelShareOfPicture > 0.05, `the model covers ${report.modelShareOfPicture} of the picture`);

  // Where the pixels change, in the model's screen box (y down, the viewer's
  // right is the face's left): the jaw and PP low in the middle, the left
  // blink above the mouth on the face's left.
  const jaw = changes.jawOpen;
  expect(jaw.changedShareOfBox > 0.002 && jaw.insideShare > 0.9, `jawOpen changes too little: ${JSON.stringify(jaw)}`);
  if (jaw.centroid) {
    expect(jaw.centroid[1] > 0.45 && Math.abs(jaw.centroid[0] - 0.5) < 0.15, `jawOpen changes pixels away from the mouth: ${jaw.centroid}`);
  }
  const blink = changes.blinkLeft;
  expect(blink.changedShareOfBox > 0.0003 && blink.insideShare > 0.9, `the left blink changes too little: ${JSON.stringify(blink)}`);
  if (blink.centroid && jaw.centroid) {
    expect(blink.centroid[0] > 0.5 && blink.centroid[1] < jaw.centroid[1] - 0.1,
           `the left blink changes pixels away from the left eye: ${blink.centroid}`);
  }
  // Baked visemes: "aa" opens the mouth where jawOpen does; "PP" presses
  // the lips together, so it stays near the rest face (whose lips meet or
  // nearly meet) and changes far less than "aa".
  const aa = changes.viseme_aa;
  if (aa && jaw.centroid) {
    expect(aa.changedShareOfBox > 0.002 && aa.centroid && Math.abs(aa.centroid[1] - jaw.centroid[1]) < 0.2 &&
           Math.abs(aa.centroid[0] - 0.5) < 0.15, `viseme_aa does not open the mouth: ${JSON.stringify(aa)}`);
  }
  if (changes.viseme_PP && aa) {
    const pp = changes.viseme_PP;
    expect(pp.changedShareOfBox < 0.5 * aa.changedShareOfBox,
           `viseme_PP changes as much as viseme_aa (lips not closed): ${JSON.stringify(pp)}`);
  }
  // The tongue comes out of the mouth: it changes pixels where jawOpen does.
  const tongue = changes.tongueOut;
  if (tongue && jaw.centroid) {
    expect(tongue.changedShareOfBox > 0.001 && tongue.centroid && Math.abs(tongue.centroid[0] - 0.5) < 0.15 &&
           Math.abs(tongue.centroid[1] - jaw.centroid[1]) < 0.2, `tongueOut changes nothing at the mouth: ${JSON.stringify(tongue)}`);
  }
  return failures;
}

async function runOne(browser, base, index, glb, out) {
  const document = await glbDocument(glb.file);
  const page = await browser.newPage();
  const errors = [];
  page.on('pageerror', (error) => errors.push(error.message));
  page.on('console', (message) => { if (message.type() === 'error') errors.push(message.text()); });
  await page.setViewport({ width: 512, height: 512 });
  await page.goto(base + '/', { waitUntil: 'load' });
  await page.waitForFunction('window.ready === true', { timeout: 10000 });
  const report = await page.evaluate((url) => window.load(url), `/glb/${index}`);
  const canvas = await page.$('canvas');
  const names = document.meshes?.[0]?.extras?.targetNames ?? [];
  const poses = { rest: [], jawOpen: ['jawOpen'], blinkLeft: BLINK_NAMES, viseme_aa: ['viseme_aa'], viseme_PP: ['viseme_PP'],
                  tongueOut: ['tongueOut'], viseme_TH: ['viseme_TH'] };
  for (const shape of ['viseme_aa', 'viseme_PP', 'tongueOut', 'viseme_TH']) if (!names.includes(shape)) delete poses[shape];
  const changes = {};
  for (const [pose, shapeNames] of Object.entries(poses)) {
    await page.evaluate((n) => window.pose(n), shapeNames);
    changes[pose] = await page.evaluate(() => window.changeFromRest());
    await canvas.screenshot({ path: path.join(out, `${glb.label}-${pose}.png`) });
  }
  // The mouth up close (4x, about where jawOpen changes the picture): the tongue, the open mouth's inside.
  const box = report.screenBox, jaw = changes.jawOpen.centroid;
  for (const pose of ['rest', 'jawOpen', 'tongueOut', 'viseme_TH']) {
    if (!poses[pose] || !jaw) continue;
    await page.evaluate((n) => window.pose(n), poses[pose]);
    await page.evaluate((x, y) => window.closeUp(x, y, 4), box.x0 + jaw[0] * (box.x1 - box.x0),
                        box.y0 + (jaw[1] - 0.08) * (box.y1 - box.y0));
    await canvas.screenshot({ path: path.join(out, `${glb.label}-${pose}-mouth.png`) });
  }
  await page.close();
  const failures = check(glb.label, document, report, changes);
  for (const error of errors) failures.push(`${glb.label}: the page reported: ${error}`);
  report.denseMorphBytes = denseMorphBytes(document);
  await fs.writeFile(path.join(out, `${glb.label}.json`), JSON.stringify({ file: glb.file, ...report, changes }, null, 1));
  const mb = (bytes) => (bytes / 1e6).toFixed(1);
  console.log(`${glb.label}: ${report.meshes.length} meshes, ${names.length} morph targets, ${report.materials.length} materials; ` +
              `WebGL: morph textures ${mb(report.uploaded.arrayTextureBytes)} MB (dense deltas ${mb(report.denseMorphBytes)} MB), images ${mb(report.uploaded.textureBytes)} MB, ` +
              `buffers ${mb(report.uploaded.bufferBytes)} MB; changed share of the model's box: jawOpen ${changes.jawOpen.changedShareOfBox.toFixed(4)}, ` +
              `blink ${changes.blinkLeft.changedShareOfBox.toFixed(4)}` +
              (changes.viseme_aa ? `, viseme_aa ${changes.viseme_aa.changedShareOfBox.toFixed(4)}` : ', no viseme_aa') +
              (changes.viseme_PP ? `, viseme_PP ${changes.viseme_PP.changedShareOfBox.toFixed(4)}` : ', no viseme_PP') +
              (changes.tongueOut ? `, tongueOut ${changes.tongueOut.changedShareOfBox.toFixed(4)}` : ', no tongueOut'));
  return failures;
}

async function main(argv) {
  const options = parseArguments(argv);
  if (!options) {
    console.error('usage: node check_glb.mjs --out DIR [--chromium PATH] LABEL=FILE.glb ...');
    return 2;
  }
  let puppeteer;
  try {
    puppeteer = (await import('puppeteer-core')).default;
    await fs.access(path.join(here, 'node_modules', 'three', 'build', 'three.module.js'));
    await fs.access(options.chromium);
  } catch (error) {
    console.error(`not set up (${error.message}): run npm ci --prefix tests/browser and install Debian's chromium ` +
                  '(scripts/install-deps.sh)');
    return 2;
  }
  await fs.mkdir(options.out, { recursive: true });
  const server = await serve(options.glbs);
  const browser = await puppeteer.launch({
    executablePath: options.chromium,
    headless: true,
    // The sandbox needs user namespaces and /dev/shm that containers often
    // lack; no GPU here, so WebGL runs on SwiftShader.
    args: ['--no-sandbox', '--disable-dev-shm-usage', '--use-angle=swiftshader', '--enable-unsafe-swiftshader',
           '--mute-audio'],
  });
  const failures = [];
  try {
    const base = `http://127.0.0.1:${server.address().port}`;
    for (let i = 0; i < options.glbs.length; ++i) {
      failures.push(...await runOne(browser, base, i, options.glbs[i], options.out));
    }
  } finally {
    await browser.close();
    server.close();
  }
  for (const failure of failures) console.error(failure);
  console.log(`screenshots and reports in ${path.resolve(options.out)}`);
  return failures.length ? 1 : 0;
}

process.exitCode = await main(process.argv.slice(2)).catch((error) => {
  console.error(error.stack ?? String(error));
  return 1;
});
