#include "renderer/scene/gltf_file_safety.h"

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <cstring>
#include <limits>
#include <optional>
#include <tuple>
#include <utility>

#include "renderer/core/input_file.h"
#include "renderer/scene/avif_decoder.h"
#include "renderer/scene/gltf_context.h"
#include "renderer/scene/jpeg_decoder.h"
#include "renderer/scene/png_chunks.h"
#include "renderer/scene/png_texture_decoder.h"
#include "renderer/scene/webp_decoder.h"

namespace omnishadow::gltf_detail {

namespace {

// Images may not exceed this many texels per side or in all: a 64k x 64k PNG is a few KB of
// file but 16 GiB once decoded, so the header is checked before anything is allocated.
constexpr std::uint32_t kMaxImageSide = 32768;
constexpr std::uint64_t kMaxImageTexels = std::uint64_t{1} << 28;  // 1 GiB of RGBA8
// WebP and AVIF decoders keep the picture twice (libwebp's lossless ARGB rows, libavif's YUV
// planes, up to 6 bytes a texel, beside the RGBA output), and neither can be bounded by the
// data (see imageTooLarge): a few bytes can claim a picture as large as a container says (an
// AVIF's ispe box of 16384^2 over an 8x8 AV1 frame decodes to 16384^2). Half the texels.
constexpr std::uint64_t kMaxCodecTexels = kMaxImageTexels / 2;
// Nor may a header claim more than its data can hold: stb_image allocates for the header before
// it finds the data missing (a 400-byte JPEG can claim 16384 x 16384: 1 GiB, then decoded).
// A PNG's unfiltered rows fit in kMaxDeflateExpansion bytes per byte of file; a JPEG codes
// each 8x8 block with at least one bit, so it holds 512 texels per byte.
constexpr std::uint64_t kMaxJpegTexelsPerByte = 512;

bool isJpeg(const unsigned char* b, std::size_t size) {
  return size >= 2 && b[0] == 0xFF && b[1] == 0xD8;
}

}  // namespace

// glTF images are PNG or JPEG (WebP and AVIF through their extensions), and only those reach a
// decoder: stb_image's others would take almost any bytes for a TGA (a format without a
// signature).
bool isDecodableImage(const unsigned char* b, std::size_t size) {
  return isPng(b, size) || isJpeg(b, size) || isWebp(b, size) || isAvif(b, size);
}

namespace {

// Width and height of the JPEG frame that stb_image decodes (stbi__decode_jpeg_header): after
// SOI, markers may follow fill bytes (0xFF) and junk; DQT, DHT, DRI, APPn and COM segments are
// skipped by their length; any other marker before SOF0, SOF1 or SOF2 stops stb. nullopt when
// there is no such frame, which stb does not decode either.
std::optional<std::pair<std::uint32_t, std::uint32_t>> jpegFrameSize(const unsigned char* b,
                                                                     std::size_t size) {
  auto be16 = [&](std::size_t at) { return std::uint32_t{b[at]} << 8 | b[at + 1]; };
  constexpr int kNoMarker = 0xFF;
  std::size_t at = 2;
  const auto marker = [&]() -> int {
    if (at >= size) return 0;  // stb reads zeros past the end
    if (b[at++] != 0xFF) return kNoMarker;
    while (at < size && b[at] == 0xFF) ++at;
    return at < size ? b[at++] : 0;
  };
  int m = marker();
  while (m != 0xC0 && m != 0xC1 && m != 0xC2) {
    const bool skipped =
        m == 0xC4 || m == 0xDB || m == 0xDD || (m >= 0xE0 && m <= 0xEF) || m == 0xFE;
    if (!skipped || at + 2 > size || be16(at) < 2) return std::nullopt;
    at += be16(at);
    do {
      if (at >= size) return std::nullopt;
      m = marker();
    } while (m == kNoMarker);
  }
  // Length, precision, height, width.
  if (at + 7 > size) return std::nullopt;
  return std::make_pair(be16(at + 5), be16(at + 3));
}

}  // namespace

std::string imageMimeType(const unsigned char* bytes, std::size_t size) {
  return isPng(bytes, size)    ? "image/png"
         : isJpeg(bytes, size) ? "image/jpeg"
         : isWebp(bytes, size) ? "image/webp"
         : isAvif(bytes, size) ? "image/avif"
                               : "";
}

// Empty string when a PNG, JPEG, WebP or AVIF may be decoded, else why not.
std::string imageTooLarge(const unsigned char* bytes, std::size_t size) {
  std::uint32_t width = 0, height = 0;
  std::uint64_t rawBytes = 0;     // PNG: the unfiltered rows
  std::uint64_t neededBytes = 0;  // the least data that can hold the image
  std::string format;
  std::uint64_t maxTexels = kMaxImageTexels;
  if (isPng(bytes, size)) {
    // IHDR, which stb requires first: width, height, bit depth, color type. Shorter files and
    // other color types fail in stb before it allocates.
    if (size < 29) return {};
    const unsigned depth = bytes[24], colorType = bytes[25];
    const std::uint64_t channels = colorType == 0 || colorType == 3 ? 1
                                   : colorType == 4                 ? 2
                                   : colorType == 2                 ? 3
                                   : colorType == 6                 ? 4
                                                                    : 0;
    if (channels == 0) return {};
    width = pngBe32(bytes + 16);
    height = pngBe32(bytes + 20);
    rawBytes = (1 + (std::uint64_t{width} * channels * depth + 7) / 8) * height;
    neededBytes = (rawBytes + kMaxDeflateExpansion - 1) / kMaxDeflateExpansion;
    format = "PNG";
  } else if (isJpeg(bytes, size)) {
    const auto frame = jpegFrameSize(bytes, size);
    if (!frame) return "no JPEG frame header that can be decoded";
    std::tie(width, height) = *frame;
    neededBytes =
        (std::uint64_t{width} * height + kMaxJpegTexelsPerByte - 1) / kMaxJpegTexelsPerByte;
    format = "JPEG";
  } else if (isWebp(bytes, size)) {
    // No bound from the data: a lossless WebP of one color codes any number of texels in a few
    // bytes. libwebp decodes into untouched memory of its own (webp_decoder.h).
    const ImageHeader header = readWebpHeader(bytes, size);
    if (!header.ok) return "no WebP header that can be decoded: " + header.error;
    if (header.animated) return "an animated WebP (EXT_texture_webp takes still images)";
    width = header.width;
    height = header.height;
    format = "WebP";
    maxTexels = kMaxCodecTexels;
  } else if (isAvif(bytes, size)) {
    // Nor for AVIF; libavif reads the container's size (ispe) without decoding, and is given
    // the limits again to pass on to the AV1 decoder.
    const ImageHeader header = readAvifHeader(bytes, size);
    if (!header.ok) return "cannot read the AVIF: " + header.error;
    if (header.animated) return "an AVIF image sequence (EXT_texture_avif takes still images)";
    width = header.width;
    height = header.height;
    format = "AVIF";
    maxTexels = kMaxCodecTexels;
  } else {
    return {};
  }
  const std::string texels = std::to_string(width) + "x" + std::to_string(height) + " texels";
  if (width > kMaxImageSide || height > kMaxImageSide ||
      std::uint64_t{width} * height > maxTexels) {
    return texels + " is too large (at most " + std::to_string(kMaxImageSide) + " per side and " +
           std::to_string(maxTexels) + " in all" +
           (maxTexels != kMaxImageTexels ? " for " + format + ")" : ")");
  }
  // stb sizes its buffer for a PNG's rows with an int (16-bit RGBA at the limit overflows it).
  if (rawBytes > static_cast<std::uint64_t>(std::numeric_limits<int>::max())) {
    return texels + " of " + std::to_string(bytes[24]) + "-bit channels is too large";
  }
  if (neededBytes > size) {
    return texels + " cannot be in " + std::to_string(size) + " bytes of " + format +
           " (at least " + std::to_string(neededBytes) + " needed)";
  }
  // Every PNG chunk up to IEND must lie within the data: stb reserves memory for an IDAT
  // chunk's declared length before reading it (a 70-byte PNG from the fuzzer declared 1 GiB).
  if (format == "PNG") {
    const auto any = [](std::string_view, const unsigned char*, std::uint32_t) { return true; };
    if (const std::size_t at = walkPngChunks(bytes, size, any); at != 0) {
      return "a PNG chunk at byte " + std::to_string(at) + " extends past the end of the " +
             std::to_string(size) + " bytes";
    }
  }
  return {};
}

namespace {

// A picture our decoders made, as tinygltf describes the RGBA8 ones stb_image makes.
void setRgba8(tinygltf::Image& image, int width, int height, std::vector<unsigned char> rgba) {
  image.width = width;
  image.height = height;
  image.component = 4;
  image.bits = 8;
  image.pixel_type = TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE;
  image.image = std::move(rgba);
}

}  // namespace

namespace {

bool decodePixels(tinygltf::Image* image, int index, std::string* error, std::string* warning,
                  const unsigned char* bytes, int size) {
  const auto length = static_cast<std::size_t>(std::max(size, 0));
  if (isJpeg(bytes, length)) {
    DecodedJpeg jpeg = decodeJpeg(bytes, length, kMaxImageSide, kMaxImageTexels);
    if (jpeg.ok) {
      setRgba8(*image, jpeg.width, jpeg.height, std::move(jpeg.rgba));
      if (!jpeg.warning.empty() && warning)
        *warning += "damaged JPEG data (" + jpeg.warning + "); drawn as decoded\n";
      return true;
    }
    // stb_image only for what libjpeg-turbo leaves in CMYK: a file it refuses (too large a
    // frame, too many progressive scans, data it gives up on) is not tried again.
    if (!jpeg.cmyk) {
      if (error) *error += "cannot decode the JPEG: " + jpeg.error + "\n";
      return false;
    }
  }
  if (isAvif(bytes, length)) {
    DecodedImage avif = decodeAvif(bytes, length, kMaxImageSide, kMaxCodecTexels);
    if (!avif.ok) {
      if (error) *error += "cannot decode the AVIF: " + avif.error + "\n";
      return false;
    }
    setRgba8(*image, avif.width, avif.height, std::move(avif.rgba));
    return true;
  }
  if (isWebp(bytes, length)) {
    DecodedImage webp = decodeWebp(bytes, length, kMaxImageSide, kMaxCodecTexels);
    if (!webp.ok) {
      if (error) *error += "cannot decode the WebP: " + webp.error + "\n";
      return false;
    }
    setRgba8(*image, webp.width, webp.height, std::move(webp.rgba));
    return true;
  }
  // stb_image for every PNG the common-case decoder leaves: palettes, grey, 16 bits,
  // transparency chunks, interlacing, damaged data.
  DecodedPng png = decodePngTexture(bytes, length, kMaxImageSide, kMaxImageTexels);
  if (png.ok) {
    setRgba8(*image, png.width, png.height, std::move(png.rgba));
    return true;
  }
  return tinygltf::LoadImageData(image, index, error, warning, 0, 0, bytes, size, nullptr);
}

}  // namespace

bool decodeImage(tinygltf::Image* image, int index, std::string* error, std::string* warning,
                 const unsigned char* bytes, int size) {
  if (!decodePixels(image, index, error, warning, bytes, size)) return false;
  image->mimeType = imageMimeType(bytes, static_cast<std::size_t>(std::max(size, 0)));
  return true;
}

bool isExtensionImageFormat(const unsigned char* b, std::size_t size) {
  static constexpr unsigned char kKtx2[] = {0xAB, 'K',  'T',  'X',  ' ',  '2',
                                            '0',  0xBB, 0x0D, 0x0A, 0x1A, 0x0A};
  const auto startsWith = [&](const unsigned char* magic, std::size_t length, std::size_t at) {
    return size >= at + length && std::memcmp(b + at, magic, length) == 0;
  };
  return startsWith(kKtx2, sizeof kKtx2, 0) ||
         startsWith(reinterpret_cast<const unsigned char*>("DDS "), 4, 0);
}

// tinygltf 2.7 hands an image stored in a bufferView to the decoder without checking that the
// view lies inside its buffer, so a broken file could make stb read past the end. Those images
// are skipped here and decoded by convertImages() after the bounds check; images from URIs
// (bytes tinygltf read itself) are decoded as usual.
bool decodeUriImage(tinygltf::Image* image, int index, std::string* error, std::string* warning,
                    int width, int height, const unsigned char* bytes, int size, void* dataUris) {
  const bool taken = dataUris && static_cast<const DataUris*>(dataUris)->restoreImage(*image);
  if (image->bufferView >= 0) return true;
  const auto length = static_cast<std::size_t>(std::max(size, 0));
  // Left undecoded for the loader, which draws the texture's fallback source instead or names
  // the extension that brought the image (gltf_extension_policy).
  if (isExtensionImageFormat(bytes, length)) return true;
  if (!isDecodableImage(bytes, length)) {
    // Worded like tinygltf's message for data stb cannot decode.
    if (error) {
      *error += "Unknown image format for image[" + std::to_string(index) +
                "]: glTF images are PNG or JPEG (or WebP and AVIF through their extensions)\n";
    }
    return false;
  }
  if (const std::string why = imageTooLarge(bytes, length); !why.empty()) {
    if (error) *error += "images[" + std::to_string(index) + "]: " + why + "\n";
    return false;
  }
  // An image in a file of its own, or in a data: URI the reader took, is decoded by the loader
  // with the scene's other images, several at a time (convertImages); here they would be decoded
  // one after the other as tinygltf parses. as_is marks the bytes as not yet decoded.
  if ((taken || (!image->uri.empty() && !tinygltf::IsDataURI(image->uri))) && width <= 0 &&
      height <= 0) {
    image->image.assign(bytes, bytes + length);
    image->as_is = true;
    return true;
  }
  std::string damaged, failure;
  if (!decodeImage(image, index, &failure, &damaged, bytes, size)) {
    // Named like the checks' messages above (the decoders' own lines name no image).
    if (error) {
      for (const std::string& line : nonEmptyLines(failure))
        *error += "images[" + std::to_string(index) + "]: " + line + "\n";
    }
    return false;
  }
  if (warning) {
    for (const std::string& line : nonEmptyLines(damaged))
      *warning += "images[" + std::to_string(index) + "]: " + line + "\n";
  }
  // tinygltf asks for a size only where a caller set one; none does, but keep its contract.
  if ((width > 0 && image->width != width) || (height > 0 && image->height != height)) {
    if (error) *error += "images[" + std::to_string(index) + "]: unexpected image size\n";
    return false;
  }
  return true;
}

namespace {

// A URI scheme (RFC 3986: a letter, then letters, digits, "+", "-" or "."; then ":"). A
// relative path whose first segment has a colon must be written "./a:b", so "file:x" and
// "http:x" are URIs in another scheme, never file names.
bool hasUriScheme(const std::string& uri) {
  const std::size_t colon = uri.find(':');
  if (colon == std::string::npos || colon == 0 || !std::isalpha(static_cast<unsigned char>(uri[0])))
    return false;
  return std::all_of(uri.begin(), uri.begin() + static_cast<std::ptrdiff_t>(colon), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '+' || c == '-' || c == '.';
  });
}

// Records why `filepath` may not be read, or returns true. Decided from the path alone
// (symbolic links resolved by weakly_canonical, which reads links but opens no file).
bool permitted(UriPolicy& policy, const std::string& filepath) {
  namespace fs = std::filesystem;
  const std::string folderPrefix = policy.folder.string() + "/";
  const std::string uri =
      filepath.starts_with(folderPrefix) ? filepath.substr(folderPrefix.size()) : filepath;
  if (filepath.find("://") != std::string::npos || hasUriScheme(uri)) {
    // tinygltf decodes the data: URIs it can (base64 of known types) before any lookup.
    const bool data = uri.starts_with("data:");
    if (policy.violation.empty()) {
      policy.violation =
          "\"" + (uri.size() > 60 ? uri.substr(0, 60) + "..." : uri) + "\": " +
          (data ? "only base64 data: URIs of buffers, PNG, JPEG, WebP and AVIF are supported"
                : "only data: URIs and relative file paths are supported");
    }
    return false;
  }
  if (policy.allowExternal) return true;
  // tinygltf's second guess, the working directory, is not where a URI points: refused without
  // a word, so that the message is about the lookup beside the scene.
  if (!filepath.starts_with(folderPrefix)) return false;
  std::error_code ec;
  const fs::path resolved = fs::weakly_canonical(fs::absolute(filepath), ec);
  const fs::path relative = resolved.lexically_relative(policy.folder);
  if (!ec && !relative.empty() && *relative.begin() != "..") return true;
  if (policy.violation.empty()) {
    policy.violation =
        "\"" + uri + "\" is outside the scene's folder; pass --allow-external-uris to read it";
  }
  return false;
}

// External buffers and images: tinygltf takes sizes as unsigned int.
constexpr std::uint64_t kMaxExternalFileBytes = std::uint64_t{2} << 30;

}  // namespace

// tinygltf looks for a URI beside the scene and then in the working directory; both lookups
// and the read itself go through the policy, before the file is looked at.
bool existsWithinFolder(const std::string& filepath, void* user) {
  auto* policy = static_cast<UriPolicy*>(user);
  if (policy->dataUris && policy->dataUris->find(filepath)) return true;
  if (!permitted(*policy, filepath)) return false;
  // Anything that exists counts, so that reading it says why a FIFO or a folder is refused.
  std::error_code ec;
  return std::filesystem::exists(filepath, ec);
}

bool readWithinFolder(std::vector<unsigned char>* out, std::string* error,
                      const std::string& filepath, void* user) {
  auto* policy = static_cast<UriPolicy*>(user);
  if (DataUris::Payload* payload = policy->dataUris ? policy->dataUris->find(filepath) : nullptr) {
    // Each placeholder is in the JSON once, so tinygltf reads it once: the bytes move.
    if (payload->served) {
      if (error) *error = "a data: URI read twice";
      return false;
    }
    *out = std::move(payload->bytes);
    payload->served = true;
    return true;
  }
  if (!permitted(*policy, filepath)) {
    if (error) *error = policy->violation;
    return false;
  }
  std::string content;
  if (std::string why = readRegularFile(filepath, kMaxExternalFileBytes, content); !why.empty()) {
    const std::string folderPrefix = policy->folder.string() + "/";
    const std::string uri =
        filepath.starts_with(folderPrefix) ? filepath.substr(folderPrefix.size()) : filepath;
    // An image tinygltf cannot read is only a warning to it; a file that is not one is an error.
    if (policy->violation.empty()) policy->violation = "\"" + uri + "\": " + why;
    if (error) *error = why;
    return false;
  }
  out->assign(content.begin(), content.end());
  return true;
}

}  // namespace omnishadow::gltf_detail
