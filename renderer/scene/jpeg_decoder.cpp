#include "renderer/scene/jpeg_decoder.h"

#include <turbojpeg.h>

#include <limits>
#include <memory>

namespace omnishadow::gltf_detail {

namespace {

struct HandleDeleter {
  void operator()(void* handle) const { tjDestroy(handle); }
};
using Decompressor = std::unique_ptr<void, HandleDeleter>;

std::string reason(void* handle) {
  const char* text = tjGetErrorStr2(handle);
  return text && *text ? text : "libjpeg-turbo cannot decode it";
}

}  // namespace

DecodedJpeg decodeJpeg(const unsigned char* bytes, std::size_t size, std::uint32_t maxSide,
                       std::uint64_t maxTexels) {
  DecodedJpeg out;
  if (size > std::numeric_limits<unsigned long>::max()) {
    out.error = "too large a JPEG";
    return out;
  }
  const Decompressor handle(tjInitDecompress());
  if (!handle) {
    out.error = "libjpeg-turbo could not start";
    return out;
  }
  int width = 0, height = 0, subsampling = 0, colorspace = 0;
  if (tjDecompressHeader3(handle.get(), bytes, static_cast<unsigned long>(size), &width, &height,
                          &subsampling, &colorspace) != 0) {
    out.error = reason(handle.get());
    return out;
  }
  if (colorspace == TJCS_CMYK || colorspace == TJCS_YCCK) {
    out.cmyk = true;
    out.error = "a CMYK JPEG";
    return out;
  }
  // The header checks before decoding follow stb_image's parsing; libjpeg may find another frame.
  if (width <= 0 || height <= 0 || static_cast<std::uint32_t>(width) > maxSide ||
      static_cast<std::uint32_t>(height) > maxSide ||
      static_cast<std::uint64_t>(width) * static_cast<std::uint64_t>(height) > maxTexels) {
    out.error = std::to_string(width) + "x" + std::to_string(height) + " texels is too large";
    return out;
  }
  out.rgba.resize(static_cast<std::size_t>(width) * static_cast<std::size_t>(height) * 4);
  if (tjDecompress2(handle.get(), bytes, static_cast<unsigned long>(size), out.rgba.data(), width,
                    0, height, TJPF_RGBA, TJFLAG_LIMITSCANS) != 0) {
    if (tjGetErrorCode(handle.get()) != TJERR_WARNING) {
      out.error = reason(handle.get());
      out.rgba.clear();
      return out;
    }
    // Damaged data (a truncated file, say): libjpeg fills in what is missing, as stb did.
    out.warning = reason(handle.get());
  }
  out.ok = true;
  out.width = width;
  out.height = height;
  return out;
}

}  // namespace omnishadow::gltf_detail
