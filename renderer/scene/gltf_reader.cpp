#include "renderer/scene/gltf_reader.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <iterator>
#include <optional>
#include <set>
#include <string_view>

#include "renderer/core/errors.h"
#include "renderer/core/input_file.h"
#include "renderer/core/json_depth.h"
#include "renderer/scene/gltf_context.h"
#include "renderer/scene/gltf_data_uris.h"
#include "renderer/scene/gltf_extension_policy.h"
#include "renderer/scene/gltf_file_safety.h"
#include "renderer/scene/gltf_json_checks.h"

namespace omnishadow::gltf_detail {

namespace {

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
void checkGlbLayout(const std::string& data, const std::string& file) {
  const auto fail = [&](const std::string& problem) { throw InputError(file + ": " + problem); };
  const std::uint64_t fileSize = data.size();
  if (fileSize < 12) {
    fail("truncated .glb: " + std::to_string(fileSize) + " bytes, less than the 12-byte header");
  }
  const auto* header = reinterpret_cast<const unsigned char*>(data.data());
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
    const auto* chunkHeader = header + at;
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
  // tinygltf's words for an image's data: URI; "Failed to decode 'uri'" alone is a buffer's.
  if (message.starts_with("Failed to decode 'uri' for image[")) {
    return at("images", model.images.size()) + ": " + message;
  }
  // A buffer's names its whole data: URI, megabytes of base64 in a one-line message.
  static constexpr std::string_view kUndecodedBuffer = "Failed to decode 'uri' : ";
  static constexpr std::string_view kInBuffer = " in Buffer";
  if (message.starts_with(kUndecodedBuffer) && message.ends_with(kInBuffer)) {
    constexpr std::size_t kShown = 60;
    std::string uri = message.substr(kUndecodedBuffer.size(),
                                     message.size() - kUndecodedBuffer.size() - kInBuffer.size());
    if (uri.size() > kShown) uri = uri.substr(0, kShown) + "...";
    return at("buffers", model.buffers.size()) + ": " + std::string(kUndecodedBuffer) + uri +
           std::string(kInBuffer);
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

// `glb` (its layout checked) with its JSON chunk replaced by `json`, padded with spaces.
std::string glbWithJson(const std::string& glb, std::string json) {
  while (json.size() % 4 != 0) json += ' ';
  const auto* bytes = reinterpret_cast<const unsigned char*>(glb.data());
  const std::size_t rest = 20 + std::size_t{le32(bytes + 12)};
  const std::size_t end = std::min<std::size_t>(glb.size(), le32(bytes + 8));
  std::string out = glb.substr(0, 20) + json + glb.substr(rest, end > rest ? end - rest : 0);
  const auto put32 = [&](std::size_t at, std::size_t value) {
    for (int i = 0; i < 4; ++i) out[at + i] = static_cast<char>((value >> (8 * i)) & 0xFF);
  };
  put32(8, out.size());
  put32(12, json.size());
  return out;
}

// tinygltf takes the size as an unsigned int; a scene is read whole into memory.
constexpr std::uint64_t kMaxSceneFileBytes = std::uint64_t{2} << 30;

// readInputFile's checks, with the scene's name as the caller shows it.
std::string readInputFileNamed(const std::filesystem::path& path, const std::string& file,
                               std::uint64_t maxBytes, std::string_view what) {
  std::string content;
  if (const std::string why = readRegularFile(path, maxBytes, content); !why.empty()) {
    throw InputError(file + ": cannot read " + std::string(what) + ": " + why);
  }
  return content;
}

// `file` (a .gltf's text, or a .glb, its layout checked by checkGlbLayout) with its JSON
// replaced by what `rewrite` makes of it, or nullopt where `rewrite` gives nullopt (the JSON
// stays as it is).
template <typename Rewrite>
std::optional<std::string> withJsonRewritten(const std::string& file, bool binary,
                                             const Rewrite& rewrite) {
  if (!binary) return rewrite(std::string_view(file));
  if (file.size() < 20) return std::nullopt;
  const auto* header = reinterpret_cast<const unsigned char*>(file.data());
  std::optional<std::string> json = rewrite(std::string_view(file).substr(20, le32(header + 12)));
  if (!json) return std::nullopt;
  return glbWithJson(file, *std::move(json));
}

// The file with its JSON rewritten for tinygltf (gltf_compressed_json.h), or nullopt when
// tinygltf reads it as it is.
std::optional<std::string> rewriteForCompression(const std::string& bytes, bool binary,
                                                 CompressionFixups& fixups) {
  return withJsonRewritten(bytes, binary, [&](std::string_view json) {
    return rewriteCompressedJson(json, binary, fixups);
  });
}

// The file with its data: URIs taken into `dataUris`, or nullopt where none was taken.
std::optional<std::string> takeDataUris(const std::string& file, bool binary, DataUris& dataUris) {
  return withJsonRewritten(file, binary,
                           [&](std::string_view json) { return dataUris.take(json); });
}

bool hasGlbExtension(const std::filesystem::path& path) {
  std::string extension = path.extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return extension == ".glb";
}

}  // namespace

tinygltf::Model readModel(const std::filesystem::path& path, const std::string& file,
                          std::vector<std::string>& warnings, bool* isBinary,
                          bool allowExternalUris, CompressionFixups& fixups) {
  // Read once, through the checks every input gets (a FIFO or /dev/zero as the scene must
  // neither block nor fill memory); tinygltf then parses from memory.
  const std::string data = readInputFileNamed(path, file, kMaxSceneFileBytes, "glTF file");
  if (data.empty()) throw InputError(file + ": cannot read glTF file: the file is empty");
  const auto* magic = reinterpret_cast<const unsigned char*>(data.data());
  const std::size_t got = std::min<std::size_t>(data.size(), 4);
  // Decided by content, not by extension: some tools write .glb data under a .gltf name.
  const bool binary = got == 4 && std::memcmp(magic, "glTF", 4) == 0;
  std::string_view json = data;
  if (binary) {
    checkGlbLayout(data, file);
    json = std::string_view(data).substr(20, le32(magic + 12));
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
  if (const std::size_t deep = findExcessiveNesting(json); deep != std::string_view::npos) {
    throw InputError(file + (binary ? ": GLB JSON chunk:" : ":") +
                     excessiveNestingMessage(json, deep));
  }
  // What tinygltf would drop or misreport is checked on the JSON itself; what it would refuse
  // wrongly is hidden from it in a rewritten copy.
  const JsonReview review = reviewGltfJson(json, file, binary);
  for (const std::string& warning : review.warnings) warnings.push_back(file + ": " + warning);
  std::string rewritten;
  if (!review.rewritten.empty()) {
    rewritten = binary ? glbWithJson(data, review.rewritten) : review.rewritten;
  }
  // The data: URIs decoded here, not by tinygltf (gltf_data_uris.h).
  DataUris dataUris;
  if (std::optional<std::string> taken =
          takeDataUris(rewritten.empty() ? data : rewritten, binary, dataUris)) {
    rewritten = *std::move(taken);
  }
  const std::string& parsed = rewritten.empty() ? data : rewritten;
  *isBinary = binary;

  tinygltf::TinyGLTF reader;
  reader.SetImageLoader(decodeUriImage, &dataUris);
  UriPolicy policy{std::filesystem::weakly_canonical(std::filesystem::absolute(path)).parent_path(),
                   allowExternalUris,
                   {},
                   &dataUris};
  // URIs are looked up beside the scene (tinygltf also tries the working directory, which the
  // policy refuses unless --allow-external-uris is given).
  const std::string baseDir = policy.folder.string();
  tinygltf::FsCallbacks files{&existsWithinFolder, &tinygltf::ExpandFilePath, &readWithinFolder,
                              &tinygltf::WriteWholeFile, &policy};
  reader.SetFsCallbacks(files);
  tinygltf::Model model;
  std::string error, warning;
  bool ok = false;
  try {
    // Files with compressed geometry also get the JSON tinygltf can parse (compressed_json).
    const std::optional<std::string> uncompressed = rewriteForCompression(parsed, binary, fixups);
    const std::string& bytes = uncompressed ? *uncompressed : parsed;
    ok = binary ? reader.LoadBinaryFromMemory(&model, &error, &warning,
                                              reinterpret_cast<const unsigned char*>(bytes.data()),
                                              static_cast<unsigned int>(bytes.size()), baseDir)
                : reader.LoadASCIIFromString(&model, &error, &warning, bytes.data(),
                                             static_cast<unsigned int>(bytes.size()), baseDir);
  } catch (const std::exception& e) {
    throw InputError(file + ": " + e.what());
  }
  // tinygltf tolerates an image it could not read; a refused file is an error all the same.
  if (!policy.violation.empty()) throw InputError(file + ": uri " + policy.violation);
  if (!ok) {
    // tinygltf reads the extension lists before the objects they change: a Draco file fails
    // at its first accessor without a bufferView, but what it needs is the extension.
    if (const std::string name = firstUnsupportedRequired(model.extensionsRequired);
        !name.empty()) {
      throw InputError(file + ": extensionsRequired: " + name + " is not supported");
    }
    std::vector<std::string> lines = nonEmptyLines(error);
    if (lines.empty()) lines = nonEmptyLines(warning);
    throw InputError(
        file + ": " +
        (lines.empty() ? "not a valid glTF file" : locateParseError(model, lines.front())));
  }
  restoreHiddenIndices(model, review.hiddenIndices);
  dataUris.restore(model);
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

}  // namespace omnishadow::gltf_detail
