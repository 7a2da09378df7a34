#pragma once

#include <functional>
#include <optional>
#include <string>

namespace omnishadow::cli {

// Looks an environment variable up: std::getenv in the product, a map in tests.
using Environment = std::function<std::optional<std::string>(const std::string& name)>;
Environment processEnvironment();

}  // namespace omnishadow::cli
