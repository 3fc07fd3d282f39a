// Label tables: each enum the tools expose has one array of {label, value} pairs beside
// it; names, parsing and the command lines' choices all come from that array.
#pragma once

#include <cstddef>
#include <string>
#include <utility>

namespace fov {

template <class E, size_t N>
using label_table = std::pair<const char*, E>[N];

// The label of `value` ("?" when the table lacks it).
template <class E, size_t N>
const char* label_of(const label_table<E, N>& table, E value) {
  for (const auto& [label, v] : table)
    if (v == value) return label;
  return "?";
}

// The value labelled `text`; false when no label matches.
template <class E, size_t N>
bool parse_label(const label_table<E, N>& table, const std::string& text, E& out) {
  for (const auto& [label, v] : table)
    if (text == label) {
      out = v;
      return true;
    }
  return false;
}

// "a, b, c": the labels, for messages.
template <class E, size_t N>
std::string label_list(const label_table<E, N>& table) {
  std::string s;
  for (const auto& entry : table) s += (s.empty() ? "" : ", ") + std::string(entry.first);
  return s;
}

// "a, b or c": the labels as alternatives, for messages that say what a value must be.
template <class E, size_t N>
std::string label_alternatives(const label_table<E, N>& table) {
  std::string s;
  for (size_t i = 0; i < N; ++i) s += (i == 0 ? "" : i + 1 == N ? " or " : ", ") + std::string(table[i].first);
  return s;
}

}  // namespace fov
