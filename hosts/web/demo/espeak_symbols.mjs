// espeak-ng's own phoneme names for the page's phoneme events. The npm build
// of espeak-ng (@echogarden/espeak-ng-emscripten) is initialised for IPA
// events ("ˈiː", "ɾ"; pauses and soundless phonemes give ""), while facerig
// maps espeak-ng's mnemonics ("i:", "t#", "_:", ";") to visemes, as the
// native espeak source gives them. The same module's text_to_phonemes gives
// the mnemonics of the same phoneme list, without times: the two sequences
// are aligned here (dynamic programming in a band) and each event takes the
// mnemonic it lines up with.

const PAUSE_SUFFIXES = ['^_', '!!', ':', '!', '|'];
const STRESS_MARKS = /^[',%=]+|[',%=]+$/g;
const IPA_STRESS = /[ˈˌ]/;

/** A word of text_to_phonemes' output ("p_'i:_t#_3", "t__:__:", "_!,a") as phoneme names. */
export function wordPhonemes(word) {
  const names = [];
  let i = 0;
  while (i < word.length) {
    let name;
    if (word[i] === '_') {  // a pause: "_" with one of its suffixes
      name = '_' + (PAUSE_SUFFIXES.find((s) => word.startsWith(s, i + 1)) ?? '');
    } else {
      const end = word.indexOf('_', i);
      name = word.slice(i, end < 0 ? word.length : end);
    }
    names.push(name);
    i += name.length;
    if (word[i] === '_') i += 1;  // the separator after a phoneme
  }
  return names;
}

/** text_to_phonemes' output for a whole text as [{name, stressed, pause}] ("|" between clauses dropped). */
export function mnemonicPhonemes(text) {
  const list = [];
  for (const raw of text.split(/\s+/)) {
    const word = raw.replace(/^\([^)]*\)/, '');  // a language switch "(en)" before the word
    if (!word || word === '|') continue;
    for (const marked of wordPhonemes(word)) {
      const name = marked.replace(STRESS_MARKS, '');
      if (!name) continue;
      list.push({ name, stressed: /^[',]/.test(marked), pause: name[0] === '_' });
    }
  }
  return list;
}

const SKIP_SILENT_EVENT = 0.5;  // clause-end pauses have events but no names
const SKIP = 1.0;

// The cost of taking mnemonic m for event e (an IPA name, "" for a pause or a soundless phoneme).
function matchCost(e, m) {
  if (e === '') return m.pause ? 0 : 0.3;
  if (m.pause) return 10;
  return IPA_STRESS.test(e) === m.stressed ? 0 : 0.2;
}

/**
 * For each event name, the mnemonic it lines up with ("_" for a pause with none, the IPA name kept
 * when nothing matches). Banded around the sequences' diagonal: O((events + names) * band).
 */
export function mnemonicsForEvents(events, mnemonics, band = 64) {
  const n = events.length, m = mnemonics.length;
  const width = 2 * band + 1;
  const centre = (i) => Math.round((i * m) / Math.max(1, n));
  const cost = new Float64Array((n + 1) * width).fill(Infinity);
  const step = new Uint8Array((n + 1) * width);  // 1 match, 2 skip event, 3 skip mnemonic
  const at = (i, j) => i * width + (j - centre(i) + band);
  const inBand = (i, j) => j >= 0 && j <= m && Math.abs(j - centre(i)) <= band;
  for (let i = 0; i <= n; ++i) {
    for (let j = Math.max(0, centre(i) - band); j <= Math.min(m, centre(i) + band); ++j) {
      if (i === 0 && j === 0) { cost[at(0, 0)] = 0; continue; }
      let best = Infinity, how = 0;
      if (i > 0 && j > 0 && inBand(i - 1, j - 1)) {
        const c = cost[at(i - 1, j - 1)] + matchCost(events[i - 1], mnemonics[j - 1]);
        if (c < best) { best = c; how = 1; }
      }
      if (i > 0 && inBand(i - 1, j)) {
        const c = cost[at(i - 1, j)] + (events[i - 1] === '' ? SKIP_SILENT_EVENT : SKIP);
        if (c < best) { best = c; how = 2; }
      }
      if (j > 0 && inBand(i, j - 1)) {
        const c = cost[at(i, j - 1)] + SKIP;
        if (c < best) { best = c; how = 3; }
      }
      cost[at(i, j)] = best;
      step[at(i, j)] = how;
    }
  }
  const names = events.map((e) => (e === '' ? '_' : e));
  if (!inBand(n, m)) return names;  // the sequences differ too much: keep the events' names
  for (let i = n, j = m; i > 0 || j > 0;) {
    const how = step[at(i, j)];
    if (how === 1) {
      if (!(mnemonics[j - 1].pause && events[i - 1] !== '')) names[i - 1] = mnemonics[j - 1].name;
      i -= 1; j -= 1;
    } else if (how === 2) {
      i -= 1;
    } else {
      j -= 1;
    }
  }
  return names;
}
