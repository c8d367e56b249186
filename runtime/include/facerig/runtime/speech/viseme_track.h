// A time-ordered track of viseme keys, each checked once when it is appended,
// so that CoarticulationJob can trust the track every frame without scanning
// it. Fixed capacity: appending and clearing allocate nothing.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "facerig/runtime/speech/viseme.h"

namespace facerig {

enum class VisemeTrackError : std::uint8_t {
  kNone,
  kInvalidKey,      // non-finite times, end < start, viseme out of range, strength outside [0,1]
  kKeysOutOfOrder,  // start or end before the previous key's
  kFull,            // more keys than the track's capacity
};

const char* ToString(VisemeTrackError error);

class VisemeTrack {
 public:
  // Reserves room for `capacity` keys (the only allocation).
  explicit VisemeTrack(std::size_t capacity = 0);
  // A track holding exactly `keys`, or the first problem found (O(keys)).
  static VisemeTrackError Make(std::span<const VisemeKey> keys, VisemeTrack& out);

  // Appends one key after checking it against the last one: O(1). Starts and
  // ends must not decrease; keys may touch or overlap. On error nothing changes.
  VisemeTrackError Append(const VisemeKey& key);
  // Appends all of `keys` or, on error, none of them: O(keys.size()).
  VisemeTrackError Append(std::span<const VisemeKey> keys);
  void Clear() { keys_.clear(); }

  std::span<const VisemeKey> keys() const { return keys_; }
  std::size_t size() const { return keys_.size(); }
  std::size_t capacity() const { return capacity_; }
  bool empty() const { return keys_.empty(); }

 private:
  std::vector<VisemeKey> keys_;  // reserved to capacity_, never grown past it
  std::size_t capacity_ = 0;
};

}  // namespace facerig
