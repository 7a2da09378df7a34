// libomnishadow_oiio.so (oiio_plugin.h): reads images through OpenImageIO for the formats that
// omnishadow does not read itself. Built as a module, loaded with dlopen, never linked.
#include <OpenImageIO/imageio.h>

#include <cstddef>
#include <string>
#include <utility>

#include "renderer/output/image_limits.h"
#include "renderer/output/image_writer.h"
#include "renderer/output/oiio_plugin.h"

namespace {

// OIIO keeps errors per object and globally; whichever is set explains the failure.
std::string oiioReason(const std::string& objectError) {
  if (!objectError.empty()) return objectError;
  std::string global = OIIO::geterror();
  return global.empty() ? "unknown OpenImageIO error" : global;
}

}  // namespace

extern "C" __attribute__((visibility("default"))) bool omnishadow_oiio_read_image(
    const char* path, omnishadow::FloatImage* image, std::string* error, int abi) {
  if (abi != omnishadow::kOiioPluginAbi) {
    *error = "the OpenImageIO plugin is from another omnishadow build";
    return false;
  }
  // Return the stored values: OIIO would otherwise premultiply colour by alpha on read.
  OIIO::ImageSpec config;
  config.attribute("oiio:UnassociatedAlpha", 1);
  auto input = OIIO::ImageInput::open(path, &config);
  if (!input) {
    *error = oiioReason("");
    return false;
  }
  const OIIO::ImageSpec& spec = input->spec();
  if (std::string problem = omnishadow::imageSizeProblem(spec.width, spec.height, spec.nchannels);
      !problem.empty()) {
    *error = std::move(problem);
    return false;
  }
  image->width = spec.width;
  image->height = spec.height;
  image->channels.assign(spec.channelnames.begin(), spec.channelnames.end());
  image->channels.resize(static_cast<std::size_t>(spec.nchannels));
  image->pixels.resize(static_cast<std::size_t>(spec.width) *
                       static_cast<std::size_t>(spec.height) *
                       static_cast<std::size_t>(spec.nchannels));
  if (!input->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, image->pixels.data())) {
    *error = oiioReason(input->geterror());
    return false;
  }
  input->close();
  return true;
}
