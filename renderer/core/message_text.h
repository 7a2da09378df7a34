// Error messages are printed as one line of bounded length: library texts may hold several
// lines (libpng), and a message may quote an input (a 50 MB data URI, a 100,000-digit number).
#pragma once

#include <cstddef>
#include <string>
#include <string_view>

namespace omnishadow {

inline constexpr std::size_t kMaxMessageBytes = 600;

// `text` on one line: line breaks become "; ", other control characters spaces, and past
// `maxBytes` it is cut (never inside a UTF-8 sequence) with a note of how much was left out.
inline std::string oneLineMessage(std::string_view text, std::size_t maxBytes = kMaxMessageBytes) {
  std::string line;
  for (std::size_t i = 0; i < text.size() && line.size() <= maxBytes; ++i) {
    const char c = text[i];
    if (c == '\n' || c == '\r') {
      while (!line.empty() && line.back() == ' ') line.pop_back();
      if (!line.empty() && !line.ends_with(';')) line += "; ";
    } else {
      line += static_cast<unsigned char>(c) < 0x20 || c == 0x7F ? ' ' : c;
    }
  }
  while (!line.empty() && (line.back() == ' ' || line.back() == ';')) line.pop_back();
  if (line.size() > maxBytes) {
    std::size_t cut = maxBytes;
    while (cut > 0 && (static_cast<unsigned char>(line[cut]) & 0xC0) == 0x80) --cut;
    line.resize(cut);
    line += "... (message cut at " + std::to_string(maxBytes) + " bytes)";
  }
  return line;
}

}  // namespace omnishadow
