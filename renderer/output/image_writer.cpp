#include "renderer/output/image_writer.h"

#include <Imath/half.h>
#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfOutputFile.h>
#include <OpenEXR/ImfThreading.h>
#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>
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
#include "renderer/core/input_file.h"
#include "renderer/output/exr_memory_stream.h"
#include "renderer/output/output_transaction.h"

namespace omnishadow {
namespace {

// Names the output as the user gave it, also where the reason quotes the temporary's name.
std::string cannotWrite(const std::filesystem::path& path, std::string reason) {
  const std::string temporary = path.string();
  const std::string final = OutputTransaction::finalPathOf(path).string();
  for (std::size_t at = 0;
       !temporary.empty() && (at = reason.find(temporary, at)) != std::string::npos;
       at += final.size())
    reason.replace(at, temporary.size(), final);
  return "cannot write " + final + ": " + reason;
}

// OIIO keeps errors per object and globally; whichever is set explains the failure.
std::string oiioReason(const std::string& objectError) {
  if (!objectError.empty()) return objectError;
  std::string global = OIIO::geterror();
  return global.empty() ? "unknown OpenImageIO error" : global;
}

// What readImage takes: files up to 2 GiB, decoded to at most 1 GiB of floats.
constexpr std::uint64_t kMaxImageFileBytes = std::uint64_t{2} << 30;
constexpr std::uint64_t kMaxImageValues = std::uint64_t{1} << 28;

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

std::vector<Imath::half> toHalf(const std::vector<float>& pixels) {
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
  // Created by format name, not by extension, so temporaries and odd names still get PNG.
  auto output = OIIO::ImageOutput::create("png");
  if (!output) throw RenderError(cannotWrite(path, oiioReason("")));
  // Encoded in memory and written by writeFileBytes: OIIO's PNG writer does not notice a write
  // that fails (a full disk), and would leave a short file that looks complete.
  std::vector<unsigned char> encoded;
  OIIO::Filesystem::IOVecOutput memory(encoded);
  if (!output->set_ioproxy(&memory))
    throw RenderError(cannotWrite(path, oiioReason(output->geterror())));
  // A bare spec: OIIO 2.4's PNG writer turns extra attributes (DateTime, Software,
  // XResolution, oiio:ColorSpace...) into tEXt/tIME/pHYs/gAMA chunks, and adds none of its own
  // beyond a constant oFFs(0,0), so identical pixels give identical bytes.
  OIIO::ImageSpec spec(width, height, channels, OIIO::TypeDesc::UINT8);
  // Our pixels already hold straight alpha, as PNG requires; without this OIIO would treat them
  // as premultiplied and divide colour by alpha. "oiio:" hints are not written to the file.
  spec.attribute("oiio:UnassociatedAlpha", 1);
  if (!output->open(path.string(), spec))
    throw RenderError(cannotWrite(path, oiioReason(output->geterror())));
  if (!output->write_image(OIIO::TypeDesc::UINT8, pixels.data())) {
    std::string reason = oiioReason(output->geterror());
    output->close();
    throw RenderError(cannotWrite(path, reason));
  }
  // close() flushes the final IDAT/IEND.
  if (!output->close()) throw RenderError(cannotWrite(path, oiioReason(output->geterror())));
  writeFileBytes(path, {reinterpret_cast<const char*>(encoded.data()), encoded.size()});
}

void writeFileBytes(const std::filesystem::path& path, std::string_view bytes) {
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0666);
  if (fd < 0) throw RenderError(cannotWrite(path, std::strerror(errno)));
  std::size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      // write() returns 0 only for a zero-length request; treat it as no space all the same.
      const int error = n < 0 ? errno : ENOSPC;
      ::close(fd);
      throw RenderError(cannotWrite(path, std::strerror(error)));
    }
    done += static_cast<std::size_t>(n);
  }
  // Some file systems (NFS, quotas) report a full disk only when the file is closed.
  if (::close(fd) != 0) throw RenderError(cannotWrite(path, std::strerror(errno)));
}

void writeExr(const std::filesystem::path& path, const FloatImage& image, ExrPixelType type) {
  validateExr(image);
  try {
    if (type == ExrPixelType::Half) {
      const std::vector<Imath::half> halves = toHalf(image.pixels);
      writeExrPixels(path, exrHeader(image, Imf::HALF),
                     interleavedFrameBuffer(image, Imf::HALF, halves.data()), image.height);
    } else {
      writeExrPixels(path, exrHeader(image, Imf::FLOAT),
                     interleavedFrameBuffer(image, Imf::FLOAT, image.pixels.data()), image.height);
    }
  } catch (const std::exception& error) {
    // Iex exceptions derive from std::exception; callers only know RenderError.
    throw RenderError(cannotWrite(path, error.what()));
  }
}

void setEncoderThreads(int threads) {
  Imf::setGlobalThreadCount(threads);
}

FloatImage readImage(const std::filesystem::path& path) {
  const std::string name = path.string();
  auto fail = [&](const std::string& reason) {
    return InputError(name + ": cannot read image: " + reason);
  };
  // Read through the checks every input gets (a FIFO or /dev/zero must neither block nor fill
  // memory), then decoded from memory.
  std::string bytes;
  if (const std::string why = readRegularFile(path, kMaxImageFileBytes, bytes); !why.empty())
    throw fail(why);
  OIIO::Filesystem::IOMemReader memory(bytes.data(), bytes.size());
  OIIO::Filesystem::IOProxy* proxy = &memory;
  // Return the stored values: OIIO would otherwise premultiply PNG colour by alpha on read.
  OIIO::ImageSpec config;
  config.attribute("oiio:UnassociatedAlpha", 1);
  config.attribute("oiio:ioproxy", OIIO::TypeDesc::PTR, &proxy);
  auto input = OIIO::ImageInput::open(name, &config);
  if (!input) throw fail(oiioReason(""));
  const OIIO::ImageSpec& spec = input->spec();
  // The header is checked before the pixels are allocated: a 1 MB PNG may claim 16384 x 16384
  // (4 GiB as float).
  const std::uint64_t values = std::uint64_t(std::max(spec.width, 0)) *
                               std::uint64_t(std::max(spec.height, 0)) *
                               std::uint64_t(std::max(spec.nchannels, 0));
  if (values > kMaxImageValues) {
    throw fail(std::to_string(spec.width) + "x" + std::to_string(spec.height) + " with " +
               std::to_string(spec.nchannels) + " channels is too large (at most " +
               std::to_string(kMaxImageValues) + " channel values, e.g. 8192x8192 RGBA)");
  }
  FloatImage image;
  image.width = spec.width;
  image.height = spec.height;
  image.channels.assign(spec.channelnames.begin(), spec.channelnames.end());
  image.channels.resize(static_cast<std::size_t>(spec.nchannels));
  image.pixels.resize(pixelCount(spec.width, spec.height) *
                      static_cast<std::size_t>(spec.nchannels));
  if (!input->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, image.pixels.data()))
    throw fail(oiioReason(input->geterror()));
  input->close();
  return image;
}

}  // namespace omnishadow
