#include "cli/devices_command.h"

#include <CLI/CLI.hpp>
#include <cstdio>
#include <cstdlib>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "cli/text_table.h"
#include "renderer/core/errors.h"
#include "renderer/render/gpu_choice.h"
#include "renderer/render/gpu_devices.h"

namespace omnishadow::cli {
namespace {

nlohmann::ordered_json orNull(const std::string& text) {
  return text.empty() ? nlohmann::ordered_json() : nlohmann::ordered_json(text);
}

}  // namespace

void addDevicesCommand(CLI::App& app, DevicesOptions& o) {
  CLI::App* devices = app.add_subcommand(
      "devices", "List the EGL devices --gpu chooses from, with their CUDA numbers");
  devices->add_flag("--json", o.json, "One JSON object instead of a table");
}

int runDevices(const DevicesOptions& o) {
  const std::vector<GpuDevice> devices = listGpuDevices(true);
  const char* visible = std::getenv("CUDA_VISIBLE_DEVICES");
  const std::optional<std::string> cudaVisible =
      visible ? std::optional<std::string>(visible) : std::nullopt;
  // What --gpu auto does here; a CUDA_VISIBLE_DEVICES that matches no device is reported, not
  // thrown: listing is how one finds out why.
  nlohmann::ordered_json autoChoice;
  std::string autoText;
  try {
    const int chosen = chooseGpu(parseGpuRequest("auto"), devices, cudaVisible);
    autoChoice = chosen >= 0 ? nlohmann::ordered_json(chosen) : nlohmann::ordered_json();
    autoText = chosen >= 0 ? "device " + std::to_string(chosen)
                           : "the default order (hardware devices first, then software, then "
                             "the surfaceless platform)";
  } catch (const InputError& e) {
    autoChoice = {{"error", e.what()}};
    autoText = std::string("error: ") + e.what();
  }

  if (o.json) {
    nlohmann::ordered_json out;
    out["devices"] = nlohmann::ordered_json::array();
    for (const GpuDevice& d : devices)
      out["devices"].push_back(
          {{"index", d.index},
           {"vendor", orNull(d.vendor)},
           {"renderer", orNull(d.renderer)},
           {"driver", orNull(d.driver)},
           {"drmNode", orNull(d.drmNode)},
           {"renderNode", orNull(d.renderNode)},
           {"cuda", d.cuda ? nlohmann::ordered_json(*d.cuda) : nlohmann::ordered_json()},
           {"software", d.software}});
    out["cudaVisibleDevices"] =
        cudaVisible ? nlohmann::ordered_json(*cudaVisible) : nlohmann::ordered_json();
    out["auto"] = autoChoice;
    std::printf("%s\n", out.dump(2).c_str());
    return 0;
  }
  if (devices.empty()) {
    std::printf(
        "No EGL devices (no EGL_EXT_platform_device, or no device): renders use the "
        "surfaceless platform.\n");
  } else {
    TextTable table = {{"index", "vendor", "renderer", "driver", "drm node", "cuda", "kind"}};
    auto cell = [](const std::string& text) { return text.empty() ? std::string("-") : text; };
    for (const GpuDevice& d : devices)
      table.push_back({std::to_string(d.index), cell(d.vendor), cell(d.renderer), cell(d.driver),
                       cell(d.renderNode.empty() ? d.drmNode : d.drmNode + " " + d.renderNode),
                       d.cuda ? std::to_string(*d.cuda) : "-",
                       d.software ? "software" : "hardware"});
    printTable(table);
  }
  std::printf("CUDA_VISIBLE_DEVICES: %s\n--gpu auto: %s\n", visible ? visible : "(not set)",
              autoText.c_str());
  return 0;
}

}  // namespace omnishadow::cli
