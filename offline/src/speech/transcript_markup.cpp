#include "facerig/offline/speech/transcript_markup.h"

#include <sstream>
#include <vector>

namespace facerig {
namespace {

bool IsTag(std::string_view word) { return word.size() >= 3 && word.front() == '<' && word.back() == '>'; }
bool IsSentenceMarker(std::string_view word) { return word == "<s>" || word == "</s>"; }
bool IsUtteranceId(std::string_view word) {
  return word.size() >= 3 && word.front() == '(' && word.back() == ')';
}

// One line's words without markup; `removed` set when some was dropped.
std::string PlainLine(const std::string& line, bool& removed) {
  std::vector<std::string> words;
  bool sentence_markers = false;
  std::istringstream in(line);
  for (std::string word; in >> word;) {
    sentence_markers = sentence_markers || IsSentenceMarker(word);
    words.push_back(word);
  }
  if (sentence_markers && !words.empty() && IsUtteranceId(words.back())) {
    words.pop_back();
    removed = true;
  }
  std::string plain;
  for (const std::string& word : words) {
    if (IsTag(word)) {
      removed = true;
      continue;
    }
    if (!plain.empty()) plain += ' ';
    plain += word;
  }
  return plain;
}

}  // namespace

PlainTranscript RemoveTranscriptMarkup(std::string_view text) {
  PlainTranscript result;
  std::istringstream in{std::string(text)};
  bool removed = false;
  std::string out;
  for (std::string line; std::getline(in, line);) {
    const std::string plain = PlainLine(line, removed);
    if (plain.empty()) continue;
    if (!out.empty()) out += '\n';
    out += plain;
  }
  if (!removed) {
    result.text = std::string(text);  // untouched: espeak reads its punctuation and layout as given
    return result;
  }
  result.text = out;
  result.markup_removed = true;
  return result;
}

}  // namespace facerig
