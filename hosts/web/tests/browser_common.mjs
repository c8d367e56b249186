// Shared by the browser tests: arguments, checks, the HTTP server, headless
// Chromium (software GL: SwiftShader), the demo page and its console.
import puppeteer from 'puppeteer-core';
import { mkdirSync } from 'node:fs';
import { serve } from './serve.mjs';

/** --name value pairs of the command line. */
export function parseArgs(argv = process.argv.slice(2)) {
  const args = {};
  for (let i = 0; i < argv.length; ++i) if (argv[i].startsWith('--')) args[argv[i].slice(2)] = argv[i + 1];
  return args;
}

let failures = 0;
export function check(condition, what) {
  console.log(`${condition ? 'ok  ' : 'FAIL'} ${what}`);
  if (!condition) failures += 1;
  return condition;
}

/** Prints the summary and exits 1 if any check failed. */
export function finish(began) {
  console.log(`${failures ? `${failures} check(s) failed` : 'all checks passed'} in ${((Date.now() - began) / 1000).toFixed(1)} s`);
  process.exit(failures ? 1 : 0);
}

export const median = (values) => {
  const sorted = [...values].sort((a, b) => a - b);
  return sorted.length ? sorted[sorted.length >> 1] : NaN;
};
export const quantile = (values, q) => {
  const sorted = [...values].sort((a, b) => a - b);
  return sorted.length ? sorted[Math.min(sorted.length - 1, Math.floor(q * sorted.length))] : NaN;
};
export const sleep = (ms) => new Promise((resolve) => setTimeout(resolve, ms));

/**
 * The server, Chromium and a helper to open the demo page: {server, browser, open(query) -> page}.
 * Each page's console errors and uncaught exceptions are collected in page.errors.
 */
export async function startBrowser(args, extraFlags = []) {
  mkdirSync(args.out, { recursive: true });
  const server = await serve();
  const browser = await puppeteer.launch({
    executablePath: args.chromium, headless: true,
    args: ['--no-sandbox', '--autoplay-policy=no-user-gesture-required', '--use-gl=angle', '--use-angle=swiftshader',
           '--enable-unsafe-swiftshader', '--window-size=640,640', ...extraFlags],
  });
  const base = `http://127.0.0.1:${server.address().port}/hosts/web/demo/index.html`;
  async function open(query = '', viewport = { width: 640, height: 640 }) {
    const page = await browser.newPage();
    page.errors = [];
    page.on('console', (m) => { if (m.type() === 'error') page.errors.push(m.text()); });
    page.on('pageerror', (e) => page.errors.push(`uncaught: ${e.message}`));
    await page.setViewport(viewport);
    await page.bringToFront();  // a hidden tab gets no animation frames
    await page.goto(`${base}${query}`);
    await page.waitForFunction('window.facerigDemo && window.facerigDemo.ready', { timeout: 60000 });
    return page;
  }
  async function close() {
    await browser.close();
    server.close();
  }
  return { server, browser, open, close };
}

/** The visible message of the page ('' when hidden or empty). */
export function visibleMessage(page) {
  return page.evaluate(() => {
    const m = document.getElementById('message');
    return getComputedStyle(m).display === 'none' ? '' : m.textContent;
  });
}

/** Opens a file through one of the page's file inputs and waits until the page has dealt with it. */
export async function openFile(page, inputId, path) {
  const before = await page.evaluate('window.facerigDemo.actions ?? 0');
  const input = await page.$(`#${inputId}`);
  await input.uploadFile(path);
  await page.waitForFunction(`(window.facerigDemo.actions ?? 0) > ${before}`, { timeout: 60000 });
}

/** Frames of the current line until `seconds` of it have passed (line time, heard clock). */
export async function framesUntil(page, seconds) {
  await page.waitForFunction(`window.facerigDemo.frames.length > 0 && window.facerigDemo.frames.at(-1).t >= ${seconds}`,
                             { timeout: 60000 + 2000 * seconds, polling: 100 });
  return page.evaluate('window.facerigDemo.frames.slice()');
}

/**
 * Lips closed on every /p b m/ of `phonemes` and open on vowels, from the page's frames: the smallest
 * aperture from 60 ms before each bilabial (a stop closes before its release) to its end.
 */
export function bilabialClosures(frames, phonemes) {
  const widest = Math.max(...frames.map((f) => f.aperture));
  const bilabials = phonemes.filter((p) => /^[pbm]/.test(p.symbol));
  const closed = bilabials.map((p) => {
    const inside = frames.filter((f) => f.t >= p.start - 0.06 && f.t <= p.start + p.duration);
    return inside.length ? Math.min(...inside.map((f) => f.aperture)) : Infinity;
  });
  return { widest, bilabials, closed, allClosed: bilabials.length > 0 && closed.every((c) => c < 0.1 * widest) };
}
