#include "renderer/output/image_writer.h"

#include <Imath/half.h>
#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfOutputFile.h>
#include <OpenEXR/ImfStandardAttributes.h>
#include <OpenEXR/ImfThreading.h>
#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <exception>
#include <set>
#include <stdexcept>
#include <string>

#include "renderer/core/errors.h"
#include "renderer/output/exr_memory_stream.h"
#include "renderer/output/output_transaction.h"
#include "renderer/output/png_encoder.h"

namespace omnishadow {
namespace {

// Names the output as the user gave it, also where the reason quotes the temporary's name.
std::string writeErrorMessage(const std::filesystem::path& path, std::string reason) {
  const std::string temporary = path.string();
  const std::string final = OutputTransaction::finalPathOf(path).string();
  for (std::size_t at = 0;
       !temporary.empty() && (at = reason.find(temporary, at)) != std::string::npos;
       at += final.size())
    reason.replace(at, temporary.size(), final);
  return "cannot write " + final + ": " + reason;
}

std::size_t pixelCount(int width, int height) {
  return static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
}

void validatePng(int width, int height, int channels, const std::vector<std::uint8_t>& pixels) {
  if (width <= 0 || height <= 0) throw std::invalid_argument("writePng: empty image");
  if (channels < 1 || channels > 4)
    throw std::invalid_argument("writePng: PNG needs 1 to 4 channels, got " +
                                std::to_string(channels));
  if (pixels.size() != pixelCount(width, height) * channels)
    throw std::invalid_argument("writePng: pixel buffer size does not match " +
                                std::to_string(width) + "x" + std::to_string(height) + "x" +
                                std::to_string(channels));
}

void validateExr(const FloatImage& image) {
  if (image.width <= 0 || image.height <= 0) throw std::invalid_argument("writeExr: empty image");
  if (image.channels.empty()) throw std::invalid_argument("writeExr: no channels");
  if (image.pixels.size() != pixelCount(image.width, image.height) * image.channels.size())
    throw std::invalid_argument("writeExr: pixel buffer size does not match width*height*channels");
  std::set<std::string> seen;
  for (const std::string& name : image.channels) {
    if (name.empty()) throw std::invalid_argument("writeExr: empty channel name");
    // OpenEXR keys channels by name, so a duplicate would silently drop data.
    if (!seen.insert(name).second)
      throw std::invalid_argument("writeExr: duplicate channel name " + name);
  }
}

// The header holds only what OpenEXR requires plus the compression: no capDate, owner or
// software attributes, so identical pixels give identical files.
Imf::Header exrHeader(const FloatImage& image, Imf::PixelType type) {
  Imf::Header header(image.width, image.height);
  header.compression() = Imf::ZIP_COMPRESSION;
  for (const std::string& name : image.channels) header.channels().insert(name, Imf::Channel(type));
  return header;
}

// Slices read straight from interleaved data; the data window starts at (0,0), so the base
// pointer needs no origin offset.
template <typename T>
Imf::FrameBuffer interleavedFrameBuffer(const FloatImage& image, Imf::PixelType type,
                                        const T* data) {
  const std::size_t channelCount = image.channels.size();
  const std::size_t xStride = sizeof(T) * channelCount;
  const std::size_t yStride = xStride * static_cast<std::size_t>(image.width);
  Imf::FrameBuffer frameBuffer;
  for (std::size_t c = 0; c < channelCount; ++c) {
    // OpenEXR's Slice takes a non-const pointer for both reading and writing.
    char* base = reinterpret_cast<char*>(const_cast<T*>(data + c));
    frameBuffer.insert(image.channels[c], Imf::Slice(type, base, xStride, yStride));
  }
  return frameBuffer;
}

void writeExrPixels(const std::filesystem::path& path, const Imf::Header& header,
                    const Imf::FrameBuffer& frameBuffer, int height) {
  ExrMemoryStream stream(path.string());
  {
    Imf::OutputFile file(stream, header);
    file.setFrameBuffer(frameBuffer);
    file.writePixels(height);
  }  // the destructor completes the file (the line offset table)
  writeFileBytes(path, stream.bytes());
}

std::vector<Imath::half> toHalf(const FloatPixels& pixels) {
  std::vector<Imath::half> halves(pixels.size());
  std::transform(pixels.begin(), pixels.end(), halves.begin(),
                 [](float value) { return Imath::half(value); });
  return halves;
}

}  // namespace

int FloatImage::channelIndex(const std::string& name) const {
  auto found = std::find(channels.begin(), channels.end(), name);
  return found == channels.end() ? -1 : static_cast<int>(found - channels.begin());
}

void writePng(const std::filesystem::path& path, int width, int height, int channels,
              const std::vector<std::uint8_t>& pixels) {
  validatePng(width, height, channels, pixels);
  // Encoded in memory and written by writeFileBytes, which notices a full disk.
  writeFileBytes(path, encodePng(width, height, channels, pixels));
}

void writeFileBytes(const std::filesystem::path& path, std::string_view bytes) {
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0666);
  if (fd < 0) throw RenderError(writeErrorMessage(path, std::strerror(errno)));
  std::size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      // write() returns 0 only for a zero-length request; treat it as no space all the same.
      const int error = n < 0 ? errno : ENOSPC;
      ::close(fd);
      throw RenderError(writeErrorMessage(path, std::strerror(error)));
    }
    done += static_cast<std::size_t>(n);
  }
  // Some file systems (NFS, quotas) report a full disk only when the file is closed.
  if (::close(fd) != 0) throw RenderError(writeErrorMessage(path, std::strerror(errno)));
}

void writeExr(const std::filesystem::path& path, const FloatImage& image, ExrPixelType type,
              const ExrCameraAttributes* camera) {
  validateExr(image);
  try {
    Imf::Header header = exrHeader(image, type == ExrPixelType::Half ? Imf::HALF : Imf::FLOAT);
    if (camera) {
      const auto matrix = [](const std::array<float, 16>& m) {
        return Imath::M44f(m[0], m[1], m[2], m[3], m[4], m[5], m[6], m[7], m[8], m[9], m[10], m[11],
                           m[12], m[13], m[14], m[15]);
      };
      Imf::addWorldToCamera(header, matrix(camera->worldToCamera));
      Imf::addWorldToNDC(header, matrix(camera->worldToNDC));
    }
    if (type == ExrPixelType::Half) {
      const std::vector<Imath::half> halves = toHalf(image.pixels);
      writeExrPixels(path, header, interleavedFrameBuffer(image, Imf::HALF, halves.data()),
                     image.height);
    } else {
      writeExrPixels(path, header, interleavedFrameBuffer(image, Imf::FLOAT, image.pixels.data()),
                     image.height);
    }
  } catch (const std::exception& error) {
    // Iex exceptions derive from std::exception; callers only know RenderError.
    throw RenderError(writeErrorMessage(path, error.what()));
  }
}

void setEncoderThreads(int threads) {
  Imf::setGlobalThreadCount(threads);
}

}  // namespace omnishadow
