#include "renderer/scene/webp_decoder.h"

#include <webp/decode.h>

#include <cstring>
#include <memory>

namespace omnishadow::gltf_detail {

namespace {

std::string statusText(VP8StatusCode status) {
  switch (status) {
    case VP8_STATUS_OUT_OF_MEMORY:
      return "out of memory";
    case VP8_STATUS_INVALID_PARAM:
      return "invalid parameters";
    case VP8_STATUS_BITSTREAM_ERROR:
      return "damaged data (a bitstream error)";
    case VP8_STATUS_UNSUPPORTED_FEATURE:
      return "a feature libwebp does not decode";
    case VP8_STATUS_SUSPENDED:
      return "decoding suspended";
    case VP8_STATUS_USER_ABORT:
      return "decoding aborted";
    case VP8_STATUS_NOT_ENOUGH_DATA:
      return "the data ends early (a truncated file)";
    default:
      return "libwebp cannot decode it";
  }
}

struct OutputDeleter {
  void operator()(WebPDecBuffer* buffer) const { WebPFreeDecBuffer(buffer); }
};

}  // namespace

bool isWebp(const unsigned char* bytes, std::size_t size) {
  return size >= 12 && std::memcmp(bytes, "RIFF", 4) == 0 && std::memcmp(bytes + 8, "WEBP", 4) == 0;
}

ImageHeader readWebpHeader(const unsigned char* bytes, std::size_t size) {
  ImageHeader header;
  WebPBitstreamFeatures features;
  const VP8StatusCode status = WebPGetFeatures(bytes, size, &features);
  if (status != VP8_STATUS_OK) {
    header.error = statusText(status);
    return header;
  }
  header.ok = true;
  header.width = static_cast<std::uint32_t>(features.width);
  header.height = static_cast<std::uint32_t>(features.height);
  header.animated = features.has_animation != 0;
  return header;
}

DecodedImage decodeWebp(const unsigned char* bytes, std::size_t size, std::uint32_t maxSide,
                        std::uint64_t maxTexels) {
  DecodedImage out;
  const ImageHeader header = readWebpHeader(bytes, size);
  if (!header.ok) {
    out.error = header.error;
    return out;
  }
  if (header.animated) {
    out.error = "an animated WebP (EXT_texture_webp takes still images)";
    return out;
  }
  if (header.width == 0 || header.height == 0 || header.width > maxSide ||
      header.height > maxSide || std::uint64_t{header.width} * header.height > maxTexels) {
    out.error =
        std::to_string(header.width) + "x" + std::to_string(header.height) + " texels is too large";
    return out;
  }
  WebPDecoderConfig config;
  if (!WebPInitDecoderConfig(&config)) {
    out.error = "libwebp could not start";
    return out;
  }
  config.output.colorspace = MODE_RGBA;  // straight alpha, as glTF's textures are
  const std::unique_ptr<WebPDecBuffer, OutputDeleter> output(&config.output);
  const VP8StatusCode status = WebPDecode(bytes, size, &config);
  if (status != VP8_STATUS_OK) {
    out.error = statusText(status);
    return out;
  }
  const WebPRGBABuffer& rgba = config.output.u.RGBA;
  const auto width = static_cast<std::size_t>(config.output.width);
  const auto height = static_cast<std::size_t>(config.output.height);
  out.rgba.reserve(width * height * 4);
  for (std::size_t row = 0; row < height; ++row) {
    const unsigned char* first = rgba.rgba + row * static_cast<std::size_t>(rgba.stride);
    out.rgba.insert(out.rgba.end(), first, first + width * 4);
  }
  out.ok = true;
  out.width = config.output.width;
  out.height = config.output.height;
  return out;
}

}  // namespace omnishadow::gltf_detail
