#pragma once

#include <limits>
#include <string>
#include <vector>

namespace CLI {
class App;
}

namespace omnishadow::cli {

// Everything `omnishadow diff` accepts, as given on the command line. NaN: not given.
struct DiffCommandOptions {
  std::string a, b;  // files, or folders (both)
  std::vector<std::string> channels;
  bool perChannel = false;
  double threshold = 0.0;
  double maxAbs = std::numeric_limits<double>::quiet_NaN();
  double maxFailingFraction = std::numeric_limits<double>::quiet_NaN();
  double peak = std::numeric_limits<double>::quiet_NaN();
  double heatScale = std::numeric_limits<double>::quiet_NaN();
  std::string out;  // heat map .png, or a folder of them in folder mode
  std::string metric = "abs";
  bool json = false;
};

void addDiffCommand(CLI::App& app, DiffCommandOptions& options);

// Compares two images, or two folders of them pair by pair, prints a table (or one JSON object
// with --json; schema in README, "omnishadow diff") and writes heat maps with --out. Returns 0
// when everything is within the tolerances, 1 when not; throws InputError (exit status 2) for
// unreadable inputs, different sizes, no shared channel and usage errors.
int runDiff(const DiffCommandOptions& options);

}  // namespace omnishadow::cli
