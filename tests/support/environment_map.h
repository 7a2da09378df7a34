#pragma once

// Environment variables given as a map, for the CLI's functions that look variables up through an
// Environment (cli/shard_env.h) instead of in the process's own.

#include <functional>
#include <map>
#include <optional>
#include <string>
#include <utility>

namespace omnishadow::test_support {

using Variables = std::map<std::string, std::string>;

inline std::function<std::optional<std::string>(const std::string&)> environmentOf(
    Variables variables) {
  return [variables = std::move(variables)](const std::string& name) {
    const auto it = variables.find(name);
    return it == variables.end() ? std::nullopt : std::optional<std::string>(it->second);
  };
}

}  // namespace omnishadow::test_support
