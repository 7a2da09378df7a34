#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "renderer/core/default_init_allocator.h"

namespace omnishadow {

// A float image's samples. FloatPixels(n) and resize(n) leave them uninitialized (each producer
// writes every sample); FloatPixels(n, 0.0f) zeroes.
using FloatPixels = std::vector<float, DefaultInitAllocator<float>>;

// Linear float image with named channels, interleaved, first row = top of the picture.
struct FloatImage {
  int width = 0;
  int height = 0;
  std::vector<std::string> channels;  // e.g. {"R","G","B","A"} or {"P.X","P.Y","P.Z",...}
  FloatPixels pixels;                 // width * height * channels.size()

  float& at(int x, int y, int c) {
    return pixels[(std::size_t(y) * width + x) * channels.size() + c];
  }
  float at(int x, int y, int c) const {
    return pixels[(std::size_t(y) * width + x) * channels.size() + c];
  }
  int channelIndex(const std::string& name) const;  // -1 when absent
};

enum class ExrPixelType { Half, Float };

// 8-bit PNG with 1..4 channels, no metadata that changes between runs (byte-identical output
// for identical pixels). Throws RenderError when the file cannot be written.
void writePng(const std::filesystem::path& path, int width, int height, int channels,
              const std::vector<std::uint8_t>& pixels);

// The camera an image was rendered with, as OpenEXR's standard attributes hold it: 4x4
// matrices in the memory order of glm (column-major for column vectors, which is Imath's
// row-major for row vectors). worldToCamera maps to OpenEXR's left-handed camera space (+x
// right, +y up, +z the viewing direction); worldToNDC maps to [-1, 1] x and y (+y up) and the
// renderer's reversed [0, 1] depth, after the division by w.
struct ExrCameraAttributes {
  std::array<float, 16> worldToCamera{};
  std::array<float, 16> worldToNDC{};
};

// OpenEXR, ZIP compressed, channels named as given (OpenEXR stores them sorted by name),
// no time stamps; with `camera`, the worldToCamera and worldToNDC header attributes. Throws
// RenderError when the file cannot be written.
void writeExr(const std::filesystem::path& path, const FloatImage& image, ExrPixelType type,
              const ExrCameraAttributes* camera = nullptr);

// Writes `bytes` to `path` (created, or emptied when it exists) and closes it, checking every
// step: a full disk or a file size limit is a RenderError naming the output, never a short file
// that looks written. The encoders write through it.
void writeFileBytes(const std::filesystem::path& path, std::string_view bytes);

// Lets OpenEXR compress blocks of scan lines on `threads` threads (0 = in the calling thread).
// Output bytes do not depend on it. Call once at start-up: it sets OpenEXR's global pool.
void setEncoderThreads(int threads);

// Reads an image as float, for tests and tools: PNG and OpenEXR directly (png_decoder.h,
// exr_reader.h) and Radiance HDR (radiance_hdr_decoder.h), any other format OpenImageIO
// understands through its plugin (oiio_plugin.h).
// Throws InputError when unreadable.
FloatImage readImage(const std::filesystem::path& path);

}  // namespace omnishadow
