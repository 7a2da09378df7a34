// Internal to the scene library: base64 data: URIs of buffers and images decoded before
// tinygltf parses the JSON. tinygltf 2.7 decodes them one character at a time (a search of the
// alphabet per character, a push_back per byte): on a glTF-Embedded file that was most of the
// load. Here the reader takes them out of the JSON, decodes them at memory speed, and hands
// them to tinygltf as files of placeholder names that the file callbacks serve from memory.
// What tinygltf then holds is what its own decoding would have given.
#pragma once

#include <tiny_gltf.h>

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace omnishadow::gltf_detail {

// The bytes tinygltf::base64_decode gives for `text`: the base64 letters before the first '='
// or other character, each four to three bytes; a last group of n < 4 letters gives n - 1
// bytes, and what follows the letters is ignored.
std::vector<unsigned char> decodeBase64AsTinygltf(std::string_view text);

// The data: URIs taken out of a glTF file's JSON.
class DataUris {
 public:
  struct Payload {
    std::size_t number = 0;  // the number in its placeholder name, which the JSON now has in
                             // the URI's place
    bool image = false;
    std::string uri;  // the data: URI (buffers keep it in tinygltf::Buffer::uri)
    // What tinygltf's DecodeDataURI sets an image's mimeType to ("" where it leaves it).
    std::string mimeType;
    std::vector<unsigned char> bytes;
    bool served = false;  // its bytes moved to tinygltf
  };

  // `json` (a .gltf's text, or a .glb's JSON chunk) with the base64 data: URIs of its buffers
  // and images replaced by placeholder names, or nullopt where none was taken. A URI is taken
  // only where tinygltf would decode it without a message: one of the data: types it knows, as
  // JSON plain characters (no escapes), giving a buffer exactly its byteLength or an image at
  // least one byte, in JSON that parses. The rest, and any file with a broken JSON, are left to
  // tinygltf, so that its messages stay what they were; so are URIs shorter than 1 KiB.
  std::optional<std::string> take(std::string_view json);

  // The payload that `filepath` (a placeholder joined to the scene's folder) names, or nullptr.
  Payload* find(std::string_view filepath);

  // The URIs put back (moved) where tinygltf keeps them: a buffer's uri is its data: URI, an
  // image's uri is empty and its mimeType the type's.
  void restore(tinygltf::Model& model);

  // For the image loader: an image that tinygltf read from a placeholder made what its own
  // decoding of the data: URI would have made (no uri, the type's mimeType).
  // Returns whether it was one.
  bool restoreImage(tinygltf::Image& image) const;

 private:
  // The payload whose name `name` is, or payloads_.size().
  std::size_t indexNamed(std::string_view name) const;

  std::vector<Payload> payloads_;
};

}  // namespace omnishadow::gltf_detail
