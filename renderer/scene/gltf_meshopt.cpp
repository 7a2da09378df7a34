#include "renderer/scene/gltf_meshopt.h"

#include <meshoptimizer.h>

#include <cstdint>
#include <utility>
#include <vector>

namespace omnishadow::gltf_detail {

namespace {

// Decoding happens on a primitive's first read of the bufferView: messages name both.
[[noreturn]] void fail(const Context& ctx, const std::string& where, const std::string& problem) {
  ctx.fail(where, problem + (ctx.primitive.empty() ? "" : " (reading " + ctx.primitive + ")"));
}

// "0.18" for MESHOPTIMIZER_VERSION 180.
std::string meshoptVersion() {
  return std::to_string(MESHOPTIMIZER_VERSION / 1000) + "." +
         std::to_string(MESHOPTIMIZER_VERSION % 1000 / 10);
}

// What the extension object says, before it is trusted.
struct Compressed {
  std::string extension;  // "EXT_meshopt_compression" or "KHR_meshopt_compression"
  int buffer = -1;
  std::uint64_t byteOffset = 0, byteLength = 0, byteStride = 0, count = 0;
  std::string mode, filter = "NONE";
};

// A non-negative integer property; `fallback` when absent, and false for anything else.
bool unsignedProperty(const tinygltf::Value& object, const char* name, bool required,
                      std::uint64_t* out) {
  if (!object.Has(name)) return !required;
  const tinygltf::Value& value = object.Get(name);
  if (!value.IsNumber()) return false;
  const double number = value.GetNumberAsDouble();
  // 2^53: beyond it doubles skip integers, and no real length comes near.
  if (!(number >= 0.0 && number <= 9007199254740992.0) ||
      number != static_cast<double>(static_cast<std::uint64_t>(number))) {
    return false;
  }
  *out = static_cast<std::uint64_t>(number);
  return true;
}

Compressed parse(const Context& ctx, const std::string& object, const std::string& extension,
                 const tinygltf::Value& value) {
  const std::string where = object + ".extensions." + extension;
  if (!value.IsObject()) fail(ctx, where, "is not an object");
  Compressed c;
  c.extension = extension;
  std::uint64_t buffer = 0;
  for (const auto& [name, required, out] :
       {std::tuple<const char*, bool, std::uint64_t*>{"buffer", true, &buffer},
        {"byteOffset", false, &c.byteOffset},
        {"byteLength", true, &c.byteLength},
        {"byteStride", true, &c.byteStride},
        {"count", true, &c.count}}) {
    if (!unsignedProperty(value, name, required, out)) {
      fail(ctx, where,
           std::string(name) +
               (value.Has(name) ? " must be a non-negative integer" : " is missing"));
    }
  }
  if (buffer >= ctx.model.buffers.size()) {
    fail(ctx, where,
         "buffer " + std::to_string(buffer) + " is out of range (the file has " +
             plural(ctx.model.buffers.size(), "buffer") + ")");
  }
  c.buffer = static_cast<int>(buffer);
  const auto text = [&](const char* name, std::string* out) {
    if (!value.Has(name)) return;
    if (!value.Get(name).IsString()) fail(ctx, where, std::string(name) + " must be a string");
    *out = value.Get(name).Get<std::string>();
  };
  if (!value.Has("mode")) fail(ctx, where, "mode is missing");
  text("mode", &c.mode);
  text("filter", &c.filter);
  return c;
}

// The extension's rules on mode, filter, stride and count (both extensions share them).
void check(const Context& ctx, const std::string& where, const Compressed& c,
           std::uint64_t viewLength) {
  const std::string stride = "byteStride " + std::to_string(c.byteStride);
  if (c.mode == "ATTRIBUTES") {
    if (c.byteStride == 0 || c.byteStride % 4 != 0 || c.byteStride > 256) {
      fail(ctx, where, stride + " must be a multiple of 4 from 4 to 256 in mode ATTRIBUTES");
    }
  } else if (c.mode == "TRIANGLES" || c.mode == "INDICES") {
    if (c.byteStride != 2 && c.byteStride != 4) {
      fail(ctx, where, stride + " must be 2 or 4 in mode " + c.mode);
    }
    if (c.mode == "TRIANGLES" && c.count % 3 != 0) {
      fail(ctx, where,
           "count " + std::to_string(c.count) + " must be a multiple of 3 in mode " + "TRIANGLES");
    }
    if (c.filter != "NONE") fail(ctx, where, "filter " + c.filter + " needs mode ATTRIBUTES");
  } else {
    fail(ctx, where, "unknown mode \"" + c.mode + "\" (ATTRIBUTES, TRIANGLES or INDICES)");
  }
  if (c.filter == "OCTAHEDRAL" && c.byteStride != 4 && c.byteStride != 8) {
    fail(ctx, where, stride + " must be 4 or 8 for filter OCTAHEDRAL");
  } else if (c.filter == "QUATERNION" && c.byteStride != 8) {
    fail(ctx, where, stride + " must be 8 for filter QUATERNION");
  } else if (c.filter == "COLOR") {
    fail(ctx, where,
         "filter COLOR is not supported by the meshoptimizer this was built with (" +
             meshoptVersion() + ")");
  } else if (c.filter != "NONE" && c.filter != "OCTAHEDRAL" && c.filter != "QUATERNION" &&
             c.filter != "EXPONENTIAL") {
    fail(ctx, where, "unknown filter \"" + c.filter + "\"");
  }
  // byteStride <= 256 here, so the product cannot overflow for any count below 2^53.
  if (c.count * c.byteStride != viewLength) {
    fail(ctx, where,
         "count " + std::to_string(c.count) + " times " + stride +
             " is not the bufferView's byteLength " + std::to_string(viewLength));
  }
}

std::vector<unsigned char> decode(const Context& ctx, const std::string& where,
                                  const Compressed& c) {
  const std::string source = at("buffers", static_cast<std::size_t>(c.buffer));
  if (ctx.fixups.placeholderBuffers.count(static_cast<std::size_t>(c.buffer)) != 0) {
    fail(ctx, where, source + " is a fallback buffer without data");
  }
  const std::vector<unsigned char>& data =
      ctx.model.buffers[static_cast<std::size_t>(c.buffer)].data;
  if (c.byteOffset > data.size() || c.byteLength > data.size() - c.byteOffset) {
    fail(ctx, where,
         "byteOffset " + std::to_string(c.byteOffset) + " and byteLength " +
             std::to_string(c.byteLength) + " extend past the end of " + source);
  }
  const std::uint64_t decodedSize = c.count * c.byteStride;
  // The codecs store at least one byte per 64 decoded ones (attributes: 2 bits per 16 bytes),
  // so a larger claim cannot be true; refusing it keeps a tiny file from allocating gigabytes.
  if (decodedSize / 64 > c.byteLength + 1024) {
    fail(ctx, where,
         "byteLength " + std::to_string(c.byteLength) + " cannot hold " +
             std::to_string(decodedSize) + " bytes of compressed data");
  }
  std::vector<unsigned char> out(decodedSize);
  const unsigned char* in = data.data() + c.byteOffset;
  const auto length = static_cast<std::size_t>(c.byteLength);
  const auto count = static_cast<std::size_t>(c.count),
             stride = static_cast<std::size_t>(c.byteStride);
  if (c.mode == "ATTRIBUTES" && length > 0 && in[0] != 0xA0) {
    // 0xA0 | version; version 1 is KHR_meshopt_compression's newer format.
    if ((in[0] & 0xF0) == 0xA0) {
      fail(ctx, where,
           "vertex data version " + std::to_string(in[0] & 0x0F) +
               " is not supported by the meshoptimizer this was built with (" + meshoptVersion() +
               ")");
    }
  }
  int status = 0;
  if (c.mode == "ATTRIBUTES") {
    status = meshopt_decodeVertexBuffer(out.data(), count, stride, in, length);
  } else if (c.mode == "TRIANGLES") {
    status = meshopt_decodeIndexBuffer(out.data(), count, stride, in, length);
  } else {
    status = meshopt_decodeIndexSequence(out.data(), count, stride, in, length);
  }
  if (status != 0) {
    // meshoptimizer: -1 for a header it does not know, -2 for data that runs out or overflows.
    fail(ctx, where,
         "the " + c.mode + " data does not decode: " +
             (status == -1
                  ? std::string("no meshopt header")
                  : "truncated or corrupt (meshoptimizer error " + std::to_string(status) + ")"));
  }
  if (c.filter == "OCTAHEDRAL") {
    meshopt_decodeFilterOct(out.data(), count, stride);
  } else if (c.filter == "QUATERNION") {
    meshopt_decodeFilterQuat(out.data(), count, stride);
  } else if (c.filter == "EXPONENTIAL") {
    meshopt_decodeFilterExp(out.data(), count, stride);
  }
  return out;
}

}  // namespace

const unsigned char* meshoptViewData(const Context& ctx, const std::string& object, int index,
                                     std::size_t* length) {
  const tinygltf::BufferView& view = ctx.model.bufferViews[static_cast<std::size_t>(index)];
  const std::string viewName = at("bufferViews", static_cast<std::size_t>(index));
  const tinygltf::Value* extension = nullptr;
  std::string name;
  for (const char* candidate : {"KHR_meshopt_compression", "EXT_meshopt_compression"}) {
    const auto found = view.extensions.find(candidate);
    if (found != view.extensions.end()) {
      extension = &found->second;
      name = candidate;
      break;
    }
  }
  if (extension == nullptr) {
    if (view.buffer >= 0 &&
        ctx.fixups.placeholderBuffers.count(static_cast<std::size_t>(view.buffer)) != 0) {
      ctx.fail(object, viewName + " is not compressed, but its " +
                           at("buffers", static_cast<std::size_t>(view.buffer)) +
                           " is a meshopt fallback buffer without data");
    }
    return nullptr;
  }
  auto cached = ctx.meshoptViews.find(index);
  if (cached == ctx.meshoptViews.end()) {
    const std::string where = viewName + ".extensions." + name;
    const Compressed compressed = parse(ctx, viewName, name, *extension);
    check(ctx, where, compressed, view.byteLength);
    cached = ctx.meshoptViews.emplace(index, decode(ctx, where, compressed)).first;
  }
  *length = cached->second.size();
  return cached->second.data();
}

}  // namespace omnishadow::gltf_detail
