#pragma once

#include <string>

#include "cli/common_options.h"

namespace CLI {
class App;
}

namespace omnishadow::cli {

// Everything `omnishadow info` accepts, as given on the command line.
struct InfoOptions {
  SceneInputOptions input;  // its render settings are unused
  bool json = false;
};

void addInfoCommand(CLI::App& app, InfoOptions& options);

// Loads the scene and the lights file (no GL context) and prints what a render would use: a
// readable report, or one JSON object with --json (schema in README, "omnishadow info").
// Returns the exit status; throws InputError to the caller.
int runInfo(const InfoOptions& options);

}  // namespace omnishadow::cli
