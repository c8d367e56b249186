// A static HTTP server over the repository (the page reaches the built-in
// head in build/data and three.js in hosts/web/node_modules), for the tests
// and scripts/run-web.sh: node hosts/web/tests/serve.mjs [PORT [PAGE]]
// It answers single-range requests (206), which the page uses to fetch one
// language's espeak-ng data, and counts the bytes it sends per path
// (server.sent) and each answer's byte range (server.log), which the tests read.
import { createServer } from 'node:http';
import { open, stat } from 'node:fs/promises';
import { extname, join, normalize } from 'node:path';
import { fileURLToPath } from 'node:url';

const root = fileURLToPath(new URL('../../../', import.meta.url));
const types = { '.html': 'text/html', '.mjs': 'text/javascript', '.js': 'text/javascript', '.wasm': 'application/wasm',
                '.glb': 'model/gltf-binary', '.json': 'application/json', '.data': 'application/octet-stream',
                '.wav': 'audio/wav', '.png': 'image/png' };

// [start, end) of "bytes=a-b", "bytes=a-" or "bytes=-n" within `size`; null when absent or unsatisfiable.
function byteRange(header, size) {
  const m = /^bytes=(\d*)-(\d*)$/.exec(header ?? '');
  if (!m || (m[1] === '' && m[2] === '')) return null;
  const start = m[1] === '' ? Math.max(0, size - Number(m[2])) : Number(m[1]);
  const end = m[1] === '' || m[2] === '' ? size : Math.min(size, Number(m[2]) + 1);
  return start < end ? { start, end } : null;
}

async function send(request, response, path, sent, log) {
  const file = join(root, path);
  const { size } = await stat(file);
  const range = byteRange(request.headers.range, size);
  const { start, end } = range ?? { start: 0, end: size };
  const handle = await open(file);
  try {
    const body = Buffer.alloc(end - start);
    await handle.read(body, 0, body.length, start);
    const headers = { 'Content-Type': types[extname(path)] ?? 'application/octet-stream', 'Accept-Ranges': 'bytes',
                      'Cache-Control': 'no-cache' };
    if (range) headers['Content-Range'] = `bytes ${start}-${end - 1}/${size}`;
    response.writeHead(range ? 206 : 200, headers).end(body);
    sent.set(path, (sent.get(path) ?? 0) + body.length);
    log.push({ path, start, end });
  } finally {
    await handle.close();
  }
}

export function serve(port = 0, host = '127.0.0.1') {
  const sent = new Map(), log = [];
  const server = createServer(async (request, response) => {
    const path = normalize(decodeURIComponent(new URL(request.url, 'http://localhost').pathname));
    if (path.includes('..')) { response.writeHead(403).end(); return; }
    try {
      await send(request, response, path, sent, log);
    } catch {
      response.writeHead(404).end(`${path}: not found`);
    }
  });
  server.sent = sent;
  server.log = log;
  return new Promise((resolve, reject) => {
    server.once('error', reject);
    server.listen(port, host, () => resolve(server));
  });
}

// node serve.mjs [PORT [PAGE]]: serves the repository, prints the page's address.
if (process.argv[1] === fileURLToPath(import.meta.url)) {
  const port = Number(process.argv[2] ?? 8080);
  try {
    const server = await serve(port);
    console.log(`http://127.0.0.1:${server.address().port}/${process.argv[3] ?? 'hosts/web/demo/index.html'}`);
  } catch (e) {
    console.error(`serve: cannot listen on 127.0.0.1:${port}: ${e.code === 'EADDRINUSE' ? 'the port is in use (give another)' : e.message}`);
    process.exit(1);
  }
}
