#pragma once

#include <optional>
#include <string_view>

namespace omnishadow::shaders {

// Source of a file from shaders/ (by file name, e.g. "lighting.frag"), embedded at build time.
std::optional<std::string_view> find(std::string_view name);

}  // namespace omnishadow::shaders
