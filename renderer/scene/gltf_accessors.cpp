#include "renderer/scene/gltf_accessors.h"

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <utility>

#include "renderer/scene/gltf_meshopt.h"

namespace omnishadow::gltf_detail {

namespace {

// An accessor without a bufferView is all zeros (plus sparse values): its count costs a file
// nothing to write but us memory and time to expand, however often it is read (every primitive
// that uses it reads it again). So all such reads of one file share a limit, far above what
// real files use them for (sparse morph targets, which are not read) yet small enough that a
// 100-byte file cannot keep the loader busy for seconds.
constexpr std::size_t kMaxCountWithoutBufferView = std::size_t{1} << 18;

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

}  // namespace

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
  // Compressed views decode to their own storage; their buffer may hold no data at all.
  if (const unsigned char* decoded = meshoptViewData(ctx, object, index, length)) return decoded;
  const tinygltf::Buffer& buffer = ctx.model.buffers[static_cast<std::size_t>(view.buffer)];
  if (!fitsIn(view.byteOffset, 1, view.byteLength, 1, buffer.data.size())) {
    ctx.fail(viewName,
             "extends past the end of " + at("buffers", static_cast<std::size_t>(view.buffer)));
  }
  *length = view.byteLength;
  return buffer.data.data() + view.byteOffset;
}

namespace {

// How an accessor stores its elements, and how they are decoded.
struct ElementFormat {
  int components = 0;
  int size = 0;  // of one component, in bytes
  int componentType = 0;
  bool normalized = false;

  std::size_t elementSize() const { return static_cast<std::size_t>(components * size); }

  // Decodes `count` elements, `step` bytes apart from `from`, into out's elements
  // destination(0), destination(1), ...
  template <typename Destination>
  void read(AccessorValues& out, const unsigned char* from, std::size_t step, std::size_t count,
            Destination&& destination) const {
    for (std::size_t e = 0; e < count; ++e) {
      double* dst = &out.values[destination(e) * static_cast<std::size_t>(components)];
      for (int c = 0; c < components; ++c) {
        dst[c] = decodeComponent(from + e * step + static_cast<std::size_t>(c * size),
                                 componentType, normalized);
      }
    }
  }
};

ElementFormat elementFormat(const Context& ctx, const tinygltf::Accessor& accessor,
                            const std::string& name, Normalize normalize) {
  ElementFormat format;
  format.components = tinygltf::GetNumComponentsInType(static_cast<std::uint32_t>(accessor.type));
  format.size = componentSize(accessor.componentType);
  format.componentType = accessor.componentType;
  if (format.components <= 0) ctx.fail(name, "invalid type " + std::to_string(accessor.type));
  if (format.size == 0) {
    ctx.fail(name, "invalid componentType " + std::to_string(accessor.componentType));
  }
  const bool isUnsigned = accessor.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE ||
                          accessor.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT;
  format.normalized = (normalize == Normalize::AsFlagged && accessor.normalized) ||
                      (normalize == Normalize::Integers && (accessor.normalized || isUnsigned));
  return format;
}

// The accessor's first element (nullptr without a bufferView: the elements are all zeros)
// and the distance between its elements, once they are known to lie inside the view.
std::pair<const unsigned char*, std::size_t> locateElements(Context& ctx,
                                                            const tinygltf::Accessor& accessor,
                                                            int index, const std::string& name,
                                                            std::size_t elementSize) {
  const unsigned char* data = nullptr;
  std::size_t stride = elementSize;
  if (const auto decoded = ctx.dracoAccessors.find(index); decoded != ctx.dracoAccessors.end()) {
    // Draco output, laid out tightly as the accessor describes (gltf_draco.cpp); its byteOffset
    // and bufferView, if any, describe the uncompressed fallback.
    if (decoded->second.size() != accessor.count * elementSize) {
      ctx.fail(name, "KHR_draco_mesh_compression decoded " +
                         std::to_string(decoded->second.size()) + " bytes, not count " +
                         std::to_string(accessor.count) + " times " + std::to_string(elementSize));
    }
    return {decoded->second.data(), elementSize};
  }
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

  return {data == nullptr ? nullptr : data + accessor.byteOffset, stride};
}

// Substitutes the sparse values of `accessor` into `out`.
void applySparse(const Context& ctx, const tinygltf::Accessor& accessor, const std::string& name,
                 const ElementFormat& format, AccessorValues& out) {
  const auto& sparse = accessor.sparse;
  if (sparse.count < 0 || static_cast<std::size_t>(sparse.count) > accessor.count) {
    ctx.fail(name, "sparse.count " + std::to_string(sparse.count) + " exceeds count " +
                       std::to_string(accessor.count));
  }
  const auto count = static_cast<std::size_t>(sparse.count);
  const std::size_t elementSize = format.elementSize();
  const std::string indicesName = name + ".sparse.indices";
  const int indexSize = componentSize(sparse.indices.componentType);
  if (sparse.indices.componentType == TINYGLTF_COMPONENT_TYPE_BYTE ||
      sparse.indices.componentType == TINYGLTF_COMPONENT_TYPE_SHORT ||
      sparse.indices.componentType == TINYGLTF_COMPONENT_TYPE_FLOAT || indexSize == 0) {
    ctx.fail(indicesName, "invalid componentType " + std::to_string(sparse.indices.componentType));
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
    ctx.fail(valuesName, "extends past the end of " +
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
  format.read(out, values + sparse.values.byteOffset, elementSize, count,
              [&targets](std::size_t k) { return targets[k]; });
}

}  // namespace

// Reads accessors[index] as doubles, element after element, with byteStride, normalization and
// sparse substitution applied. Throws InputError for anything outside its buffer.
AccessorValues readAccessor(Context& ctx, int index, Normalize normalize) {
  const tinygltf::Accessor& accessor = ctx.model.accessors[static_cast<std::size_t>(index)];
  const std::string name = at("accessors", static_cast<std::size_t>(index));
  const ElementFormat format = elementFormat(ctx, accessor, name, normalize);
  // Bounds first: the count is only trusted once the data behind it is known to exist.
  const auto [data, stride] = locateElements(ctx, accessor, index, name, format.elementSize());
  AccessorValues out;
  out.components = format.components;
  out.count = accessor.count;
  out.values.assign(accessor.count * static_cast<std::size_t>(format.components), 0.0);
  // Without a bufferView the accessor is all zeros (then usually sparse).
  if (data != nullptr) {
    format.read(out, data, stride, accessor.count, [](std::size_t e) { return e; });
  }
  if (accessor.sparse.isSparse) applySparse(ctx, accessor, name, format, out);
  return out;
}

}  // namespace omnishadow::gltf_detail
