#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "cli/render_job.h"

namespace omnishadow::cli {

// Batch-wide settings: where the outputs go, and the defaults every job starts from.
struct BatchDefaults {
  std::filesystem::path out;
  std::filesystem::path lights;  // one lights file for all; empty = per scene
  bool png = true, exr = false, aov = false;
  bool masks = false;  // --masks: <name>.instances.png, <name>.semantic.png, <name>.masks.json
  RenderJob job;       // camera, size, shading, exposure, layers... (no inputs or outputs)
};

struct BatchEntry {
  std::string name;  // for logs and reports: path relative to its input, or "jobs[i] <scene>"
  RenderJob job;
};

// Expands the inputs (folders, globs, scene files, manifest .json files) into jobs, in a
// deterministic order: inputs as given, scenes of a folder or glob sorted by path, manifest jobs
// in file order. Throws InputError for unreadable inputs, bad manifests, inputs that yield no
// scene, and two jobs writing one file.
std::vector<BatchEntry> collectJobs(const std::vector<std::string>& inputs,
                                    const BatchDefaults& defaults);

// "K/N" with 0 <= K < N.
struct Shard {
  int index = 0;
  int count = 1;
};
Shard parseShard(const std::string& text);  // throws InputError

// The jobs of one shard: those whose position in the list is index modulo count.
std::vector<BatchEntry> selectShard(std::vector<BatchEntry> jobs, const Shard& shard);

}  // namespace omnishadow::cli
