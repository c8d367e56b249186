// Names of a small enum's values (0, 1, ... in order) for its ToString and
// Parse functions.
#pragma once

#include <array>
#include <cstddef>
#include <optional>
#include <string_view>

namespace facerig {

// The value's name; "?" for a value outside the enum.
template <typename Enum, std::size_t kCount>
constexpr std::string_view EnumName(const std::array<std::string_view, kCount>& names, Enum value) {
  const auto index = static_cast<std::size_t>(value);
  return index < kCount ? names[index] : std::string_view("?");
}

// The value named `name` exactly (case-sensitive), or nullopt.
template <typename Enum, std::size_t kCount>
constexpr std::optional<Enum> EnumNamed(const std::array<std::string_view, kCount>& names, std::string_view name) {
  for (std::size_t i = 0; i < kCount; ++i) {
    if (names[i] == name) return static_cast<Enum>(i);
  }
  return std::nullopt;
}

}  // namespace facerig
