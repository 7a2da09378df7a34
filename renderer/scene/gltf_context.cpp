#include "renderer/scene/gltf_context.h"

#include <cctype>
#include <utility>

namespace omnishadow::gltf_detail {

std::string at(std::string_view array, std::size_t index) {
  return std::string(array) + "[" + std::to_string(index) + "]";
}

std::string nameOrDefault(const std::string& name, std::string_view kind, std::size_t index) {
  return name.empty() ? std::string(kind) + std::to_string(index) : name;
}

std::string plural(std::size_t count, std::string_view noun) {
  const char* ending = count == 1 ? "" : noun.ends_with("sh") ? "es" : "s";
  return std::to_string(count) + " " + std::string(noun) + ending;
}

std::vector<std::string> nonEmptyLines(const std::string& text) {
  std::vector<std::string> lines;
  std::size_t start = 0;
  while (start <= text.size()) {
    std::size_t end = text.find('\n', start);
    if (end == std::string::npos) end = text.size();
    std::string line = text.substr(start, end - start);
    while (!line.empty() && std::isspace(static_cast<unsigned char>(line.back()))) line.pop_back();
    if (!line.empty()) lines.push_back(std::move(line));
    start = end + 1;
  }
  return lines;
}

}  // namespace omnishadow::gltf_detail
