// Transcripts pasted from speech-recognition corpora carry markup that is not
// words: pocketsphinx/CMU Sphinx lines read "<s> words </s> (utterance-id)",
// with fillers such as <sil>. Spoken as words, it would be aligned with
// speech that is not there.
#pragma once

#include <string>
#include <string_view>

namespace facerig {

struct PlainTranscript {
  std::string text;             // the words (the text untouched when it had no markup)
  bool markup_removed = false;  // some markup was found and removed
};

// Removes tokens in angle brackets (<s>, </s>, <sil>, ...) and, on a line that
// had sentence markers, the utterance id in parentheses at its end.
PlainTranscript RemoveTranscriptMarkup(std::string_view text);

}  // namespace facerig
