#pragma once

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "renderer/scene/light.h"

namespace omnishadow {

// Reads a lights file (README, "The lights file"). Throws InputError with a one-line message
// "<file>: <json path>: <what was expected>" for any invalid content, or
// "<file>:<line>:<column>: <syntax problem>" for malformed JSON. Unknown fields are not errors:
// each is reported once in `warnings` ("<file>: lights[0].colour: unknown field, ignored").
LightSetup loadLightsFile(const std::filesystem::path& path, std::vector<std::string>& warnings);

// Same, from text already in memory; `fileLabel` is the name used in messages.
LightSetup parseLights(std::string_view text, std::string_view fileLabel,
                       std::vector<std::string>& warnings);

}  // namespace omnishadow
