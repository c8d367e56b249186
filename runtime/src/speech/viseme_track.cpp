#include "facerig/runtime/speech/viseme_track.h"

#include <cmath>

namespace facerig {
namespace {

VisemeTrackError CheckKey(const VisemeKey& key, const VisemeKey* previous) {
  if (!std::isfinite(key.start.count()) || !std::isfinite(key.end.count()) || key.end < key.start) {
    return VisemeTrackError::kInvalidKey;
  }
  if (static_cast<std::size_t>(key.viseme) >= kVisemeCount) return VisemeTrackError::kInvalidKey;
  if (!(key.strength >= 0.0f && key.strength <= 1.0f)) return VisemeTrackError::kInvalidKey;
  if (previous != nullptr && (key.start < previous->start || key.end < previous->end)) {
    return VisemeTrackError::kKeysOutOfOrder;
  }
  return VisemeTrackError::kNone;
}

}  // namespace

const char* ToString(VisemeTrackError error) {
  switch (error) {
    case VisemeTrackError::kNone: return "no error";
    case VisemeTrackError::kInvalidKey:
      return "a viseme key has non-finite times, end < start, an unknown viseme or strength outside [0,1]";
    case VisemeTrackError::kKeysOutOfOrder: return "viseme keys are not sorted by start and end";
    case VisemeTrackError::kFull: return "viseme track is full";
  }
  return "unknown error";
}

VisemeTrack::VisemeTrack(std::size_t capacity) : capacity_(capacity) { keys_.reserve(capacity); }

VisemeTrackError VisemeTrack::Make(std::span<const VisemeKey> keys, VisemeTrack& out) {
  VisemeTrack track(keys.size());
  if (const VisemeTrackError error = track.Append(keys); error != VisemeTrackError::kNone) return error;
  out = std::move(track);
  return VisemeTrackError::kNone;
}

VisemeTrackError VisemeTrack::Append(const VisemeKey& key) {
  if (keys_.size() >= capacity_) return VisemeTrackError::kFull;
  const VisemeKey* previous = keys_.empty() ? nullptr : &keys_.back();
  if (const VisemeTrackError error = CheckKey(key, previous); error != VisemeTrackError::kNone) return error;
  keys_.push_back(key);
  return VisemeTrackError::kNone;
}

VisemeTrackError VisemeTrack::Append(std::span<const VisemeKey> keys) {
  if (keys.size() > capacity_ - keys_.size()) return VisemeTrackError::kFull;
  const VisemeKey* previous = keys_.empty() ? nullptr : &keys_.back();
  for (const VisemeKey& key : keys) {
    if (const VisemeTrackError error = CheckKey(key, previous); error != VisemeTrackError::kNone) return error;
    previous = &key;
  }
  keys_.insert(keys_.end(), keys.begin(), keys.end());
  return VisemeTrackError::kNone;
}

}  // namespace facerig
