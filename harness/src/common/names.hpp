// An enumeration's names in one table: the name of a value, the value of a name, and the list of
// names for messages ("json|csv|md|html").
#pragma once

#include <algorithm>
#include <array>
#include <optional>
#include <string>
#include <string_view>
#include <utility>

namespace pldamp::harness {

template <class Enum, std::size_t N>
using NameTable = std::array<std::pair<Enum, std::string_view>, N>;

template <class Enum, std::size_t N>
constexpr std::string_view name_of(const NameTable<Enum, N>& table, Enum value) {
  const auto* found = std::find_if(table.begin(), table.end(),
                                   [&](const auto& entry) { return entry.first == value; });
  return found == table.end() ? std::string_view{} : found->second;
}

template <class Enum, std::size_t N>
constexpr std::optional<Enum> value_named(const NameTable<Enum, N>& table, std::string_view name) {
  const auto* found = std::find_if(table.begin(), table.end(),
                                   [&](const auto& entry) { return entry.second == name; });
  return found == table.end() ? std::nullopt : std::optional<Enum>(found->first);
}

template <class Enum, std::size_t N>
std::string names_of(const NameTable<Enum, N>& table) {
  std::string names;
  for (const auto& [value, name] : table) {
    names += names.empty() ? "" : "|";
    names += name;
  }
  return names;
}

} // namespace pldamp::harness
