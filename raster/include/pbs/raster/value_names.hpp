// One table of names per enum, read both ways: what option parsers, reports and file readers share, so
// that a value and its name are written down once.
#pragma once

#include <array>
#include <cstddef>
#include <optional>
#include <string_view>
#include <utility>

namespace pbs {

template <typename Enum, std::size_t N>
struct ValueNames {
  std::array<std::pair<Enum, std::string_view>, N> entries;

  // The value's name; "unknown" for a value not in the table. Names are string literals, so
  // .data() is a terminated C string.
  constexpr std::string_view name(Enum value) const {
    for (const auto& [known, text] : entries)
      if (known == value) return text;
    return "unknown";
  }

  constexpr std::optional<Enum> parse(std::string_view text) const {
    for (const auto& [value, known] : entries)
      if (known == text) return value;
    return std::nullopt;
  }
};

}  // namespace pbs
