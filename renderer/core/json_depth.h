// The nesting limit for every JSON document the tool reads (scenes, lights files, manifests),
// checked by a flat scan before any parser sees the text: tinygltf's parser and nlohmann's
// dump() recurse once per level, so 100,000 nested arrays overflow the stack.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>

namespace omnishadow {

// Far more than any glTF, lights file or manifest needs (a glTF with extensions and extras nests
// about 10 deep), far less than what exhausts an 8 MiB stack even with sanitizers.
inline constexpr std::size_t kMaxJsonDepth = 128;

// The byte offset of the first '[' or '{' that opens level `maxDepth + 1`, or npos when the text
// nests no deeper. Strings are skipped (with their escapes); anything else is left to the parser.
inline std::size_t findExcessiveNesting(std::string_view text,
                                        std::size_t maxDepth = kMaxJsonDepth) {
  std::size_t depth = 0;
  bool inString = false;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (inString) {
      if (c == '\\') {
        ++i;
      } else if (c == '"') {
        inString = false;
      }
    } else if (c == '"') {
      inString = true;
    } else if (c == '[' || c == '{') {
      if (++depth > maxDepth) return i;
    } else if ((c == ']' || c == '}') && depth > 0) {
      --depth;
    }
  }
  return std::string_view::npos;
}

// "<line>:<column>: JSON nests deeper than 128 levels" for an offset from findExcessiveNesting,
// with 1-based line and byte column.
inline std::string excessiveNestingMessage(std::string_view text, std::size_t offset,
                                           std::size_t maxDepth = kMaxJsonDepth) {
  std::size_t line = 1, lineStart = 0;
  for (std::size_t i = 0; i < offset && i < text.size(); ++i) {
    if (text[i] == '\n') {
      ++line;
      lineStart = i + 1;
    }
  }
  return std::to_string(line) + ":" + std::to_string(offset - lineStart + 1) +
         ": JSON nests deeper than " + std::to_string(maxDepth) + " levels";
}

}  // namespace omnishadow
