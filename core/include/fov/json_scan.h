// Scans of JSON text before a parser sees it: parsers that recurse once per nesting level
// (Assimp's rapidjson reader, fovstair's line map) crash on deep nesting, so every JSON
// input is checked here first.
#pragma once

#include <cstddef>
#include <string>

namespace fov {

// Calls f(i, line) for each character of the text outside JSON strings (and their
// escapes), until f returns false.
template <class F>
void outside_json_strings(const std::string& text, F&& f) {
  int line = 1;
  bool in_string = false;
  for (size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (c == '\n') ++line;
    if (in_string) {
      if (c == '\\') ++i;
      else if (c == '"') in_string = false;
    } else if (c == '"') {
      in_string = true;
    } else if (!f(i, line)) {
      return;
    }
  }
}

// The line of the first bracket ('{' or '[') nested deeper than max_depth, or 0 if none is.
inline int json_too_deep_line(const std::string& text, int max_depth) {
  int depth = 0, found = 0;
  outside_json_strings(text, [&](size_t i, int line) {
    if (text[i] == '{' || text[i] == '[') {
      if (++depth > max_depth) return found = line, false;
    } else if (text[i] == '}' || text[i] == ']') {
      --depth;
    }
    return true;
  });
  return found;
}

}  // namespace fov
