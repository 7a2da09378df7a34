#pragma once

namespace CLI {
class App;
}

namespace omnishadow::cli {

// Everything `omnishadow devices` accepts.
struct DevicesOptions {
  bool json = false;
};

void addDevicesCommand(CLI::App& app, DevicesOptions& options);

// Lists every EGL device (index, vendor, renderer, driver, DRM nodes, CUDA number, software)
// and which one --gpu auto takes here: a table, or one JSON object with --json. Returns 0.
int runDevices(const DevicesOptions& options);

}  // namespace omnishadow::cli
