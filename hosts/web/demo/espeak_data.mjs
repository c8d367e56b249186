// One language's espeak-ng data, not all 24 MB: @echogarden/espeak-ng-emscripten
// packs every language into espeak-ng.data (emscripten's file packager) and
// fetches it whole, unless the module is given getPreloadedPackage(), which
// it calls synchronously for the package's bytes. Here the package index
// (file name, start, end) is read from the factory's own source text, only
// the byte ranges a voice needs are fetched with HTTP Range requests (the
// phoneme tables, intonations, the lang/ voice files and the language's
// dictionary: about 0.9 MB for en-us), placed at their offsets in a buffer
// that is otherwise never written, and every file not fetched is deleted
// from the module's file system once it has started, so that espeak-ng finds
// it missing rather than reading zeros. A server without Range support
// answers 200 with the whole package, which is then used as it is.
const DATA_FOLDER = '/usr/share/espeak-ng-data/';
const SHARED_FILES = ['phontab', 'phonindex', 'phondata', 'intonations'];

/** The package's files {name -> {start, end}} and size, from the factory's source; null if not found. */
export function packageIndex(factory) {
  const source = factory.toString();
  const size = /remote_package_size:(\d+)/.exec(source);
  if (!size) return null;
  const files = new Map();
  for (const m of source.matchAll(/filename:"([^"]+)",start:(\d+),end:(\d+)/g)) {
    if (m[1].startsWith(DATA_FOLDER)) files.set(m[1].slice(DATA_FOLDER.length), { start: Number(m[2]), end: Number(m[3]) });
  }
  return files.size ? { files, size: Number(size[1]) } : null;
}

// Byte ranges covering `names`, neighbours merged (the lang/ files lie together).
function rangesOf(index, names) {
  const spans = names.map((name) => index.files.get(name)).sort((a, b) => a.start - b.start);
  const ranges = [];
  for (const { start, end } of spans) {
    const last = ranges.at(-1);
    if (last && start <= last.end) last.end = Math.max(last.end, end); else ranges.push({ start, end });
  }
  return ranges;
}

/**
 * The voice files under lang/ as {file, languages: [[code, priority]], dictionary} (parsed from
 * their text: "language en-us 2", "dictionary cmn"), to find the dictionary a voice needs.
 */
function parseVoiceFiles(index, bytes, offset) {
  const voices = [];
  const decoder = new TextDecoder();
  for (const [name, { start, end }] of index.files) {
    if (!name.startsWith('lang/')) continue;
    const text = decoder.decode(bytes.subarray(start - offset, end - offset));
    const languages = [...text.matchAll(/^language\s+(\S+)(?:\s+(\d+))?/gm)].map((m) => [m[1].toLowerCase(), Number(m[2] ?? 5)]);
    const dictionary = /^dictionary\s+(\S+)/m.exec(text)?.[1];
    voices.push({ file: name, languages, dictionary: dictionary ?? languages[0]?.[0].split('-')[0] });
  }
  return voices;
}

/** The voice file for `voice` (its file name, else the language it serves first), or undefined. */
function findVoice(voices, voice) {
  const wanted = voice.toLowerCase();
  const byName = voices.find((v) => v.file.split('/').pop().toLowerCase() === wanted);
  if (byName) return byName;
  let best;
  for (const v of voices) {
    for (const [code, priority] of v.languages) {
      if (code === wanted && (!best || priority < best.priority)) best = { voice: v, priority };
    }
  }
  return best?.voice;
}

/**
 * Loads espeak-ng data for one voice at a time. `url`: espeak-ng.data's address. `fetched` counts
 * the bytes received (the page's HUD and the tests read it).
 */
export class EspeakData {
  constructor(factory, url) {
    this.index = packageIndex(factory);
    this.url = url;
    this.fetched = 0;
    this.whole = null;       // the whole package, when the server ignored a Range request
    this.present = new Set(); // files whose bytes are in the module's file system
    this.pending = new Map(); // dictionary -> its fetch under way
    this.voices = null;
  }

  async fetchRange({ start, end }) {
    const response = await fetch(this.url, { headers: { Range: `bytes=${start}-${end - 1}` } });
    if (!response.ok) throw new Error(`${this.url}: HTTP ${response.status}`);
    const bytes = new Uint8Array(await response.arrayBuffer());
    this.fetched += bytes.length;
    if (response.status === 200) {  // no Range support: this is the whole package
      this.whole = bytes;
      return null;
    }
    if (bytes.length !== end - start) throw new Error(`${this.url}: asked for ${end - start} bytes, got ${bytes.length}`);
    return bytes;
  }

  /**
   * Emscripten options that start the module with the shared tables, the voice files and the
   * dictionary of `voice` (a language such as 'en-us'); then call prune(module).
   * Throws "unknown voice" for a voice no lang/ file serves.
   */
  async moduleOptions(voice) {
    if (!this.index) return {};  // an unexpected package layout: the module fetches it whole
    const langFiles = [...this.index.files.keys()].filter((name) => name.startsWith('lang/'));
    const [langRange] = rangesOf(this.index, langFiles);
    const langBytes = await this.fetchRange(langRange);
    if (this.whole) return { getPreloadedPackage: () => this.whole.buffer };
    this.voices = parseVoiceFiles(this.index, langBytes, langRange.start);
    const dictionary = this.dictionaryOf(voice);
    const names = [...SHARED_FILES, `${dictionary}_dict`];
    const ranges = rangesOf(this.index, names);
    const parts = await Promise.all(ranges.map((range) => this.fetchRange(range)));
    if (this.whole) return { getPreloadedPackage: () => this.whole.buffer };
    const end = Math.max(langRange.end, ...ranges.map((r) => r.end));
    const sparse = new Uint8Array(end);  // only the fetched ranges are ever written
    sparse.set(langBytes, langRange.start);
    ranges.forEach((range, i) => sparse.set(parts[i], range.start));
    for (const name of [...langFiles, ...names]) this.present.add(name);
    return { getPreloadedPackage: () => sparse.buffer };
  }

  /** Deletes from the module's file system every packaged file whose bytes were not fetched. */
  prune(module) {
    if (!this.index || this.whole) return;
    for (const name of this.index.files.keys()) {
      if (!this.present.has(name)) module.FS.unlink(DATA_FOLDER + name);
    }
  }

  dictionaryOf(voice) {
    const found = findVoice(this.voices, voice);
    if (!found || !this.index.files.has(`${found.dictionary}_dict`)) throw new Error(`unknown voice '${voice}'`);
    return found.dictionary;
  }

  /** Before speaking with `voice`: fetches its dictionary into the running module if missing (once). */
  ensureVoice(module, voice) {
    if (!this.index || this.whole) return Promise.resolve();
    const name = `${this.dictionaryOf(voice)}_dict`;
    if (!this.present.has(name) && !this.pending.has(name)) {
      this.pending.set(name, this.fetchDictionary(module, name).finally(() => this.pending.delete(name)));
    }
    return this.pending.get(name) ?? Promise.resolve();
  }

  async fetchDictionary(module, name) {
    const bytes = await this.fetchRange(this.index.files.get(name));
    if (this.whole) {
      const { start, end } = this.index.files.get(name);
      module.FS.writeFile(DATA_FOLDER + name, this.whole.subarray(start, end));
    } else {
      module.FS.writeFile(DATA_FOLDER + name, bytes);
    }
    this.present.add(name);
  }
}
