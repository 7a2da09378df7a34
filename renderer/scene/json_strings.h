// Internal to the scene library: the string tokens of JSON text, found without parsing it.
#pragma once

#include <cstddef>
#include <string_view>

namespace omnishadow::gltf_detail {

// Calls `visit(open, close)` with the offsets of the quotes around each string in `json`, in
// order, as a JSON lexer would see them where the text is JSON. Stops at a string left open.
// Found with memchr, not byte by byte: the strings are most of a file with data: URIs.
template <typename Visit>
void forEachJsonString(std::string_view json, Visit&& visit) {
  for (std::size_t open = json.find('"'); open != std::string_view::npos;
       open = json.find('"', open + 1)) {
    // A quote after an odd number of backslashes is escaped.
    std::size_t close = json.find('"', open + 1);
    while (close != std::string_view::npos) {
      std::size_t backslashes = 0;
      while (json[close - 1 - backslashes] == '\\') ++backslashes;
      if (backslashes % 2 == 0) break;
      close = json.find('"', close + 1);
    }
    if (close == std::string_view::npos) return;
    visit(open, close);
    open = close;
  }
}

// A byte that JSON string content may hold as it is and that stands for itself: no quote,
// escape, control or non-ASCII byte. A run of them is valid string content in any position.
inline bool plainStringByte(char c) {
  const auto byte = static_cast<unsigned char>(c);
  return byte >= 0x20 && byte < 0x80 && c != '"' && c != '\\';
}

}  // namespace omnishadow::gltf_detail
