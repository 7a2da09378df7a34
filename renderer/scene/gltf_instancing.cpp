#include "renderer/scene/gltf_instancing.h"

#include <algorithm>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <optional>
#include <string>

#include "renderer/scene/gltf_accessors.h"

namespace omnishadow::gltf_detail {

namespace {

constexpr const char* kInstancingExtension = "EXT_mesh_gpu_instancing";

// The attribute's values, or nullopt when the extension does not give it.
std::optional<AccessorValues> readInstanceAttribute(Context& ctx, const tinygltf::Value& attributes,
                                                    const std::string& where, const char* name,
                                                    int type, std::size_t* count) {
  if (!attributes.Has(name)) return std::nullopt;
  const std::string object = where + ".attributes." + name;
  const tinygltf::Value& value = attributes.Get(name);
  if (!value.IsNumber()) ctx.fail(object, "must be an accessor index");
  const int index = value.GetNumberAsInt();
  ctx.checkIndex(object, "accessor", index, ctx.model.accessors.size());
  const tinygltf::Accessor& accessor = ctx.model.accessors[static_cast<std::size_t>(index)];
  const std::string name_ = at("accessors", static_cast<std::size_t>(index));
  if (accessor.type != type) ctx.fail(object, name_ + " has the wrong type for " + name);
  // Float, or 8- and 16-bit integers as KHR_mesh_quantization allows them (normalized as
  // flagged); 32-bit integers are not allowed.
  if (accessor.componentType == TINYGLTF_COMPONENT_TYPE_INT ||
      accessor.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT) {
    ctx.fail(object, name_ + " must be float or a normalized or quantized 8- or 16-bit integer");
  }
  if (*count != SIZE_MAX && accessor.count != *count) {
    ctx.fail(object, name_ + " has " + std::to_string(accessor.count) +
                         " elements, but the other attributes have " + std::to_string(*count));
  }
  *count = accessor.count;
  return readAccessor(ctx, index, Normalize::AsFlagged);
}

}  // namespace

std::vector<glm::mat4> instanceTransforms(Context& ctx, std::size_t nodeIndex) {
  const tinygltf::Node& node = ctx.model.nodes[nodeIndex];
  const auto found = node.extensions.find(kInstancingExtension);
  if (found == node.extensions.end()) return {};
  const std::string where = at("nodes", nodeIndex) + ".extensions." + kInstancingExtension;
  if (!found->second.IsObject() || !found->second.Get("attributes").IsObject()) {
    ctx.fail(where, "needs an attributes object");
  }
  const tinygltf::Value& attributes = found->second.Get("attributes");
  std::size_t count = SIZE_MAX;
  const auto translation =
      readInstanceAttribute(ctx, attributes, where, "TRANSLATION", TINYGLTF_TYPE_VEC3, &count);
  const auto rotation =
      readInstanceAttribute(ctx, attributes, where, "ROTATION", TINYGLTF_TYPE_VEC4, &count);
  const auto scale =
      readInstanceAttribute(ctx, attributes, where, "SCALE", TINYGLTF_TYPE_VEC3, &count);
  if (count == SIZE_MAX) ctx.fail(where, "has none of TRANSLATION, ROTATION and SCALE");
  std::vector<glm::mat4> transforms(count, glm::mat4(1.0f));
  for (std::size_t i = 0; i < count; ++i) {
    const auto vec = [i](const AccessorValues& values, int component) {
      return static_cast<float>(values.get(i, component));
    };
    glm::mat4& m = transforms[i];
    if (translation) {
      m = glm::translate(m, {vec(*translation, 0), vec(*translation, 1), vec(*translation, 2)});
    }
    if (rotation) {
      const glm::quat q(vec(*rotation, 3), vec(*rotation, 0), vec(*rotation, 1), vec(*rotation, 2));
      // Quantized quaternions are only nearly unit length.
      if (glm::length(q) > 0.0f) m *= glm::mat4_cast(glm::normalize(q));
    }
    if (scale) m = glm::scale(m, {vec(*scale, 0), vec(*scale, 1), vec(*scale, 2)});
  }
  return transforms;
}

}  // namespace omnishadow::gltf_detail
