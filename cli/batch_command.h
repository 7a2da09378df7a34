#pragma once

#include <optional>
#include <string>
#include <vector>

#include "cli/batch_worker.h"
#include "cli/common_options.h"
#include "cli/view_options.h"

namespace CLI {
class App;
}

namespace omnishadow::cli {

// Everything `omnishadow batch` accepts, as given on the command line.
struct BatchOptions {
  std::vector<std::string> inputs;
  std::string out;
  SceneInputOptions input;  // its scene is unused: the scenes are the inputs
  bool exr = false, noPng = false, aov = false;
  bool masks = false;    // --masks
  int antialiasing = 1;  // --aa
  std::string aovLayers;
  ViewOptions view;
  float exposure = 0.0f;
  std::string shading = "pbr";
  bool skipExisting = false;
  std::string shard;
  int shardCount = 0;  // --shard-count, for --shard auto
  int jobs = -1;       // -1 = number of cores
  std::string report;
  bool quiet = false;
  DeviceOptions device;       // without --stats
  BatchWorkerOptions worker;  // --job-timeout, --in-process, --gpus
};

void addBatchCommand(CLI::App& app, BatchOptions& options);

// Renders every job; returns 0 when all succeeded (or were skipped), 1 when some failed.
// Throws InputError for usage errors (bad inputs, manifest, shard).
int runBatch(const BatchOptions& options);

}  // namespace omnishadow::cli
