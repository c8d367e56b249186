#include "facerig/runtime/ascii_case.h"
#include "facerig/runtime/shape_names.h"

#include <algorithm>
#include <cctype>
#include <optional>
#include <utility>

#include "facerig/runtime/speech/viseme.h"

namespace facerig {

const std::array<std::string_view, kArkitShapeCount> kArkitShapeNames = {
    "eyeBlinkLeft",      "eyeLookDownLeft",    "eyeLookInLeft",    "eyeLookOutLeft",     "eyeLookUpLeft",
    "eyeSquintLeft",     "eyeWideLeft",        "eyeBlinkRight",    "eyeLookDownRight",   "eyeLookInRight",
    "eyeLookOutRight",   "eyeLookUpRight",     "eyeSquintRight",   "eyeWideRight",       "jawForward",
    "jawLeft",           "jawRight",           "jawOpen",          "mouthClose",         "mouthFunnel",
    "mouthPucker",       "mouthLeft",          "mouthRight",       "mouthSmileLeft",     "mouthSmileRight",
    "mouthFrownLeft",    "mouthFrownRight",    "mouthDimpleLeft",  "mouthDimpleRight",   "mouthStretchLeft",
    "mouthStretchRight", "mouthRollLower",     "mouthRollUpper",   "mouthShrugLower",    "mouthShrugUpper",
    "mouthPressLeft",    "mouthPressRight",    "mouthLowerDownLeft", "mouthLowerDownRight", "mouthUpperUpLeft",
    "mouthUpperUpRight", "browDownLeft",       "browDownRight",    "browInnerUp",        "browOuterUpLeft",
    "browOuterUpRight",  "cheekPuff",          "cheekSquintLeft",  "cheekSquintRight",   "noseSneerLeft",
    "noseSneerRight",    "tongueOut"};

std::string IctShapeName(std::string_view arkit_name) {
  // Whole-face motions whose name ends in a side word.
  for (std::string_view motion : {"jawLeft", "jawRight", "mouthLeft", "mouthRight"}) {
    if (arkit_name == motion) return std::string(arkit_name);
  }
  for (const auto& [word, suffix] : {std::pair<std::string_view, std::string_view>{"Left", "_L"}, {"Right", "_R"}}) {
    if (arkit_name.size() > word.size() && arkit_name.ends_with(word)) {
      return std::string(arkit_name.substr(0, arkit_name.size() - word.size())) + std::string(suffix);
    }
  }
  return std::string(arkit_name);
}

CanonicalShapeName CanonicalShapeNameOf(std::string_view name) {
  std::string s = LowerAscii(name);
  CanonicalShapeName out;
  for (const auto& [suffix, side] : {std::pair<std::string_view, char>{"left", 'l'}, {"right", 'r'},
                                     {"_l", 'l'}, {"_r", 'r'}, {".l", 'l'}, {".r", 'r'}}) {
    if (s.size() > suffix.size() && std::string_view(s).substr(s.size() - suffix.size()) == suffix) {
      s.resize(s.size() - suffix.size());
      while (!s.empty() && (s.back() == '_' || s.back() == '.')) s.pop_back();
      out.side = side;
      break;
    }
  }
  if (const std::size_t prefix = s.find_last_of(".:|"); prefix != std::string::npos) s.erase(0, prefix + 1);
  out.base = std::move(s);
  return out;
}

std::vector<std::string> WithRightTwin(std::string_view name) {
  std::vector<std::string> names = {std::string(name)};
  if (name.size() > 2 && name.substr(name.size() - 2) == "_L") {
    names.push_back(std::string(name.substr(0, name.size() - 2)) + "_R");
  }
  return names;
}

std::vector<std::size_t> FindShapesByArkitName(const Rig& rig, std::string_view name) {
  if (const auto exact = rig.FindShape(name)) return {*exact};
  const CanonicalShapeName want = CanonicalShapeNameOf(name);
  std::vector<CanonicalShapeName> names;
  names.reserve(rig.shape_count());
  for (std::size_t s = 0; s < rig.shape_count(); ++s) names.push_back(CanonicalShapeNameOf(rig.shape_name(s)));
  auto find = [&](const std::string& base, char side) -> std::optional<std::size_t> {
    for (std::size_t s = 0; s < names.size(); ++s) {
      if (names[s].base == base && names[s].side == side) return s;
    }
    return std::nullopt;
  };
  if (const auto same = find(want.base, want.side)) return {*same};
  std::vector<std::size_t> found;
  if (want.side == 0) {
    // "browInnerUp" on a rig that has it per side.
    if (const auto l = find(want.base, 'l')) found.push_back(*l);
    if (const auto r = find(want.base, 'r')) found.push_back(*r);
  } else if (const auto unsided = find(want.base, 0)) {
    found.push_back(*unsided);
  }
  return found;
}

std::vector<std::size_t> FindShapesNotingMissing(const Rig& rig, const std::string& name,
                                                 std::vector<std::string>& missing) {
  std::vector<std::size_t> found = FindShapesByArkitName(rig, name);
  if (found.empty() && std::find(missing.begin(), missing.end(), name) == missing.end()) missing.push_back(name);
  return found;
}

const char* ToString(ShapeMatchKind kind) {
  switch (kind) {
    case ShapeMatchKind::kExact: return "exact";
    case ShapeMatchKind::kSpelling: return "spelling";
    case ShapeMatchKind::kBothSides: return "both-sides";
    case ShapeMatchKind::kUnsided: return "unsided";
  }
  return "unknown";
}

ShapeNameReport MatchShapeNames(const Rig& rig) {
  ShapeNameReport report;
  std::vector<bool> used(rig.shape_count(), false);
  for (std::string_view arkit : kArkitShapeNames) {
    std::vector<std::size_t> shapes = FindShapesByArkitName(rig, arkit);
    if (shapes.empty()) {
      report.missing.push_back(arkit);
      continue;
    }
    const CanonicalShapeName want = CanonicalShapeNameOf(arkit);
    const CanonicalShapeName got = CanonicalShapeNameOf(rig.shape_name(shapes.front()));
    ShapeMatchKind kind = ShapeMatchKind::kSpelling;
    if (shapes.size() > 1) {
      kind = ShapeMatchKind::kBothSides;
    } else if (rig.shape_name(shapes.front()) == arkit) {
      kind = ShapeMatchKind::kExact;
    } else if (got.side != want.side) {
      kind = ShapeMatchKind::kUnsided;
    }
    for (std::size_t s : shapes) used[s] = true;
    report.matched.push_back({arkit, std::move(shapes), kind});
  }
  for (std::size_t s = 0; s < rig.shape_count(); ++s) {
    if (used[s]) continue;
    (VisemeOfTargetName(rig.shape_name(s)) ? report.viseme_targets : report.other).push_back(s);
  }
  return report;
}

}  // namespace facerig
