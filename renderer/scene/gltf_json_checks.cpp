#include "renderer/scene/gltf_json_checks.h"

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <initializer_list>
#include <iterator>
#include <limits>
#include <nlohmann/json.hpp>

#include "renderer/core/errors.h"
#include "renderer/scene/gltf_compressed_json.h"
#include "renderer/scene/gltf_context.h"
#include "renderer/scene/json_strings.h"

namespace omnishadow::gltf_detail {

namespace {

using Json = nlohmann::json;

// What the file contained, short enough for a one-line message.
std::string quoted(const Json& value) {
  std::string text = value.dump(-1, ' ', false, Json::error_handler_t::replace);
  if (text.size() > 40) text = text.substr(0, 40) + "...";
  return text;
}

bool isInteger(const Json& value, std::int64_t low, std::int64_t high) {
  if (!value.is_number_integer()) return false;
  const auto number = value.get<std::int64_t>();
  return number >= low && number <= high;
}

// An index into a glTF array, as tinygltf holds one (an int).
bool isIndex(const Json& value) {
  return isInteger(value, 0, std::numeric_limits<std::int32_t>::max());
}

// Members of `array` (a top-level glTF array or a nested one), with their index; nothing when
// the field is missing or not an array (tinygltf reports that).
template <typename F>
void eachObject(const Json& parent, const char* array, F&& visit) {
  const auto it = parent.find(array);
  if (it == parent.end() || !it->is_array()) return;
  for (std::size_t i = 0; i < it->size(); ++i) {
    if ((*it)[i].is_object()) visit(i, (*it)[i]);
  }
}

class Reviewer {
 public:
  explicit Reviewer(const std::string& file) : file_(file) {}

  [[noreturn]] void fail(const std::string& object, const std::string& problem) const {
    throw InputError(file_ + ": " + object + ": " + problem);
  }

  // tinygltf skips a top-level collection that is no array, members and all, and reads a
  // `scene` that is no integer as none: the file would load as another one (no nodes, no
  // meshes) or fail far from the cause.
  void topLevel(const Json& root) {
    for (const char* name : {"accessors", "animations", "buffers", "bufferViews", "cameras",
                             "images", "materials", "meshes", "nodes", "samplers", "scenes",
                             "skins", "textures", "extensionsUsed", "extensionsRequired"}) {
      const auto it = root.find(name);
      if (it != root.end() && !it->is_array()) fail(name, quoted(*it) + " is not an array");
    }
    const auto scene = root.find("scene");
    if (scene != root.end() && !isIndex(*scene))
      fail("scene", quoted(*scene) + " is not a scene index");
  }

  void bufferViews(const Json& root) {
    eachObject(root, "bufferViews", [&](std::size_t i, const Json& view) {
      const auto stride = view.find("byteStride");
      if (stride != view.end() &&
          (!isInteger(*stride, 4, 252) || stride->get<std::int64_t>() % 4 != 0)) {
        fail(at("bufferViews", i),
             "byteStride " + quoted(*stride) + " is not a multiple of 4 from 4 to 252");
      }
    });
  }

  // The required fields tinygltf reports without the accessor's index.
  void accessors(const Json& root) {
    eachObject(root, "accessors", [&](std::size_t i, const Json& accessor) {
      const std::string object = at("accessors", i);
      const auto count = accessor.find("count");
      if (count == accessor.end()) fail(object, "count is missing");
      if (!isInteger(*count, 1, INT64_MAX)) {
        fail(object + ".count", "expected an integer >= 1, got " + quoted(*count));
      }
      const auto componentType = accessor.find("componentType");
      if (componentType == accessor.end()) fail(object, "componentType is missing");
      if (!isInteger(*componentType, 5120, 5126) || componentType->get<int>() == 5124) {
        fail(object + ".componentType",
             quoted(*componentType) + " is not one of 5120, 5121, 5122, 5123, 5125, 5126");
      }
      const auto type = accessor.find("type");
      if (type == accessor.end()) fail(object, "type is missing");
      static const char* const kTypes[] = {"SCALAR", "VEC2", "VEC3", "VEC4",
                                           "MAT2",   "MAT3", "MAT4"};
      if (!type->is_string() || std::none_of(std::begin(kTypes), std::end(kTypes), [&](auto t) {
            return type->get_ref<const std::string&>() == t;
          })) {
        fail(object + ".type", quoted(*type) + " is not SCALAR, VEC2-4 or MAT2-4");
      }
    });
  }

  void meshes(Json& root, JsonReview& review) {
    const auto accessors = root.find("accessors");
    const auto meshes = root.find("meshes");
    if (meshes == root.end() || !meshes->is_array()) return;
    for (std::size_t m = 0; m < meshes->size(); ++m) {
      Json& mesh = (*meshes)[m];
      if (!mesh.is_object() || !mesh.contains("primitives") || !mesh["primitives"].is_array())
        continue;
      Json& primitives = mesh["primitives"];
      for (std::size_t p = 0; p < primitives.size(); ++p) {
        Json& primitive = primitives[p];
        const std::string object = at("meshes", m) + "." + at("primitives", p);
        // tinygltf drops such a primitive silently, which would also shift the index of every
        // primitive after it (and the indices restored below onto the wrong one).
        if (!primitive.is_object()) fail(object, "is not an object");
        const auto attributes = primitive.find("attributes");
        if (attributes == primitive.end() || !attributes->is_object()) {
          fail(object, "has no attributes object (every primitive must have one)");
        }
        // tinygltf drops the whole primitive for one attribute that is no integer, and a morph
        // target's such attribute alone.
        const auto accessorIndices = [&](const Json& map, const std::string& where) {
          for (const auto& [name, value] : map.items())
            if (!isIndex(value))
              fail(where + "." + name, quoted(value) + " is not an accessor index");
        };
        accessorIndices(*attributes, object + ".attributes");
        const auto targets = primitive.find("targets");
        if (targets != primitive.end() && targets->is_array())
          for (std::size_t t = 0; t < targets->size(); ++t)
            if ((*targets)[t].is_object())
              accessorIndices((*targets)[t], object + "." + at("targets", t));
        const auto mode = primitive.find("mode");
        if (mode != primitive.end() && !isInteger(*mode, 0, 6)) {
          fail(object + ".mode", quoted(*mode) + " is not one of the modes 0 to 6");
        }
        // tinygltf refuses an index accessor without a bufferView; glTF reads it as zeros.
        const auto indices = primitive.find("indices");
        if (indices == primitive.end() || !indices->is_number_integer() ||
            accessors == root.end() || !accessors->is_array()) {
          continue;
        }
        const auto index = indices->get<std::int64_t>();
        if (index < 0 || static_cast<std::size_t>(index) >= accessors->size()) continue;
        const Json& accessor = (*accessors)[static_cast<std::size_t>(index)];
        if (!accessor.is_object() || accessor.contains("bufferView")) continue;
        review.hiddenIndices.push_back({m, p, static_cast<int>(index)});
        primitive.erase("indices");
      }
    }
  }

  // A buffer without a uri (other than a .glb's BIN chunk) that no bufferView uses holds
  // nothing the file needs; tinygltf refuses it, so it becomes one byte of data. One that
  // meshopt-compressed bufferViews use is their fallback, left to gltf_compressed_json (which
  // also names an uncompressed view of it).
  void placeholderBuffers(Json& root, bool binary, JsonReview& review) {
    const auto buffers = root.find("buffers");
    if (buffers == root.end() || !buffers->is_array()) return;
    constexpr std::size_t kUnused = SIZE_MAX;
    std::vector<std::size_t> firstView(buffers->size(), kUnused);
    std::vector<bool> fallback(buffers->size(), false);
    eachObject(root, "bufferViews", [&](std::size_t v, const Json& view) {
      const auto buffer = view.find("buffer");
      if (buffer == view.end() || !isInteger(*buffer, 0, std::int64_t(firstView.size()) - 1))
        return;
      const auto b = buffer->get<std::size_t>();
      if (usesMeshopt(view)) {
        fallback[b] = true;
      } else if (firstView[b] == kUnused) {
        firstView[b] = v;
      }
    });
    for (std::size_t i = binary ? 1 : 0; i < buffers->size(); ++i) {
      Json& buffer = (*buffers)[i];
      if (!buffer.is_object() || buffer.contains("uri") || fallback[i]) continue;
      // tinygltf's own words name neither the buffer's user nor the rule.
      if (firstView[i] != kUnused) {
        fail(at("buffers", i),
             "has no uri, but " + at("bufferViews", firstView[i]) +
                 " uses it (only the first buffer of a .glb, its BIN chunk, may leave uri out)");
      }
      buffer = Json{{"byteLength", 1}, {"uri", "data:application/octet-stream;base64,AA=="}};
      review.warnings.push_back(at("buffers", i) + ": no uri and no bufferView uses it; ignored");
      changed_ = true;
    }
  }

  // WebP and AVIF images (EXT_texture_webp, EXT_texture_avif). tinygltf takes a data: URI of
  // either for a file name, so the URI is retyped as octet-stream; its bytes are sniffed, not
  // labelled. What the specifications forbid but can still be drawn is drawn with a warning: such
  // an image that a core `source` names, one without its extension in extensionsUsed, and an
  // extension `source` that names an image of another format.
  void extensionImages(Json& root, JsonReview& review) {
    const auto images = root.find("images");
    if (images == root.end() || !images->is_array()) return;
    const auto used = root.find("extensionsUsed");
    const auto declared = [&](const char* extension) {
      return used != root.end() && used->is_array() &&
             std::find(used->begin(), used->end(), extension) != used->end();
    };
    // `expected`: the format the naming field may name ("" for a core source: PNG or JPEG).
    const auto imageNamed = [&](const Json& parent, std::size_t texture, const std::string& field,
                                const std::string& expected) {
      const auto source = parent.find("source");
      if (source == parent.end() || !source->is_number_integer()) return;
      const auto i = source->get<std::int64_t>();
      if (i < 0 || std::uint64_t(i) >= images->size()) return;
      const Json& image = (*images)[std::size_t(i)];
      const std::string format = image.is_object() ? imageFormat(image) : "";
      if (format.empty() || format == expected) return;
      const char* extension = extensionOf(format);
      if (expected.empty() && !extension) return;  // PNG or JPEG from a core source
      review.warnings.push_back(
          at("textures", texture) + field + ": " + at("images", std::size_t(i)) + " is " + format +
          (expected.empty() ? std::string(", which only ") + extension + " may name"
                            : ", not " + expected) +
          "; drawn as it is");
    };
    eachObject(root, "textures", [&](std::size_t t, const Json& texture) {
      imageNamed(texture, t, ".source", "");
      const auto extensions = texture.find("extensions");
      if (extensions == texture.end() || !extensions->is_object()) return;
      for (const char* format : {"WebP", "AVIF"}) {
        const auto named = extensions->find(extensionOf(format));
        if (named != extensions->end() && named->is_object())
          imageNamed(*named, t, std::string(".extensions.") + extensionOf(format) + ".source",
                     format);
      }
    });
    for (std::size_t i = 0; i < images->size(); ++i) {
      Json& image = (*images)[i];
      if (!image.is_object()) continue;
      const std::string format = imageFormat(image);
      const char* extension = extensionOf(format);
      if (!extension) continue;
      if (!declared(extension)) {
        review.warnings.push_back(at("images", i) + ": " + format + ", but " + extension +
                                  " is not in extensionsUsed; decoded as " + format);
      }
      const auto uri = image.find("uri");
      if (uri == image.end() || !uri->is_string()) continue;
      std::string text = uri->get<std::string>();
      const std::size_t comma = text.find(',');
      const std::string type = "data:image/" + lowercase(format);
      if (comma == std::string::npos || !lowercase(text.substr(0, comma)).starts_with(type))
        continue;  // a file name, or a data: URI of another type that tinygltf decodes
      if (lowercase(text.substr(0, comma)) != type + ";base64") {
        fail(at("images", i) + ".uri", "\"" + text.substr(0, std::min<std::size_t>(comma, 60)) +
                                           "\": only base64 data: URIs are supported");
      }
      text.replace(0, comma, "data:application/octet-stream;base64");
      *uri = std::move(text);
      changed_ = true;
    }
  }

  bool changed() const { return changed_; }

  // KHR_lights_punctual: tinygltf reads an absent range as 0, so 0 and below are caught here.
  void lights(const Json& root) {
    const auto extensions = root.find("extensions");
    if (extensions == root.end() || !extensions->is_object()) return;
    const auto punctual = extensions->find("KHR_lights_punctual");
    if (punctual == extensions->end() || !punctual->is_object()) return;
    eachObject(*punctual, "lights", [&](std::size_t i, const Json& light) {
      const auto range = light.find("range");
      if (range != light.end() && !(range->is_number() && range->get<double>() > 0.0)) {
        fail("KHR_lights_punctual." + at("lights", i) + ".range",
             quoted(*range) + ": expected a number > 0 (leave it out for no limit)");
      }
    });
  }

 private:
  // The extension through which images of `format` (as imageFormat names it) reach textures;
  // nullptr for the core formats.
  static const char* extensionOf(const std::string& format) {
    return format == "WebP" ? "EXT_texture_webp" : format == "AVIF" ? "EXT_texture_avif" : nullptr;
  }

  static std::string lowercase(std::string text) {
    std::transform(text.begin(), text.end(), text.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return text;
  }

  // "PNG", "JPEG", "WebP" or "AVIF" as the image's mimeType, data: URI or file name says, else
  // "".
  static std::string imageFormat(const Json& image) {
    const auto text = [&](const char* key) {
      const auto it = image.find(key);
      return it != image.end() && it->is_string() ? lowercase(it->get<std::string>())
                                                  : std::string();
    };
    const std::string mime = text("mimeType"), uri = text("uri");
    const auto is = [&](const char* type, std::initializer_list<const char*> suffixes) {
      if (mime == std::string("image/") + type ||
          uri.starts_with(std::string("data:image/") + type))
        return true;
      if (uri.starts_with("data:")) return false;
      return std::any_of(suffixes.begin(), suffixes.end(),
                         [&](const char* suffix) { return uri.ends_with(suffix); });
    };
    return is("webp", {".webp"})           ? "WebP"
           : is("avif", {".avif"})         ? "AVIF"
           : is("png", {".png"})           ? "PNG"
           : is("jpeg", {".jpg", ".jpeg"}) ? "JPEG"
                                           : "";
  }

  const std::string& file_;
  bool changed_ = false;
};

// `json` with every string longer than kLongString bytes cut to its plain first and last
// (at most kKept) bytes. The review reads no long string but to spot WebP (a data: URI's
// start, a file name's end): parsed whole, a 40 MB data URI cost nlohmann as much as tinygltf's
// own parse. Text that is no JSON stays no JSON (an unterminated string is copied as it is).
std::string withoutLongStrings(std::string_view json) {
  constexpr std::size_t kLongString = 256, kKept = 32;
  std::string out;
  out.reserve(std::min<std::size_t>(json.size(), 1 << 20));
  std::size_t copied = 0;
  forEachJsonString(json, [&](std::size_t open, std::size_t close) {
    const std::size_t length = close - open - 1;
    if (length <= kLongString) return;
    const std::string_view content = json.substr(open + 1, length);
    std::size_t head = 0, tail = 0;
    while (head < kKept && plainStringByte(content[head])) ++head;
    while (tail < kKept && plainStringByte(content[length - 1 - tail])) ++tail;
    out.append(json, copied, open + 1 - copied);
    out.append(content.substr(0, head)).append(content.substr(length - tail));
    copied = close;
  });
  out.append(json.substr(copied));
  return out;
}

// Runs the review on `json`; with `rewrite`, review.rewritten holds the changed JSON (when
// something changed). Returns whether something did.
bool review(std::string_view json, const std::string& file, bool binary, bool rewrite,
            JsonReview& review) {
  Json root = Json::parse(json.begin(), json.end(), nullptr, /*allow_exceptions=*/false);
  if (!root.is_object()) return false;
  Reviewer reviewer(file);
  reviewer.topLevel(root);
  reviewer.bufferViews(root);
  reviewer.accessors(root);
  reviewer.lights(root);
  reviewer.meshes(root, review);
  reviewer.placeholderBuffers(root, binary, review);
  reviewer.extensionImages(root, review);
  const bool changed = !review.hiddenIndices.empty() || reviewer.changed();
  if (changed && rewrite) review.rewritten = root.dump();
  return changed;
}

}  // namespace

JsonReview reviewGltfJson(std::string_view json, const std::string& file, bool binary) {
  JsonReview cut;
  // The rewritten JSON keeps the long strings: the rare file that needs one is parsed again.
  if (!review(withoutLongStrings(json), file, binary, /*rewrite=*/false, cut)) return cut;
  JsonReview whole;
  review(json, file, binary, /*rewrite=*/true, whole);
  return whole;
}

void restoreHiddenIndices(tinygltf::Model& model, const std::vector<HiddenIndices>& hidden) {
  for (const HiddenIndices& h : hidden) {
    model.meshes.at(h.mesh).primitives.at(h.primitive).indices = h.accessor;
  }
}

}  // namespace omnishadow::gltf_detail
