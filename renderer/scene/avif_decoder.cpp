#include "renderer/scene/avif_decoder.h"

#include <avif/avif.h>
#include <dlfcn.h>

#include <algorithm>
#include <cstring>
#include <memory>

#include "renderer/core/library_symbol.h"

#ifndef OMNISHADOW_LIBAVIF_SONAME
#error "OMNISHADOW_LIBAVIF_SONAME: the CMake build defines it from the libavif it found"
#endif

namespace omnishadow::gltf_detail {

namespace {

// The functions of libavif a decode calls, resolved once from the library loaded on first use.
struct LibAvif {
  std::string error;  // set when the library or one of its functions could not be loaded
  decltype(&avifDecoderCreate) decoderCreate = nullptr;
  decltype(&avifDecoderDestroy) decoderDestroy = nullptr;
  decltype(&avifDecoderSetIOMemory) decoderSetIOMemory = nullptr;
  decltype(&avifDecoderParse) decoderParse = nullptr;
  decltype(&avifDecoderNextImage) decoderNextImage = nullptr;
  decltype(&avifRGBImageSetDefaults) rgbImageSetDefaults = nullptr;
  decltype(&avifImageYUVToRGB) imageYuvToRgb = nullptr;
  decltype(&avifResultToString) resultToString = nullptr;
};

LibAvif load() {
  LibAvif lib;
  // Never closed: the decoders' threads and function pointers live as long as the process.
  void* handle = ::dlopen(OMNISHADOW_LIBAVIF_SONAME, RTLD_NOW | RTLD_LOCAL);
  if (!handle) {
    lib.error = std::string("libavif (") + OMNISHADOW_LIBAVIF_SONAME +
                ") is not installed; on Debian: apt install libavif15";
    return lib;
  }
  const bool all = resolveSymbol(handle, "avifDecoderCreate", lib.decoderCreate) &&
                   resolveSymbol(handle, "avifDecoderDestroy", lib.decoderDestroy) &&
                   resolveSymbol(handle, "avifDecoderSetIOMemory", lib.decoderSetIOMemory) &&
                   resolveSymbol(handle, "avifDecoderParse", lib.decoderParse) &&
                   resolveSymbol(handle, "avifDecoderNextImage", lib.decoderNextImage) &&
                   resolveSymbol(handle, "avifRGBImageSetDefaults", lib.rgbImageSetDefaults) &&
                   resolveSymbol(handle, "avifImageYUVToRGB", lib.imageYuvToRgb) &&
                   resolveSymbol(handle, "avifResultToString", lib.resultToString);
  if (!all)
    lib.error = std::string(OMNISHADOW_LIBAVIF_SONAME) + " lacks a function omnishadow calls";
  return lib;
}

const LibAvif& libavif() {
  static const LibAvif lib = load();  // thread-safe: images are decoded on several threads
  return lib;
}

struct DecoderDeleter {
  void operator()(avifDecoder* decoder) const { libavif().decoderDestroy(decoder); }
};
using Decoder = std::unique_ptr<avifDecoder, DecoderDeleter>;

// A decoder that has parsed the container of `bytes` (which it reads in place), or an error.
// maxSide 0: no limit but libavif's own (for the header alone, which the caller checks).
struct Parsed {
  Decoder decoder;
  std::string error;
};

Parsed parse(const unsigned char* bytes, std::size_t size, std::uint32_t maxSide,
             std::uint64_t maxTexels) {
  Parsed out;
  const LibAvif& lib = libavif();
  if (!lib.error.empty()) {
    out.error = lib.error;
    return out;
  }
  out.decoder.reset(lib.decoderCreate());
  if (!out.decoder) {
    out.error = "libavif could not start";
    return out;
  }
  avifDecoder& decoder = *out.decoder;
  // libavif checks the container's size (ispe) against these, and passes the texel limit on
  // to dav1d, before anything of the picture is allocated.
  // (libavif takes no texel limit above its default, 2^28: a larger one fails every parse.)
  decoder.imageDimensionLimit = maxSide;
  if (maxSide != 0) {
    decoder.imageSizeLimit = static_cast<std::uint32_t>(
        std::min<std::uint64_t>(maxTexels, AVIF_DEFAULT_IMAGE_SIZE_LIMIT));
  }
  decoder.ignoreExif = AVIF_TRUE;
  decoder.ignoreXMP = AVIF_TRUE;
  avifResult result = lib.decoderSetIOMemory(&decoder, bytes, size);
  if (result == AVIF_RESULT_OK) result = lib.decoderParse(&decoder);
  if (result != AVIF_RESULT_OK) {
    out.error = lib.resultToString(result);
    if (decoder.diag.error[0] != '\0') out.error += std::string(" (") + decoder.diag.error + ")";
    out.decoder.reset();
  }
  return out;
}

}  // namespace

bool isAvif(const unsigned char* bytes, std::size_t size) {
  if (size < 16 || std::memcmp(bytes + 4, "ftyp", 4) != 0) return false;
  const std::size_t box =
      std::min<std::size_t>(size, std::size_t{bytes[0]} << 24 | std::size_t{bytes[1]} << 16 |
                                      std::size_t{bytes[2]} << 8 | bytes[3]);
  const auto avifBrand = [&](std::size_t at) {
    return std::memcmp(bytes + at, "avif", 4) == 0 || std::memcmp(bytes + at, "avis", 4) == 0;
  };
  if (avifBrand(8)) return true;
  // After the major brand and its version, the compatible brands fill the box.
  for (std::size_t at = 16; at + 4 <= box; at += 4)
    if (avifBrand(at)) return true;
  return false;
}

ImageHeader readAvifHeader(const unsigned char* bytes, std::size_t size) {
  ImageHeader header;
  const Parsed parsed = parse(bytes, size, 0, 0);
  if (!parsed.decoder) {
    header.error = parsed.error;
    return header;
  }
  header.ok = true;
  header.width = parsed.decoder->image->width;
  header.height = parsed.decoder->image->height;
  header.animated = parsed.decoder->imageCount > 1;
  return header;
}

DecodedImage decodeAvif(const unsigned char* bytes, std::size_t size, std::uint32_t maxSide,
                        std::uint64_t maxTexels) {
  DecodedImage out;
  const Parsed parsed = parse(bytes, size, maxSide, maxTexels);
  if (!parsed.decoder) {
    out.error = parsed.error;
    return out;
  }
  avifDecoder& decoder = *parsed.decoder;
  if (decoder.imageCount > 1) {
    out.error = "an AVIF image sequence (" + std::to_string(decoder.imageCount) +
                " frames; EXT_texture_avif takes still images)";
    return out;
  }
  const LibAvif& lib = libavif();
  if (const avifResult result = lib.decoderNextImage(&decoder); result != AVIF_RESULT_OK) {
    out.error = lib.resultToString(result);
    if (decoder.diag.error[0] != '\0') out.error += std::string(" (") + decoder.diag.error + ")";
    return out;
  }
  const avifImage& image = *decoder.image;
  avifRGBImage rgb;
  lib.rgbImageSetDefaults(&rgb, &image);
  rgb.format = AVIF_RGB_FORMAT_RGBA;
  rgb.depth = 8;                        // 10- and 12-bit pictures rounded to 8
  rgb.alphaPremultiplied = AVIF_FALSE;  // straight alpha, as glTF's textures are
  const auto width = static_cast<std::size_t>(image.width);
  const auto height = static_cast<std::size_t>(image.height);
  // The AV1 data decoded whole: the picture is real, and written straight into our buffer.
  out.rgba.resize(width * height * 4);
  rgb.pixels = out.rgba.data();
  rgb.rowBytes = static_cast<std::uint32_t>(width * 4);
  if (const avifResult result = lib.imageYuvToRgb(&image, &rgb); result != AVIF_RESULT_OK) {
    out.error = std::string("cannot convert its colors: ") + lib.resultToString(result);
    out.rgba.clear();
    return out;
  }
  out.ok = true;
  out.width = static_cast<int>(image.width);
  out.height = static_cast<int>(image.height);
  return out;
}

}  // namespace omnishadow::gltf_detail
