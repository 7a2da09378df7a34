#include "renderer/scene/gltf_loader.h"

#include <tiny_gltf.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <limits>
#include <optional>
#include <set>
#include <span>
#include <string>
#include <string_view>
#include <tuple>
#include <utility>
#include <vector>

#include "renderer/core/errors.h"
#include "renderer/scene/tangents.h"

namespace omnishadow {

namespace {

// Extensions whose meaning we implement; anything else in extensionsRequired cannot be drawn
// correctly, anything else merely used is ignored with a warning.
constexpr std::string_view kSupportedExtensions[] = {"KHR_lights_punctual",
                                                     "KHR_materials_emissive_strength"};

// An accessor without a bufferView is all zeros (plus sparse values): its count costs a file
// nothing to write but us memory and time to expand, however often it is read (every primitive
// that uses it reads it again). So all such reads of one file share a limit, far above what
// real files use them for (sparse morph targets, which are not read) yet small enough that a
// 100-byte file cannot keep the loader busy for seconds.
constexpr std::size_t kMaxCountWithoutBufferView = std::size_t{1} << 18;

std::string at(std::string_view array, std::size_t index) {
  return std::string(array) + "[" + std::to_string(index) + "]";
}

std::string plural(std::size_t count, std::string_view noun) {
  const char* ending = count == 1 ? "" : noun.ends_with("sh") ? "es" : "s";
  return std::to_string(count) + " " + std::string(noun) + ending;
}

std::vector<std::string> nonEmptyLines(const std::string& text) {
  std::vector<std::string> lines;
  std::size_t start = 0;
  while (start <= text.size()) {
    std::size_t end = text.find('\n', start);
    if (end == std::string::npos) end = text.size();
    std::string line = text.substr(start, end - start);
    while (!line.empty() && std::isspace(static_cast<unsigned char>(line.back()))) line.pop_back();
    if (!line.empty()) lines.push_back(std::move(line));
    start = end + 1;
  }
  return lines;
}

// State shared by the conversion steps: the parsed file, the scene being filled, and the
// message conventions ("<file>: <glTF object>: <problem>").
struct Context {
  std::string file;
  const tinygltf::Model& model;
  Scene& scene;
  bool warnedSkins = false;
  bool warnedMorphTargets = false;
  std::size_t countWithoutBufferView = 0;  // elements read so far from accessors without one

  [[noreturn]] void fail(const std::string& object, const std::string& problem) const {
    throw InputError(file + ": " + object + ": " + problem);
  }
  void warn(const std::string& message) const { scene.warnings.push_back(file + ": " + message); }

  // Validates a reference from `object` to model array `array` of `size` elements.
  void checkIndex(const std::string& object, std::string_view array, int index,
                  std::size_t size) const {
    if (index < 0 || static_cast<std::size_t>(index) >= size) {
      fail(object, std::string(array) + " " + std::to_string(index) +
                       " is out of range (the file has " + plural(size, array) + ")");
    }
  }
};

// -----------------------------------------------------------------------------------------------
// Reading the file

// tinygltf 2.7 hands an image stored in a bufferView to the decoder without checking that the
// view lies inside its buffer, so a broken file could make stb read past the end. Those images
// are skipped here and decoded by convertImages() after the bounds check; images from URIs
// (bytes tinygltf read itself) are decoded as usual.
// Images may not exceed this many texels per side or in all: a 64k x 64k PNG is a few KB of
// file but 16 GiB once decoded, so the header is checked before anything is allocated.
constexpr std::uint32_t kMaxImageSide = 32768;
constexpr std::uint64_t kMaxImageTexels = std::uint64_t{1} << 28;  // 1 GiB of RGBA8
// Nor may a header claim more than its data can hold: stb_image allocates for the header before
// it finds the data missing (a 400-byte JPEG can claim 16384 x 16384: 1 GiB, then decoded).
// Deflate expands at most 1032 times, so a PNG's unfiltered rows fit in 1032 bytes per byte of
// file; a JPEG codes each 8x8 block with at least one bit, so it holds 512 texels per byte.
constexpr std::uint64_t kMaxPngExpansion = 1032;
constexpr std::uint64_t kMaxJpegTexelsPerByte = 512;

bool isPng(const unsigned char* b, std::size_t size) {
  return size >= 8 && std::memcmp(b, "\x89PNG\r\n\x1a\n", 8) == 0;
}
bool isJpeg(const unsigned char* b, std::size_t size) {
  return size >= 2 && b[0] == 0xFF && b[1] == 0xD8;
}

// glTF images are PNG or JPEG, and only those reach stb_image: its other decoders would take
// almost any bytes for a TGA (a format without a signature) of any size.
bool isPngOrJpeg(const unsigned char* b, std::size_t size) {
  return isPng(b, size) || isJpeg(b, size);
}

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

// Empty string when a PNG or JPEG may be decoded, else why not.
std::string imageTooLarge(const unsigned char* bytes, std::size_t size) {
  auto be32 = [&](std::size_t at) {
    return std::uint32_t{bytes[at]} << 24 | std::uint32_t{bytes[at + 1]} << 16 |
           std::uint32_t{bytes[at + 2]} << 8 | bytes[at + 3];
  };
  std::uint32_t width = 0, height = 0;
  std::uint64_t rawBytes = 0;     // PNG: the unfiltered rows
  std::uint64_t neededBytes = 0;  // the least data that can hold the image
  std::string format;
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
    width = be32(16);
    height = be32(20);
    rawBytes = (1 + (std::uint64_t{width} * channels * depth + 7) / 8) * height;
    neededBytes = (rawBytes + kMaxPngExpansion - 1) / kMaxPngExpansion;
    format = "PNG";
  } else if (isJpeg(bytes, size)) {
    const auto frame = jpegFrameSize(bytes, size);
    if (!frame) return "no JPEG frame header that can be decoded";
    std::tie(width, height) = *frame;
    neededBytes =
        (std::uint64_t{width} * height + kMaxJpegTexelsPerByte - 1) / kMaxJpegTexelsPerByte;
    format = "JPEG";
  } else {
    return {};
  }
  const std::string texels = std::to_string(width) + "x" + std::to_string(height) + " texels";
  if (width > kMaxImageSide || height > kMaxImageSide ||
      std::uint64_t{width} * height > kMaxImageTexels) {
    return texels + " is too large (at most " + std::to_string(kMaxImageSide) + " per side and " +
           std::to_string(kMaxImageTexels) + " in all)";
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
  for (std::size_t at = 8; format == "PNG";) {
    if (size - at < 12 || be32(at) > size - at - 12) {
      return "a PNG chunk at byte " + std::to_string(at) + " extends past the end of the " +
             std::to_string(size) + " bytes";
    }
    if (std::memcmp(bytes + at + 4, "IEND", 4) == 0) break;
    at += 12 + std::size_t{be32(at)};
  }
  return {};
}

bool decodeUriImage(tinygltf::Image* image, int index, std::string* error, std::string* warning,
                    int width, int height, const unsigned char* bytes, int size, void*) {
  if (image->bufferView >= 0) return true;
  const auto length = static_cast<std::size_t>(std::max(size, 0));
  if (!isPngOrJpeg(bytes, length)) {
    // Worded like tinygltf's message for data stb cannot decode.
    if (error) {
      *error += "Unknown image format for image[" + std::to_string(index) +
                "]: glTF images are PNG or JPEG\n";
    }
    return false;
  }
  if (const std::string why = imageTooLarge(bytes, length); !why.empty()) {
    if (error) *error += "images[" + std::to_string(index) + "]: " + why + "\n";
    return false;
  }
  return tinygltf::LoadImageData(image, index, error, warning, width, height, bytes, size, nullptr);
}

// Where external files may come from: the scene's folder (and below), unless the user allows
// any path. Files a .gltf names are read only through this check, so a downloaded scene cannot
// make the renderer read /etc/passwd or ../../secrets into a texture.
struct UriPolicy {
  std::filesystem::path folder;  // canonical
  bool allowExternal = false;
  std::string violation;  // the first refused path, for the error message
};

// Records why `filepath` may not be read, or returns true.
bool permitted(UriPolicy& policy, const std::string& filepath) {
  namespace fs = std::filesystem;
  if (filepath.find("://") != std::string::npos) {
    policy.violation =
        "\"" + filepath + "\": only data: URIs and relative file paths are supported";
    return false;
  }
  if (policy.allowExternal) return true;
  std::error_code ec;
  const fs::path resolved = fs::weakly_canonical(fs::absolute(filepath), ec);
  const fs::path relative = resolved.lexically_relative(policy.folder);
  if (!ec && !relative.empty() && *relative.begin() != "..") return true;
  policy.violation =
      "\"" + filepath + "\" is outside the scene's folder; pass --allow-external-uris to read it";
  return false;
}

// tinygltf looks for a URI beside the scene and then in the working directory; both lookups
// and the read itself go through the policy.
bool existsWithinFolder(const std::string& filepath, void* user) {
  auto* policy = static_cast<UriPolicy*>(user);
  if (!tinygltf::FileExists(filepath, nullptr)) return false;
  return permitted(*policy, filepath);
}

bool readWithinFolder(std::vector<unsigned char>* out, std::string* error,
                      const std::string& filepath, void* user) {
  auto* policy = static_cast<UriPolicy*>(user);
  if (!permitted(*policy, filepath)) {
    if (error) *error = policy->violation;
    return false;
  }
  return tinygltf::ReadWholeFile(out, error, filepath, nullptr);
}

// -----------------------------------------------------------------------------------------------
// The .glb container

constexpr std::uint32_t kGlbJsonChunk = 0x4E4F534A;  // "JSON", little-endian
constexpr std::uint32_t kGlbBinChunk = 0x004E4942;   // "BIN\0"

std::uint32_t le32(const unsigned char* b) {
  return std::uint32_t{b[0]} | std::uint32_t{b[1]} << 8 | std::uint32_t{b[2]} << 16 |
         std::uint32_t{b[3]} << 24;
}

// The bytes as text where they are printable, else as \xNN, for messages.
std::string printable(const unsigned char* bytes, std::size_t size) {
  static constexpr char kHex[] = "0123456789ABCDEF";
  std::string text;
  for (std::size_t i = 0; i < size; ++i) {
    const unsigned char c = bytes[i];
    if (c >= 0x20 && c < 0x7F && c != '"' && c != '\\') {
      text += static_cast<char>(c);
    } else {
      text += std::string("\\x") + kHex[c >> 4] + kHex[c & 15];
    }
  }
  return text;
}

// tinygltf says "Invalid glTF binary." for any broken header or chunk length; this says which
// field is wrong and where, from the 12-byte header and the 8-byte chunk headers alone.
void checkGlbLayout(std::ifstream& in, const std::string& file, std::uint64_t fileSize) {
  const auto fail = [&](const std::string& problem) { throw InputError(file + ": " + problem); };
  if (fileSize < 12) {
    fail("truncated .glb: " + std::to_string(fileSize) + " bytes, less than the 12-byte header");
  }
  unsigned char header[12];
  in.seekg(0);
  if (!in.read(reinterpret_cast<char*>(header), sizeof header)) {
    fail(std::string("cannot read glTF file: ") + std::strerror(errno));
  }
  const std::uint32_t version = le32(header + 4), length = le32(header + 8);
  if (version != 2) {
    fail("GLB header: version " + std::to_string(version) + " is not supported (expected 2)");
  }
  if (length > fileSize) {
    fail("GLB header: length " + std::to_string(length) + " is more than the file's " +
         std::to_string(fileSize) + " bytes (truncated file?)");
  }
  std::uint64_t at = 12;
  for (int index = 0; at < length; ++index) {
    const std::string chunk = "GLB chunk " + std::to_string(index);
    const std::string where = " at byte " + std::to_string(at);
    if (length - at < 8) fail(chunk + where + ": truncated chunk header");
    unsigned char chunkHeader[8];
    in.seekg(static_cast<std::streamoff>(at));
    if (!in.read(reinterpret_cast<char*>(chunkHeader), sizeof chunkHeader)) {
      fail(std::string("cannot read glTF file: ") + std::strerror(errno));
    }
    const std::uint32_t chunkLength = le32(chunkHeader), type = le32(chunkHeader + 4);
    const std::string name = (type == kGlbJsonChunk  ? chunk + " (JSON)"
                              : type == kGlbBinChunk ? chunk + " (BIN)"
                                                     : chunk) +
                             where;
    if (index == 0 && type != kGlbJsonChunk) {
      fail(name + ": type \"" + printable(chunkHeader + 4, 4) +
           "\", but the first chunk must be JSON");
    }
    if (chunkLength > length - at - 8) {
      fail(name + ": length " + std::to_string(chunkLength) + " extends past the end of the " +
           std::to_string(length) + " bytes of the file");
    }
    at += 8 + std::uint64_t{chunkLength};
  }
  if (length <= 12) fail("GLB: no JSON chunk");
}

// tinygltf stops at the first buffer or bufferView it cannot use without saying which one. It
// appends every one it has parsed before going on to the next, so the number parsed so far is
// the index of the one that failed.
std::string locateParseError(const tinygltf::Model& model, const std::string& message) {
  static constexpr std::string_view kNotFound = "File not found : ";
  if (message.starts_with(kNotFound)) {
    return at("buffers", model.buffers.size()) + ": uri \"" + message.substr(kNotFound.size()) +
           "\": no such file";
  }
  static constexpr std::string_view kBufferErrors[] = {"File read error",
                                                       "File is empty",
                                                       "File size mismatch",
                                                       "Failed to decode 'uri'",
                                                       "Invalid binary data in `Buffer'",
                                                       "'uri' is missing"};
  for (std::string_view prefix : kBufferErrors) {
    if (message.starts_with(prefix)) return at("buffers", model.buffers.size()) + ": " + message;
  }
  if (message.starts_with("Invalid `byteStride' value")) {
    return at("bufferViews", model.bufferViews.size()) + ": byteStride " +
           message.substr(message.rfind(' ') + 1) + " is not a multiple of 4 from 4 to 252";
  }
  return message;
}

bool hasGlbExtension(const std::filesystem::path& path) {
  std::string extension = path.extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return extension == ".glb";
}

tinygltf::Model readModel(const std::filesystem::path& path, const std::string& file,
                          std::vector<std::string>& warnings, bool* isBinary,
                          bool allowExternalUris) {
  std::error_code ec;
  const std::filesystem::file_status status = std::filesystem::status(path, ec);
  if (!std::filesystem::exists(status)) {
    throw InputError(file + ": cannot read glTF file: no such file");
  }
  if (std::filesystem::is_directory(status)) {
    throw InputError(file + ": cannot read glTF file: is a directory");
  }
  unsigned char magic[4] = {};
  // Decided by content, not by extension: some tools write .glb data under a .gltf name.
  bool binary = false;
  {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw InputError(file + ": cannot read glTF file: " + std::strerror(errno));
    in.read(reinterpret_cast<char*>(magic), sizeof magic);
    const auto got = static_cast<std::size_t>(in.gcount());
    const std::uint64_t size = std::filesystem::file_size(path, ec);
    binary = got == 4 && std::memcmp(magic, "glTF", 4) == 0;
    if (binary) {
      in.clear();
      checkGlbLayout(in, file, ec ? 0 : size);
    } else if (hasGlbExtension(path)) {
      // JSON under a .glb name is read as such; anything else would only give a JSON syntax
      // error about what is really a broken binary header.
      std::size_t first = 0;
      while (first < got && std::isspace(magic[first])) ++first;
      if (first == got || magic[first] != '{') {
        throw InputError(file + ": not a binary glTF: it starts with \"" + printable(magic, got) +
                         "\", not the magic \"glTF\"");
      }
    }
  }
  *isBinary = binary;

  tinygltf::TinyGLTF reader;
  reader.SetImageLoader(decodeUriImage, nullptr);
  UriPolicy policy{std::filesystem::weakly_canonical(std::filesystem::absolute(path)).parent_path(),
                   allowExternalUris,
                   {}};
  tinygltf::FsCallbacks files{&existsWithinFolder, &tinygltf::ExpandFilePath, &readWithinFolder,
                              &tinygltf::WriteWholeFile, &policy};
  reader.SetFsCallbacks(files);
  tinygltf::Model model;
  std::string error, warning;
  bool ok = false;
  try {
    ok = binary ? reader.LoadBinaryFromFile(&model, &error, &warning, path.string())
                : reader.LoadASCIIFromFile(&model, &error, &warning, path.string());
  } catch (const std::exception& e) {
    throw InputError(file + ": " + e.what());
  }
  // tinygltf tolerates an image it could not read; a refused file is an error all the same.
  if (!policy.violation.empty()) throw InputError(file + ": uri " + policy.violation);
  if (!ok) {
    std::vector<std::string> lines = nonEmptyLines(error);
    if (lines.empty()) lines = nonEmptyLines(warning);
    throw InputError(
        file + ": " +
        (lines.empty() ? "not a valid glTF file" : locateParseError(model, lines.front())));
  }
  // On success tinygltf's error text only holds tolerated oddities, so it is a warning too.
  // tinygltf repeats a message for every object it applies to; once each is enough.
  std::set<std::string> seen;
  for (const std::string* text : {&error, &warning}) {
    for (const std::string& line : nonEmptyLines(*text)) {
      if (seen.insert(line).second) warnings.push_back(file + ": " + line);
    }
  }
  return model;
}

void checkExtensions(const Context& ctx) {
  const auto supported = [](const std::string& name) {
    return std::find(std::begin(kSupportedExtensions), std::end(kSupportedExtensions), name) !=
           std::end(kSupportedExtensions);
  };
  for (const std::string& name : ctx.model.extensionsRequired) {
    if (!supported(name)) ctx.fail("extensionsRequired", name + " is not supported");
  }
  for (const std::string& name : ctx.model.extensionsUsed) {
    if (!supported(name)) ctx.warn("extensionsUsed: " + name + " is not supported; ignored");
  }
}

// -----------------------------------------------------------------------------------------------
// Accessors

enum class Normalize {
  AsFlagged,  // the accessor's `normalized` flag decides
  Integers,   // unsigned integer data is normalized (TEXCOORD_n and COLOR_n, glTF 3.7.2.1)
  Never,      // indices
};

struct AccessorValues {
  int components = 0;
  std::size_t count = 0;
  std::vector<double> values;  // count * components, element after element

  double get(std::size_t element, int component) const {
    return values[element * static_cast<std::size_t>(components) +
                  static_cast<std::size_t>(component)];
  }
};

// True when `count` elements of `elementSize` bytes, `stride` bytes apart starting at
// `offset`, end within `limit` bytes. Written to be free of overflow for any input.
bool fitsIn(std::uint64_t offset, std::uint64_t stride, std::uint64_t count,
            std::uint64_t elementSize, std::uint64_t limit) {
  if (offset > limit) return false;
  if (count == 0) return true;
  if (elementSize > limit - offset) return false;
  const std::uint64_t room = limit - offset - elementSize;
  return stride == 0 || count - 1 <= room / stride;
}

double decodeComponent(const unsigned char* p, int componentType, bool normalized) {
  const auto load = [p]<typename T>(T) {
    T value;
    std::memcpy(&value, p, sizeof value);
    return value;
  };
  switch (componentType) {
    case TINYGLTF_COMPONENT_TYPE_BYTE: {
      const double v = load(std::int8_t{});
      return normalized ? std::max(v / 127.0, -1.0) : v;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: {
      const double v = load(std::uint8_t{});
      return normalized ? v / 255.0 : v;
    }
    case TINYGLTF_COMPONENT_TYPE_SHORT: {
      const double v = load(std::int16_t{});
      return normalized ? std::max(v / 32767.0, -1.0) : v;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
      const double v = load(std::uint16_t{});
      return normalized ? v / 65535.0 : v;
    }
    case TINYGLTF_COMPONENT_TYPE_INT: {
      const double v = load(std::int32_t{});
      return normalized ? std::max(v / 2147483647.0, -1.0) : v;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: {
      const double v = load(std::uint32_t{});
      return normalized ? v / 4294967295.0 : v;
    }
    default:
      return load(float{});
  }
}

int componentSize(int componentType) {
  switch (componentType) {
    case TINYGLTF_COMPONENT_TYPE_BYTE:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
      return 1;
    case TINYGLTF_COMPONENT_TYPE_SHORT:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT:
      return 2;
    case TINYGLTF_COMPONENT_TYPE_INT:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
    case TINYGLTF_COMPONENT_TYPE_FLOAT:
      return 4;
    default:
      return 0;
  }
}

// Returns the bytes of bufferViews[index] after checking that they lie inside their buffer.
const unsigned char* bufferViewData(const Context& ctx, const std::string& object, int index,
                                    std::size_t* length) {
  ctx.checkIndex(object, "bufferView", index, ctx.model.bufferViews.size());
  const tinygltf::BufferView& view = ctx.model.bufferViews[static_cast<std::size_t>(index)];
  const std::string viewName = at("bufferViews", static_cast<std::size_t>(index));
  ctx.checkIndex(viewName, "buffer", view.buffer, ctx.model.buffers.size());
  const tinygltf::Buffer& buffer = ctx.model.buffers[static_cast<std::size_t>(view.buffer)];
  if (!fitsIn(view.byteOffset, 1, view.byteLength, 1, buffer.data.size())) {
    ctx.fail(viewName,
             "extends past the end of " + at("buffers", static_cast<std::size_t>(view.buffer)));
  }
  *length = view.byteLength;
  return buffer.data.data() + view.byteOffset;
}

// Reads accessors[index] as doubles, element after element, with byteStride, normalization and
// sparse substitution applied. Throws InputError for anything outside its buffer.
AccessorValues readAccessor(Context& ctx, int index, Normalize normalize) {
  const tinygltf::Accessor& accessor = ctx.model.accessors[static_cast<std::size_t>(index)];
  const std::string name = at("accessors", static_cast<std::size_t>(index));
  const int components =
      tinygltf::GetNumComponentsInType(static_cast<std::uint32_t>(accessor.type));
  const int size = componentSize(accessor.componentType);
  if (components <= 0) ctx.fail(name, "invalid type " + std::to_string(accessor.type));
  if (size == 0) ctx.fail(name, "invalid componentType " + std::to_string(accessor.componentType));
  const bool isUnsigned = accessor.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE ||
                          accessor.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT;
  const bool normalized = (normalize == Normalize::AsFlagged && accessor.normalized) ||
                          (normalize == Normalize::Integers && (accessor.normalized || isUnsigned));
  const std::size_t elementSize = static_cast<std::size_t>(components * size);

  // Bounds first: the count is only trusted once the data behind it is known to exist.
  const unsigned char* data = nullptr;
  std::size_t stride = elementSize;
  if (accessor.bufferView >= 0) {
    const std::string viewName = at("bufferViews", static_cast<std::size_t>(accessor.bufferView));
    std::size_t viewLength = 0;
    data = bufferViewData(ctx, name, accessor.bufferView, &viewLength);
    const std::size_t viewStride =
        ctx.model.bufferViews[static_cast<std::size_t>(accessor.bufferView)].byteStride;
    if (viewStride != 0 && viewStride < elementSize) {
      ctx.fail(name, "byteStride " + std::to_string(viewStride) + " of " + viewName +
                         " is smaller than the element size " + std::to_string(elementSize));
    }
    if (viewStride != 0) stride = viewStride;
    if (!fitsIn(accessor.byteOffset, stride, accessor.count, elementSize, viewLength)) {
      ctx.fail(name, "extends past the end of " + viewName);
    }
  } else if (accessor.count > kMaxCountWithoutBufferView - ctx.countWithoutBufferView) {
    ctx.fail(name, "count " + std::to_string(accessor.count) +
                       " is too large without a bufferView (accessors without one may hold " +
                       std::to_string(kMaxCountWithoutBufferView) + " elements in all)");
  } else {
    ctx.countWithoutBufferView += accessor.count;
  }

  AccessorValues out;
  out.components = components;
  out.count = accessor.count;
  out.values.assign(accessor.count * static_cast<std::size_t>(components), 0.0);
  const auto readElements = [&](const unsigned char* from, std::size_t step, std::size_t count,
                                auto&& destination) {
    for (std::size_t e = 0; e < count; ++e) {
      double* dst = &out.values[destination(e) * static_cast<std::size_t>(components)];
      for (int c = 0; c < components; ++c) {
        dst[c] = decodeComponent(from + e * step + static_cast<std::size_t>(c * size),
                                 accessor.componentType, normalized);
      }
    }
  };
  // Without a bufferView the accessor is all zeros (then usually sparse).
  if (data != nullptr) {
    readElements(data + accessor.byteOffset, stride, accessor.count,
                 [](std::size_t e) { return e; });
  }

  if (accessor.sparse.isSparse) {
    const auto& sparse = accessor.sparse;
    if (sparse.count < 0 || static_cast<std::size_t>(sparse.count) > accessor.count) {
      ctx.fail(name, "sparse.count " + std::to_string(sparse.count) + " exceeds count " +
                         std::to_string(accessor.count));
    }
    const auto count = static_cast<std::size_t>(sparse.count);
    const std::string indicesName = name + ".sparse.indices";
    const int indexSize = componentSize(sparse.indices.componentType);
    if (sparse.indices.componentType == TINYGLTF_COMPONENT_TYPE_BYTE ||
        sparse.indices.componentType == TINYGLTF_COMPONENT_TYPE_SHORT ||
        sparse.indices.componentType == TINYGLTF_COMPONENT_TYPE_FLOAT || indexSize == 0) {
      ctx.fail(indicesName,
               "invalid componentType " + std::to_string(sparse.indices.componentType));
    }
    std::size_t indicesLength = 0, valuesLength = 0;
    const unsigned char* indices =
        bufferViewData(ctx, indicesName, sparse.indices.bufferView, &indicesLength);
    const std::string valuesName = name + ".sparse.values";
    const unsigned char* values =
        bufferViewData(ctx, valuesName, sparse.values.bufferView, &valuesLength);
    if (sparse.indices.byteOffset < 0 ||
        !fitsIn(static_cast<std::size_t>(sparse.indices.byteOffset),
                static_cast<std::size_t>(indexSize), count, static_cast<std::size_t>(indexSize),
                indicesLength)) {
      ctx.fail(indicesName,
               "extends past the end of " +
                   at("bufferViews", static_cast<std::size_t>(sparse.indices.bufferView)));
    }
    if (sparse.values.byteOffset < 0 || !fitsIn(static_cast<std::size_t>(sparse.values.byteOffset),
                                                elementSize, count, elementSize, valuesLength)) {
      ctx.fail(valuesName,
               "extends past the end of " +
                   at("bufferViews", static_cast<std::size_t>(sparse.values.bufferView)));
    }
    indices += sparse.indices.byteOffset;
    std::vector<std::size_t> targets(count);
    for (std::size_t k = 0; k < count; ++k) {
      const double target = decodeComponent(indices + k * static_cast<std::size_t>(indexSize),
                                            sparse.indices.componentType, false);
      if (target >= static_cast<double>(accessor.count)) {
        ctx.fail(indicesName, "index " + std::to_string(static_cast<std::uint64_t>(target)) +
                                  " >= count " + std::to_string(accessor.count));
      }
      targets[k] = static_cast<std::size_t>(target);
    }
    readElements(values + sparse.values.byteOffset, elementSize, count,
                 [&targets](std::size_t k) { return targets[k]; });
  }
  return out;
}

// -----------------------------------------------------------------------------------------------
// Images, textures, materials

// Decodes an image stored in a bufferView (see decodeUriImage) into a copy of its description.
tinygltf::Image decodeBufferViewImage(const Context& ctx, std::size_t index,
                                      const std::string& object) {
  const tinygltf::Image& source = ctx.model.images[index];
  std::size_t length = 0;
  const unsigned char* bytes = bufferViewData(ctx, object, source.bufferView, &length);
  if (length == 0 || length > static_cast<std::size_t>(std::numeric_limits<int>::max())) {
    ctx.fail(object, "bufferView " + std::to_string(source.bufferView) + " has " +
                         std::to_string(length) + " bytes");
  }
  if (!isPngOrJpeg(bytes, length)) {
    ctx.fail(object, "unknown image format: glTF images are PNG or JPEG");
  }
  if (const std::string why = imageTooLarge(bytes, length); !why.empty()) ctx.fail(object, why);
  tinygltf::Image decoded = source;
  std::string error, warning;
  if (!tinygltf::LoadImageData(&decoded, static_cast<int>(index), &error, &warning, 0, 0, bytes,
                               static_cast<int>(length), nullptr)) {
    const std::vector<std::string> lines = nonEmptyLines(error);
    ctx.fail(object, lines.empty() ? "cannot decode the image data" : lines.front());
  }
  return decoded;
}

// Any channel count (1 = gray, 2 = gray + alpha) and 8 or 16 bits to RGBA8.
std::vector<std::uint8_t> toRgba8(const Context& ctx, const tinygltf::Image& decoded,
                                  const std::string& object) {
  const auto pixels =
      static_cast<std::size_t>(decoded.width) * static_cast<std::size_t>(decoded.height);
  const int channels = decoded.component;
  const int bytes = decoded.bits / 8;
  if (channels < 1 || channels > 4 || (decoded.bits != 8 && decoded.bits != 16) ||
      decoded.image.size() < pixels * static_cast<std::size_t>(channels * bytes)) {
    ctx.fail(object, "unsupported pixel format (" + std::to_string(channels) + " channels, " +
                         std::to_string(decoded.bits) + " bits)");
  }
  const unsigned char* data = decoded.image.data();
  const auto sample = [&](std::size_t index) -> std::uint8_t {
    if (bytes == 1) return data[index];
    std::uint16_t value;
    std::memcpy(&value, data + 2 * index, 2);
    return static_cast<std::uint8_t>((value * 255u + 32767u) / 65535u);
  };
  std::vector<std::uint8_t> rgba(pixels * 4);
  for (std::size_t p = 0; p < pixels; ++p) {
    const std::size_t in = p * static_cast<std::size_t>(channels);
    std::uint8_t* out = &rgba[p * 4];
    const bool gray = channels <= 2;
    out[0] = sample(in);
    out[1] = gray ? out[0] : sample(in + 1);
    out[2] = gray ? out[0] : sample(in + 2);
    out[3] = channels == 2 ? sample(in + 1) : channels == 4 ? sample(in + 3) : 255;
  }
  return rgba;
}

void convertImages(Context& ctx) {
  for (std::size_t i = 0; i < ctx.model.images.size(); ++i) {
    const tinygltf::Image& source = ctx.model.images[i];
    const bool externalFile = !source.uri.empty() && !tinygltf::IsDataURI(source.uri);
    Image image;
    image.name = !source.name.empty() ? source.name
                 : externalFile       ? source.uri
                                      : "image" + std::to_string(i);
    const std::string object = at("images", i) + " \"" + image.name + "\"";
    tinygltf::Image fromBufferView;
    if (source.bufferView >= 0) fromBufferView = decodeBufferViewImage(ctx, i, object);
    const tinygltf::Image& decoded = source.bufferView >= 0 ? fromBufferView : source;
    if (decoded.image.empty() || decoded.width <= 0 || decoded.height <= 0) {
      // tinygltf only warns when an external image is missing or undecodable.
      ctx.fail(object, externalFile ? "cannot read or decode " + source.uri
                                    : "cannot decode the image data");
    }
    image.width = decoded.width;
    image.height = decoded.height;
    image.rgba = toRgba8(ctx, decoded, object);
    ctx.scene.images.push_back(std::move(image));
  }
}

void convertTextures(Context& ctx) {
  const SamplerDesc defaults;
  for (std::size_t i = 0; i < ctx.model.textures.size(); ++i) {
    const tinygltf::Texture& source = ctx.model.textures[i];
    const std::string object = at("textures", i);
    Texture texture;
    if (source.source >= 0) {
      ctx.checkIndex(object, "image", source.source, ctx.model.images.size());
      texture.image = source.source;
    } else {
      // Images in formats we do not read come through extensions (KTX2, WebP).
      ctx.warn(object + ": no image in a supported format; the texture is ignored");
    }
    if (source.sampler >= 0) {
      ctx.checkIndex(object, "sampler", source.sampler, ctx.model.samplers.size());
      const tinygltf::Sampler& sampler =
          ctx.model.samplers[static_cast<std::size_t>(source.sampler)];
      texture.sampler.magFilter = sampler.magFilter >= 0 ? sampler.magFilter : defaults.magFilter;
      texture.sampler.minFilter = sampler.minFilter >= 0 ? sampler.minFilter : defaults.minFilter;
      texture.sampler.wrapS = sampler.wrapS;
      texture.sampler.wrapT = sampler.wrapT;
    }
    ctx.scene.textures.push_back(texture);
  }
}

// NormalTextureInfo, OcclusionTextureInfo and TextureInfo share these fields but no base class.
template <typename Info>
TextureSlot textureSlot(const Context& ctx, const std::string& object, const Info& info) {
  if (info.index < 0) return {};
  ctx.checkIndex(object, "texture", info.index, ctx.model.textures.size());
  if (info.texCoord < 0 || info.texCoord > 1) {
    ctx.warn(object + ": TEXCOORD_" + std::to_string(info.texCoord) +
             " is not supported; the texture is ignored");
    return {};
  }
  if (ctx.scene.textures[static_cast<std::size_t>(info.index)].image < 0) return {};
  return {info.index, info.texCoord};
}

template <glm::length_t N>
glm::vec<N, float> factor(const std::vector<double>& values, glm::vec<N, float> fallback) {
  if (values.size() != N) return fallback;
  glm::vec<N, float> out;
  for (glm::length_t i = 0; i < N; ++i)
    out[i] = static_cast<float>(values[static_cast<std::size_t>(i)]);
  return out;
}

void convertMaterials(Context& ctx) {
  for (std::size_t i = 0; i < ctx.model.materials.size(); ++i) {
    const tinygltf::Material& source = ctx.model.materials[i];
    const std::string object = at("materials", i);
    const tinygltf::PbrMetallicRoughness& pbr = source.pbrMetallicRoughness;
    Material material;
    material.name = source.name;
    material.baseColorFactor = factor<4>(pbr.baseColorFactor, material.baseColorFactor);
    material.baseColorTexture =
        textureSlot(ctx, object + ".baseColorTexture", pbr.baseColorTexture);
    material.metallicFactor = static_cast<float>(pbr.metallicFactor);
    material.roughnessFactor = static_cast<float>(pbr.roughnessFactor);
    material.metallicRoughnessTexture =
        textureSlot(ctx, object + ".metallicRoughnessTexture", pbr.metallicRoughnessTexture);
    material.normalTexture = textureSlot(ctx, object + ".normalTexture", source.normalTexture);
    material.normalScale = static_cast<float>(source.normalTexture.scale);
    material.occlusionTexture =
        textureSlot(ctx, object + ".occlusionTexture", source.occlusionTexture);
    material.occlusionStrength = static_cast<float>(source.occlusionTexture.strength);
    material.emissiveFactor = factor<3>(source.emissiveFactor, material.emissiveFactor);
    material.emissiveTexture =
        textureSlot(ctx, object + ".emissiveTexture", source.emissiveTexture);
    const auto strength = source.extensions.find("KHR_materials_emissive_strength");
    if (strength != source.extensions.end() && strength->second.IsObject() &&
        strength->second.Get("emissiveStrength").IsNumber()) {
      material.emissiveStrength =
          static_cast<float>(strength->second.Get("emissiveStrength").GetNumberAsDouble());
    }
    if (source.alphaMode == "MASK") {
      material.alphaMode = AlphaMode::Mask;
    } else if (source.alphaMode == "BLEND") {
      material.alphaMode = AlphaMode::Blend;
    } else if (source.alphaMode != "OPAQUE" && !source.alphaMode.empty()) {
      ctx.warn(object + ": unknown alphaMode \"" + source.alphaMode + "\"; using OPAQUE");
    }
    material.alphaCutoff = static_cast<float>(source.alphaCutoff);
    material.doubleSided = source.doubleSided;
    ctx.scene.materials.push_back(std::move(material));
  }
}

// -----------------------------------------------------------------------------------------------
// Primitives

std::string componentTypeName(int componentType) {
  switch (componentType) {
    case TINYGLTF_COMPONENT_TYPE_BYTE:
      return "BYTE";
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
      return "UNSIGNED_BYTE";
    case TINYGLTF_COMPONENT_TYPE_SHORT:
      return "SHORT";
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT:
      return "UNSIGNED_SHORT";
    case TINYGLTF_COMPONENT_TYPE_INT:
      return "INT";
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
      return "UNSIGNED_INT";
    case TINYGLTF_COMPONENT_TYPE_FLOAT:
      return "FLOAT";
    default:
      return std::to_string(componentType);
  }
}

// The component types glTF 2.0 allows for vertex attributes (3.7.2.1). Others would be read,
// but as numbers the file never meant (a POSITION of unsigned bytes is what
// KHR_mesh_quantization allows, and that extension is not supported).
constexpr int kFloatOnly[] = {TINYGLTF_COMPONENT_TYPE_FLOAT};
constexpr int kFloatOrNormalized[] = {TINYGLTF_COMPONENT_TYPE_FLOAT,
                                      TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE,
                                      TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT};

// Reads one vertex attribute of a primitive, checking its type, component type and element
// count.
AccessorValues readAttribute(Context& ctx, const std::string& object,
                             const tinygltf::Primitive& primitive, const std::string& semantic,
                             std::initializer_list<int> types, std::span<const int> componentTypes,
                             std::size_t vertexCount, Normalize normalize) {
  const auto found = primitive.attributes.find(semantic);
  if (found == primitive.attributes.end()) return {};
  const std::string attribute = object + ".attributes." + semantic;
  ctx.checkIndex(attribute, "accessor", found->second, ctx.model.accessors.size());
  const tinygltf::Accessor& accessor = ctx.model.accessors[static_cast<std::size_t>(found->second)];
  if (std::find(types.begin(), types.end(), accessor.type) == types.end()) {
    ctx.fail(attribute, at("accessors", static_cast<std::size_t>(found->second)) +
                            " has the wrong type for " + semantic);
  }
  if (std::find(componentTypes.begin(), componentTypes.end(), accessor.componentType) ==
      componentTypes.end()) {
    std::string allowed;
    for (std::size_t i = 0; i < componentTypes.size(); ++i) {
      allowed += (i == 0                           ? ""
                  : i + 1 == componentTypes.size() ? " or "
                                                   : ", ") +
                 componentTypeName(componentTypes[i]);
    }
    ctx.fail(attribute, at("accessors", static_cast<std::size_t>(found->second)) +
                            " has componentType " + componentTypeName(accessor.componentType) +
                            "; " + semantic + " must be " + allowed);
  }
  if (vertexCount != SIZE_MAX && accessor.count != vertexCount) {
    ctx.fail(attribute, "has " + std::to_string(accessor.count) + " elements but POSITION has " +
                            std::to_string(vertexCount));
  }
  return readAccessor(ctx, found->second, normalize);
}

template <int N>
std::vector<glm::vec<N, float>> toVectors(const AccessorValues& values) {
  std::vector<glm::vec<N, float>> out(values.count, glm::vec<N, float>(0.0f));
  for (std::size_t e = 0; e < values.count; ++e) {
    for (int c = 0; c < std::min(N, values.components); ++c) {
      out[e][c] = static_cast<float>(values.get(e, c));
    }
  }
  return out;
}

// Turns strips and fans into lists, following the glTF spec's vertex order (3.7.2.1), which
// keeps every triangle's winding the same as the first one's.
std::vector<std::uint32_t> toTriangleList(const std::vector<std::uint32_t>& in, int mode) {
  if (mode == TINYGLTF_MODE_TRIANGLES) return in;
  std::vector<std::uint32_t> out;
  for (std::size_t i = 0; i + 2 < in.size(); ++i) {
    std::uint32_t a, b, c;
    if (mode == TINYGLTF_MODE_TRIANGLE_STRIP) {
      a = in[i];
      b = in[i + 1 + i % 2];
      c = in[i + 2 - i % 2];
    } else {
      a = in[i + 1];
      b = in[i + 2];
      c = in[0];
    }
    // Strips are often stitched together with repeated vertices; those triangles are empty.
    if (a == b || b == c || a == c) continue;
    out.insert(out.end(), {a, b, c});
  }
  return out;
}

std::optional<Mesh> convertPrimitive(Context& ctx, std::size_t meshIndex, std::size_t primIndex) {
  const tinygltf::Mesh& source = ctx.model.meshes[meshIndex];
  const tinygltf::Primitive& primitive = source.primitives[primIndex];
  const std::string object = at("meshes", meshIndex) + "." + at("primitives", primIndex);
  const int mode = primitive.mode < 0 ? TINYGLTF_MODE_TRIANGLES : primitive.mode;
  if (mode < TINYGLTF_MODE_TRIANGLES) {
    static constexpr const char* kNames[] = {"points", "lines", "line loop", "line strip"};
    ctx.warn(object + ": " + kNames[mode] + " primitives are not drawn");
    return std::nullopt;
  }
  if (mode > TINYGLTF_MODE_TRIANGLE_FAN) ctx.fail(object, "invalid mode " + std::to_string(mode));
  if (primitive.attributes.count("POSITION") == 0) {
    ctx.warn(object + ": no POSITION attribute; not drawn");
    return std::nullopt;
  }
  if (!primitive.targets.empty() && !ctx.warnedMorphTargets) {
    ctx.warn(object + ": morph targets are not applied (base shape drawn; warned once)");
    ctx.warnedMorphTargets = true;
  }

  Mesh mesh;
  mesh.name = (source.name.empty() ? "mesh" + std::to_string(meshIndex) : source.name) + "/" +
              std::to_string(primIndex);
  if (primitive.material >= 0) {
    ctx.checkIndex(object, "material", primitive.material, ctx.model.materials.size());
    mesh.material = primitive.material;
  }

  const int vec2 = TINYGLTF_TYPE_VEC2, vec3 = TINYGLTF_TYPE_VEC3, vec4 = TINYGLTF_TYPE_VEC4;
  mesh.positions = toVectors<3>(readAttribute(ctx, object, primitive, "POSITION", {vec3},
                                              kFloatOnly, SIZE_MAX, Normalize::AsFlagged));
  const std::size_t n = mesh.positions.size();
  // Non-finite positions would poison bounds, cameras and shadow ranges: skip the primitive.
  if (std::any_of(mesh.positions.begin(), mesh.positions.end(), [](const glm::vec3& p) {
        return !std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z);
      })) {
    ctx.warn(object + ": POSITION has non-finite values; primitive not drawn");
    return std::nullopt;
  }
  mesh.normals = toVectors<3>(
      readAttribute(ctx, object, primitive, "NORMAL", {vec3}, kFloatOnly, n, Normalize::AsFlagged));
  for (glm::vec3& normal : mesh.normals) {
    const float length = glm::length(normal);
    if (length > 0.0f && std::isfinite(length)) normal /= length;
  }
  mesh.tangents = toVectors<4>(readAttribute(ctx, object, primitive, "TANGENT", {vec4}, kFloatOnly,
                                             n, Normalize::AsFlagged));
  mesh.uv0 = toVectors<2>(readAttribute(ctx, object, primitive, "TEXCOORD_0", {vec2},
                                        kFloatOrNormalized, n, Normalize::Integers));
  mesh.uv1 = toVectors<2>(readAttribute(ctx, object, primitive, "TEXCOORD_1", {vec2},
                                        kFloatOrNormalized, n, Normalize::Integers));
  const AccessorValues colors = readAttribute(ctx, object, primitive, "COLOR_0", {vec3, vec4},
                                              kFloatOrNormalized, n, Normalize::Integers);
  mesh.colors = toVectors<4>(colors);
  if (colors.components == 3) {
    for (glm::vec4& color : mesh.colors) color.a = 1.0f;
  }

  std::vector<std::uint32_t> indices;
  if (primitive.indices >= 0) {
    ctx.checkIndex(object + ".indices", "accessor", primitive.indices, ctx.model.accessors.size());
    const tinygltf::Accessor& accessor =
        ctx.model.accessors[static_cast<std::size_t>(primitive.indices)];
    if (accessor.type != TINYGLTF_TYPE_SCALAR ||
        (accessor.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE &&
         accessor.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
         accessor.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT)) {
      ctx.fail(object + ".indices", at("accessors", static_cast<std::size_t>(primitive.indices)) +
                                        " must be SCALAR unsigned byte, short or int");
    }
    const AccessorValues values = readAccessor(ctx, primitive.indices, Normalize::Never);
    indices.reserve(values.count);
    for (double value : values.values) {
      if (value >= static_cast<double>(n)) {
        ctx.fail(object, "index " + std::to_string(static_cast<std::uint64_t>(value)) +
                             " >= vertex count " + std::to_string(n));
      }
      indices.push_back(static_cast<std::uint32_t>(value));
    }
  } else {
    indices.resize(n);
    for (std::size_t i = 0; i < n; ++i) indices[i] = static_cast<std::uint32_t>(i);
  }
  mesh.indices = toTriangleList(indices, mode);
  if (mesh.indices.size() % 3 != 0) {
    ctx.warn(object + ": " + std::to_string(mesh.indices.size()) +
             " indices is not a multiple of 3; the last triangle is dropped");
    mesh.indices.resize(mesh.indices.size() / 3 * 3);
  }

  if (mesh.normals.empty()) {
    mesh.tangents.clear();  // the spec says to ignore tangents given without normals
    generateNormals(mesh);
    ctx.warn(object + ": no normals; generated flat normals");
  }
  if (mesh.tangents.empty() && mesh.material >= 0) {
    const TextureSlot& normalMap =
        ctx.scene.materials[static_cast<std::size_t>(mesh.material)].normalTexture;
    const std::vector<glm::vec2>& uvs = normalMap.texCoord == 0 ? mesh.uv0 : mesh.uv1;
    if (normalMap.texture >= 0 && !uvs.empty()) generateTangents(mesh, uvs);
  }
  for (const glm::vec3& p : mesh.positions) mesh.bounds.extend(p);
  return mesh;
}

// -----------------------------------------------------------------------------------------------
// Node hierarchy

glm::mat4 localMatrix(const Context& ctx, std::size_t nodeIndex) {
  const tinygltf::Node& node = ctx.model.nodes[nodeIndex];
  const std::string object = at("nodes", nodeIndex);
  if (!node.matrix.empty()) {
    if (node.matrix.size() != 16) ctx.fail(object, "matrix must have 16 numbers");
    glm::mat4 m;
    for (int i = 0; i < 16; ++i) {
      glm::value_ptr(m)[i] = static_cast<float>(node.matrix[static_cast<std::size_t>(i)]);
    }
    return m;  // both column-major
  }
  glm::mat4 m(1.0f);
  if (!node.translation.empty()) {
    if (node.translation.size() != 3) ctx.fail(object, "translation must have 3 numbers");
    m = glm::translate(m, factor<3>(node.translation, glm::vec3(0.0f)));
  }
  if (!node.rotation.empty()) {
    if (node.rotation.size() != 4) ctx.fail(object, "rotation must have 4 numbers");
    const glm::vec4 xyzw = factor<4>(node.rotation, glm::vec4(0, 0, 0, 1));
    glm::quat q(xyzw.w, xyzw.x, xyzw.y, xyzw.z);
    // Exporters round quaternions; mat4_cast expects unit length.
    if (glm::length(q) > 0.0f) m *= glm::mat4_cast(glm::normalize(q));
  }
  if (!node.scale.empty()) {
    if (node.scale.size() != 3) ctx.fail(object, "scale must have 3 numbers");
    m = glm::scale(m, factor<3>(node.scale, glm::vec3(1.0f)));
  }
  return m;
}

// The node's KHR_lights_punctual light index, or -1.
int lightOf(const Context& ctx, std::size_t nodeIndex) {
  const tinygltf::Node& node = ctx.model.nodes[nodeIndex];
  const auto found = node.extensions.find("KHR_lights_punctual");
  if (found == node.extensions.end() || !found->second.IsObject() ||
      !found->second.Get("light").IsNumber()) {
    return -1;
  }
  const int light = found->second.Get("light").GetNumberAsInt();
  ctx.checkIndex(at("nodes", nodeIndex) + ".extensions.KHR_lights_punctual", "light", light,
                 ctx.model.lights.size());
  return light;
}

Light convertLight(const Context& ctx, int index, const glm::mat4& world,
                   std::set<std::string>& usedNames) {
  const tinygltf::Light& source = ctx.model.lights[static_cast<std::size_t>(index)];
  const std::string object = "KHR_lights_punctual." + at("lights", static_cast<std::size_t>(index));
  Light light;
  // Light names must be unique within a render; a light placed by two nodes appears twice.
  const std::string base = source.name.empty() ? "gltf_light" + std::to_string(index) : source.name;
  light.name = base;
  for (int k = 2; !usedNames.insert(light.name).second; ++k)
    light.name = base + "_" + std::to_string(k);
  if (source.type == "point") {
    light.type = LightType::Point;
  } else if (source.type == "spot") {
    light.type = LightType::Spot;
    light.innerConeAngle = static_cast<float>(source.spot.innerConeAngle);
    light.outerConeAngle = static_cast<float>(source.spot.outerConeAngle);
  } else if (source.type == "directional") {
    light.type = LightType::Directional;
  } else {
    ctx.fail(object, "unknown type \"" + source.type + "\"");
  }
  light.color = factor<3>(source.color, light.color);
  light.intensity = static_cast<float>(source.intensity);
  light.range = source.range > 0.0 ? static_cast<float>(source.range) : 0.0f;
  light.position = glm::vec3(world[3]);
  const glm::vec3 direction = glm::mat3(world) * glm::vec3(0.0f, 0.0f, -1.0f);
  if (glm::length(direction) > 0.0f) light.direction = glm::normalize(direction);
  light.origin = "glTF";
  return light;
}

Camera convertCamera(const Context& ctx, std::size_t nodeIndex, const glm::mat4& world) {
  const tinygltf::Node& node = ctx.model.nodes[nodeIndex];
  ctx.checkIndex(at("nodes", nodeIndex), "camera", node.camera, ctx.model.cameras.size());
  const tinygltf::Camera& source = ctx.model.cameras[static_cast<std::size_t>(node.camera)];
  Camera camera;
  camera.name = source.name.empty() ? node.name : source.name;
  camera.nodeName = node.name;
  camera.index = node.camera;
  camera.world = world;
  if (source.type == "orthographic") {
    camera.orthographic = true;
    camera.xmag = static_cast<float>(source.orthographic.xmag);
    camera.ymag = static_cast<float>(source.orthographic.ymag);
    camera.znear = static_cast<float>(source.orthographic.znear);
    camera.zfar = static_cast<float>(source.orthographic.zfar);
  } else {
    // yfov and znear are required and positive; keep usable defaults when a file breaks that.
    if (source.perspective.yfov > 0.0) camera.yfov = static_cast<float>(source.perspective.yfov);
    if (source.perspective.znear > 0.0) {
      camera.znear = static_cast<float>(source.perspective.znear);
    }
    camera.aspectRatio = static_cast<float>(std::max(source.perspective.aspectRatio, 0.0));
    camera.zfar = static_cast<float>(std::max(source.perspective.zfar, 0.0));
  }
  return camera;
}

bool isFinite(const glm::mat4& m) {
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r)
      if (!std::isfinite(m[c][r])) return false;
  return true;
}

class SceneBuilder {
 public:
  explicit SceneBuilder(Context& ctx) : ctx_(ctx) {
    for (const tinygltf::Mesh& mesh : ctx.model.meshes) {
      meshOf_.emplace_back(mesh.primitives.size(), kNotConverted);
    }
  }

  // Depth-first, parents before children, without recursion so that deep hierarchies cannot
  // overflow the stack.
  void traverse(const std::vector<int>& roots, const std::string& rootsObject) {
    const std::size_t nodeCount = ctx_.model.nodes.size();
    std::vector<char> onPath(nodeCount, 0), visited(nodeCount, 0);
    struct Frame {
      std::size_t node;
      glm::mat4 world;
      std::size_t nextChild;
    };
    std::vector<Frame> stack;
    const auto enter = [&](int node, const glm::mat4& parentWorld, const std::string& referrer) {
      ctx_.checkIndex(referrer, "node", node, nodeCount);
      const auto index = static_cast<std::size_t>(node);
      if (onPath[index]) ctx_.fail(at("nodes", index), "the node hierarchy has a cycle");
      // glTF nodes have at most one parent; a second path would draw the subtree twice.
      if (visited[index]) ctx_.fail(at("nodes", index), "is reachable along two paths");
      onPath[index] = visited[index] = 1;
      ++ctx_.scene.source.reachedNodes;
      const glm::mat4 world = parentWorld * localMatrix(ctx_, index);
      if (!isFinite(world)) {
        // A NaN or infinite transform would place everything below it nowhere.
        ctx_.warn(at("nodes", index) +
                  ": non-finite transform; the node and its children are "
                  "not drawn");
        onPath[index] = 0;
        return;
      }
      visit(index, world);
      stack.push_back({index, world, 0});
    };
    for (int root : roots) {
      enter(root, glm::mat4(1.0f), rootsObject);
      while (!stack.empty()) {
        Frame& top = stack.back();
        const std::vector<int>& children = ctx_.model.nodes[top.node].children;
        if (top.nextChild == children.size()) {
          onPath[top.node] = 0;
          stack.pop_back();
          continue;
        }
        const int child = children[top.nextChild++];
        const glm::mat4 parentWorld = top.world;  // `top` dies when the stack grows
        enter(child, parentWorld, at("nodes", top.node) + ".children");
      }
    }
    // Cameras keep traversal order within one glTF camera.
    std::stable_sort(ctx_.scene.cameras.begin(), ctx_.scene.cameras.end(),
                     [](const Camera& a, const Camera& b) { return a.index < b.index; });
  }

 private:
  static constexpr int kNotConverted = -2;  // -1: converted, but not drawn

  void visit(std::size_t nodeIndex, const glm::mat4& world) {
    const tinygltf::Node& node = ctx_.model.nodes[nodeIndex];
    if (node.mesh >= 0) {
      ctx_.checkIndex(at("nodes", nodeIndex), "mesh", node.mesh, ctx_.model.meshes.size());
      if (node.skin >= 0 && !ctx_.warnedSkins) {
        ctx_.warn(at("nodes", nodeIndex) +
                  ": skins are not applied (bind pose drawn; warned once)");
        ctx_.warnedSkins = true;
      }
      const auto meshIndex = static_cast<std::size_t>(node.mesh);
      for (std::size_t p = 0; p < meshOf_[meshIndex].size(); ++p) {
        const int mesh = sceneMesh(meshIndex, p);
        if (mesh < 0) continue;
        ctx_.scene.instances.push_back({mesh, world, static_cast<int>(nodeIndex)});
        ctx_.scene.bounds.extend(
            ctx_.scene.meshes[static_cast<std::size_t>(mesh)].bounds.transformed(world));
      }
    }
    if (node.camera >= 0) ctx_.scene.cameras.push_back(convertCamera(ctx_, nodeIndex, world));
    if (const int light = lightOf(ctx_, nodeIndex); light >= 0) {
      ctx_.scene.lights.push_back(convertLight(ctx_, light, world, lightNames_));
    }
  }

  // Each glTF primitive becomes one Scene mesh however many nodes use it.
  int sceneMesh(std::size_t meshIndex, std::size_t primIndex) {
    int& slot = meshOf_[meshIndex][primIndex];
    if (slot == kNotConverted) {
      std::optional<Mesh> mesh = convertPrimitive(ctx_, meshIndex, primIndex);
      slot = -1;
      if (mesh) {
        ctx_.scene.meshes.push_back(std::move(*mesh));
        slot = static_cast<int>(ctx_.scene.meshes.size()) - 1;
      }
    }
    return slot;
  }

  Context& ctx_;
  std::vector<std::vector<int>> meshOf_;  // [glTF mesh][primitive] -> Scene::meshes index
  std::set<std::string> lightNames_;
};

// Root nodes of the scene to draw, and how messages name that list.
std::pair<std::vector<int>, std::string> sceneRoots(const Context& ctx,
                                                    const GltfLoadOptions& options) {
  const tinygltf::Model& model = ctx.model;
  const bool chosen = options.sceneIndex >= 0;
  if (model.scenes.empty()) {
    if (options.sceneIndex > 0) {
      ctx.fail("--scene " + std::to_string(options.sceneIndex), "the file has no scenes");
    }
    // The spec allows a file without scenes; drawing every root node is what viewers do.
    std::vector<char> isChild(model.nodes.size(), 0);
    for (const tinygltf::Node& node : model.nodes) {
      for (int child : node.children) {
        if (child >= 0 && static_cast<std::size_t>(child) < isChild.size()) {
          isChild[static_cast<std::size_t>(child)] = 1;
        }
      }
    }
    std::vector<int> roots;
    for (std::size_t i = 0; i < model.nodes.size(); ++i) {
      if (!isChild[i]) roots.push_back(static_cast<int>(i));
    }
    if (!model.nodes.empty()) {
      ctx.warn("the file has no scenes; drawing all " + plural(roots.size(), "root node"));
    }
    return {roots, "nodes"};
  }
  const int index = chosen ? options.sceneIndex : std::max(model.defaultScene, 0);
  if (static_cast<std::size_t>(index) >= model.scenes.size()) {
    ctx.fail(chosen ? "--scene " + std::to_string(index) : "scene " + std::to_string(index),
             "the file has " + plural(model.scenes.size(), "scene"));
  }
  ctx.scene.source.sceneIndex = index;
  const std::string object = at("scenes", static_cast<std::size_t>(index));
  return {model.scenes[static_cast<std::size_t>(index)].nodes, object + ".nodes"};
}

// The files this scene reads: itself and the external (non data:) URIs of buffers and images.
std::vector<std::string> referencedFiles(const std::filesystem::path& path,
                                         const tinygltf::Model& model) {
  std::vector<std::string> files = {path.string()};
  auto add = [&](const std::string& uri) {
    if (uri.empty() || tinygltf::IsDataURI(uri)) return;
    files.push_back((path.parent_path() / uri).string());
  };
  for (const tinygltf::Buffer& buffer : model.buffers) add(buffer.uri);
  for (const tinygltf::Image& image : model.images) add(image.uri);
  return files;
}

SourceSummary summarize(const tinygltf::Model& model, bool binary) {
  SourceSummary source;
  source.format = binary ? "glb" : "gltf";
  source.version = model.asset.version;
  source.minVersion = model.asset.minVersion;
  source.generator = model.asset.generator;
  source.copyright = model.asset.copyright;
  source.sceneCount = static_cast<int>(model.scenes.size());
  source.fileNodes = static_cast<int>(model.nodes.size());
  source.gltfMeshes = static_cast<int>(model.meshes.size());
  for (const tinygltf::Mesh& mesh : model.meshes) {
    source.gltfPrimitives += static_cast<int>(mesh.primitives.size());
  }
  return source;
}

}  // namespace

Scene loadGltf(const std::filesystem::path& path, const GltfLoadOptions& options) {
  Scene scene;
  scene.path = path.string();
  bool binary = false;
  const tinygltf::Model model =
      readModel(path, scene.path, scene.warnings, &binary, options.allowExternalUris);
  scene.inputFiles = referencedFiles(path, model);
  scene.source = summarize(model, binary);
  Context ctx{scene.path, model, scene};
  checkExtensions(ctx);
  const auto [roots, rootsObject] = sceneRoots(ctx, options);
  convertImages(ctx);
  convertTextures(ctx);
  convertMaterials(ctx);
  SceneBuilder(ctx).traverse(roots, rootsObject);
  return scene;
}

}  // namespace omnishadow
