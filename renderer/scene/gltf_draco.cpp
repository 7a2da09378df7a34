#include "renderer/scene/gltf_draco.h"

#include <draco/compression/decode.h>
#include <draco/mesh/mesh.h>

#include <cstdint>
#include <cstring>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "renderer/scene/gltf_accessors.h"

namespace omnishadow::gltf_detail {

namespace {

constexpr const char* kDracoExtension = "KHR_draco_mesh_compression";

// Converts every point's value of `attribute` to the accessor's component type T, appended to
// `out`; false when a value does not fit T.
template <typename T>
bool appendValues(const draco::PointAttribute& attribute, std::size_t points, int components,
                  std::vector<unsigned char>& out) {
  std::vector<T> element(static_cast<std::size_t>(components));
  out.reserve(points * element.size() * sizeof(T));
  for (std::size_t i = 0; i < points; ++i) {
    const draco::AttributeValueIndex value =
        attribute.mapped_index(draco::PointIndex(static_cast<std::uint32_t>(i)));
    if (value.value() >= attribute.size() ||
        !attribute.ConvertValue<T>(value, static_cast<std::int8_t>(components), element.data())) {
      return false;
    }
    const auto* bytes = reinterpret_cast<const unsigned char*>(element.data());
    out.insert(out.end(), bytes, bytes + element.size() * sizeof(T));
  }
  return true;
}

bool convertAttribute(const draco::PointAttribute& attribute, int componentType, std::size_t points,
                      int components, std::vector<unsigned char>& out) {
  switch (componentType) {
    case TINYGLTF_COMPONENT_TYPE_BYTE:
      return appendValues<std::int8_t>(attribute, points, components, out);
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
      return appendValues<std::uint8_t>(attribute, points, components, out);
    case TINYGLTF_COMPONENT_TYPE_SHORT:
      return appendValues<std::int16_t>(attribute, points, components, out);
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT:
      return appendValues<std::uint16_t>(attribute, points, components, out);
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
      return appendValues<std::uint32_t>(attribute, points, components, out);
    case TINYGLTF_COMPONENT_TYPE_FLOAT:
      return appendValues<float>(attribute, points, components, out);
    default:
      return false;
  }
}

template <typename T>
void appendIndex(std::uint32_t index, std::vector<unsigned char>& out) {
  const auto value = static_cast<T>(index);
  const auto* bytes = reinterpret_cast<const unsigned char*>(&value);
  out.insert(out.end(), bytes, bytes + sizeof value);
}

}  // namespace

int indicesAccessor(const Context& ctx, std::size_t meshIndex, std::size_t primIndex) {
  const auto found = ctx.fixups.dracoIndices.find({meshIndex, primIndex});
  if (found != ctx.fixups.dracoIndices.end()) return found->second;
  return ctx.model.meshes[meshIndex].primitives[primIndex].indices;
}

void decodeDraco(Context& ctx, std::size_t meshIndex, std::size_t primIndex) {
  ctx.dracoAccessors.clear();
  const tinygltf::Primitive& primitive = ctx.model.meshes[meshIndex].primitives[primIndex];
  const auto found = primitive.extensions.find(kDracoExtension);
  if (found == primitive.extensions.end()) return;
  const std::string where = ctx.primitive + ".extensions." + kDracoExtension;
  const tinygltf::Value& extension = found->second;
  if (!extension.IsObject() || !extension.Get("bufferView").IsNumber() ||
      !extension.Get("attributes").IsObject()) {
    ctx.fail(where, "needs a bufferView and an attributes object");
  }
  const int view = extension.Get("bufferView").GetNumberAsInt();
  std::size_t length = 0;
  const unsigned char* bytes = bufferViewData(ctx, where, view, &length);

  draco::DecoderBuffer buffer;
  buffer.Init(reinterpret_cast<const char*>(bytes), length);
  draco::Decoder decoder;
  auto decoded = decoder.DecodePointCloudFromBuffer(&buffer);
  if (!decoded.ok()) {
    ctx.fail(where, "the Draco data in " + at("bufferViews", static_cast<std::size_t>(view)) +
                        " does not decode: " + decoded.status().error_msg_string());
  }
  const std::unique_ptr<draco::PointCloud> cloud = std::move(decoded).value();
  const auto points = static_cast<std::size_t>(cloud->num_points());

  const tinygltf::Value& attributes = extension.Get("attributes");
  for (const std::string& semantic : attributes.Keys()) {
    const std::string object = where + ".attributes." + semantic;
    const auto target = primitive.attributes.find(semantic);
    if (target == primitive.attributes.end()) {
      ctx.fail(object, "the primitive has no " + semantic + " attribute to decode into");
    }
    ctx.checkIndex(object, "accessor", target->second, ctx.model.accessors.size());
    const std::string accessorName = at("accessors", static_cast<std::size_t>(target->second));
    const tinygltf::Accessor& accessor =
        ctx.model.accessors[static_cast<std::size_t>(target->second)];
    const tinygltf::Value& id = attributes.Get(semantic);
    const draco::PointAttribute* attribute =
        id.IsNumber() && id.GetNumberAsInt() >= 0
            ? cloud->GetAttributeByUniqueId(static_cast<std::uint32_t>(id.GetNumberAsInt()))
            : nullptr;
    if (attribute == nullptr) ctx.fail(object, "the Draco data has no attribute with this id");
    const int components =
        tinygltf::GetNumComponentsInType(static_cast<std::uint32_t>(accessor.type));
    if (components <= 0 || attribute->num_components() != components) {
      ctx.fail(object, "decoded " + std::to_string(int{attribute->num_components()}) +
                           " components per vertex, but " + accessorName + " has " +
                           std::to_string(components));
    }
    if (accessor.count != points) {
      ctx.fail(object, "decoded " + std::to_string(points) + " vertices, but " + accessorName +
                           " has count " + std::to_string(accessor.count));
    }
    std::vector<unsigned char> data;
    if (!convertAttribute(*attribute, accessor.componentType, points, components, data)) {
      ctx.fail(object, "decoded values do not fit " + accessorName + "'s componentType " +
                           std::to_string(accessor.componentType));
    }
    ctx.dracoAccessors[target->second] = std::move(data);
  }

  const int indices = indicesAccessor(ctx, meshIndex, primIndex);
  const auto* mesh = dynamic_cast<const draco::Mesh*>(cloud.get());
  if (indices < 0) {
    if (mesh != nullptr && mesh->num_faces() > 0) {
      ctx.fail(where, "the Draco data has triangles, but the primitive has no indices accessor");
    }
    return;
  }
  const std::string object = where + " indices";
  ctx.checkIndex(object, "accessor", indices, ctx.model.accessors.size());
  const std::string accessorName = at("accessors", static_cast<std::size_t>(indices));
  const tinygltf::Accessor& accessor = ctx.model.accessors[static_cast<std::size_t>(indices)];
  const std::size_t faces = mesh == nullptr ? 0 : mesh->num_faces();
  if (accessor.count != faces * 3) {
    ctx.fail(object, "decoded " + plural(faces, "triangle") + ", but " + accessorName +
                         " has count " + std::to_string(accessor.count));
  }
  std::uint32_t largest = 0;
  switch (accessor.componentType) {
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
      largest = std::numeric_limits<std::uint8_t>::max();
      break;
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT:
      largest = std::numeric_limits<std::uint16_t>::max();
      break;
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
      largest = std::numeric_limits<std::uint32_t>::max();
      break;
    default:
      ctx.fail(object, accessorName + " must be SCALAR unsigned byte, short or int");
  }
  std::vector<unsigned char> data;
  data.reserve(faces * 3 * static_cast<std::size_t>(componentSize(accessor.componentType)));
  for (std::size_t f = 0; f < faces; ++f) {
    const draco::Mesh::Face& face = mesh->face(draco::FaceIndex(static_cast<std::uint32_t>(f)));
    for (const draco::PointIndex& point : face) {
      const std::uint32_t value = point.value();
      if (value > largest) {
        ctx.fail(object, "decoded index " + std::to_string(value) + " does not fit " +
                             accessorName + "'s componentType");
      }
      if (largest == 0xFF)
        appendIndex<std::uint8_t>(value, data);
      else if (largest == 0xFFFF)
        appendIndex<std::uint16_t>(value, data);
      else
        appendIndex<std::uint32_t>(value, data);
    }
  }
  ctx.dracoAccessors[indices] = std::move(data);
}

}  // namespace omnishadow::gltf_detail
