#include "renderer/scene/gltf_primitives.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <initializer_list>
#include <map>
#include <span>
#include <string>
#include <vector>

#include "renderer/scene/gltf_accessors.h"
#include "renderer/scene/gltf_draco.h"
#include "renderer/scene/gltf_material_variants.h"
#include "renderer/scene/tangents.h"

namespace omnishadow::gltf_detail {

namespace {

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
// but as numbers the file never meant, unless the file declares KHR_mesh_quantization.
constexpr int kFloatOnly[] = {TINYGLTF_COMPONENT_TYPE_FLOAT};
constexpr int kFloatOrNormalized[] = {TINYGLTF_COMPONENT_TYPE_FLOAT,
                                      TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE,
                                      TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT};
// KHR_mesh_quantization: POSITION and TEXCOORD_n any 8- or 16-bit integer, normalized or not;
// NORMAL and TANGENT signed 8- or 16-bit normalized (checked in readVertices).
constexpr int kQuantized[] = {TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_COMPONENT_TYPE_BYTE,
                              TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE, TINYGLTF_COMPONENT_TYPE_SHORT,
                              TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT};
constexpr int kQuantizedDirection[] = {TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_COMPONENT_TYPE_BYTE,
                                       TINYGLTF_COMPONENT_TYPE_SHORT};

// KHR_mesh_quantization's NORMAL and TANGENT are integers only when normalized.
void requireNormalizedIntegers(const Context& ctx, const std::string& object,
                               const tinygltf::Primitive& primitive, const std::string& semantic) {
  const auto found = primitive.attributes.find(semantic);
  if (found == primitive.attributes.end()) return;
  const tinygltf::Accessor& accessor = ctx.model.accessors[static_cast<std::size_t>(found->second)];
  if (accessor.componentType != TINYGLTF_COMPONENT_TYPE_FLOAT && !accessor.normalized) {
    ctx.fail(object + ".attributes." + semantic,
             at("accessors", static_cast<std::size_t>(found->second)) + " has componentType " +
                 componentTypeName(accessor.componentType) + " but is not normalized; " + semantic +
                 " must be (KHR_mesh_quantization)");
  }
}

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

// Line strips and loops as pairs of indices (glTF 3.7.2.1); lines as they are.
std::vector<std::uint32_t> toLinePairs(const std::vector<std::uint32_t>& in, int mode) {
  if (mode == TINYGLTF_MODE_LINE) return {in.begin(), in.begin() + in.size() / 2 * 2};
  std::vector<std::uint32_t> out;
  for (std::size_t i = 0; i + 1 < in.size(); ++i) out.insert(out.end(), {in[i], in[i + 1]});
  if (mode == TINYGLTF_MODE_LINE_LOOP && in.size() > 2) out.insert(out.end(), {in.back(), in[0]});
  return out;
}

// Warns about primitives that are not drawn (no POSITION) and returns false for them; fails for
// modes glTF does not define.
bool isDrawn(Context& ctx, const tinygltf::Primitive& primitive, const std::string& object,
             int mode) {
  if (mode < TINYGLTF_MODE_POINTS || mode > TINYGLTF_MODE_TRIANGLE_FAN) {
    ctx.fail(object, "invalid mode " + std::to_string(mode) + " (glTF defines 0 to 6)");
  }
  if (primitive.attributes.count("POSITION") == 0) {
    ctx.warn(object + ": no POSITION attribute; not drawn");
    return false;
  }
  return true;
}

// glTF requires min and max on every POSITION accessor (3.7.2.1), primitive and morph target
// alike. Nothing here reads them (bounds come from the values), so the file still draws as it
// says; a warning names the accessor.
void warnAboutPositionsWithoutBounds(const Context& ctx, const std::string& object,
                                     const tinygltf::Primitive& primitive) {
  const auto check = [&](const std::map<std::string, int>& attributes, const std::string& owner) {
    const auto found = attributes.find("POSITION");
    if (found == attributes.end() || found->second < 0 ||
        static_cast<std::size_t>(found->second) >= ctx.model.accessors.size()) {
      return;
    }
    const tinygltf::Accessor& accessor =
        ctx.model.accessors[static_cast<std::size_t>(found->second)];
    if (!accessor.minValues.empty() && !accessor.maxValues.empty()) return;
    ctx.warn(owner + ".POSITION: " + at("accessors", static_cast<std::size_t>(found->second)) +
             " has no min/max, which glTF requires; bounds are computed from its values");
  };
  check(primitive.attributes, object + ".attributes");
  for (std::size_t t = 0; t < primitive.targets.size(); ++t) {
    check(primitive.targets[t], object + "." + at("targets", t));
  }
}

// Float COLOR_0 values must lie in 0..1 (glTF 3.7.2.1); integer ones always do. Values outside
// would brighten or negate the base color: they are clamped (NaN reads as 1, no tint), and a
// warning names the accessor.
void clampColors(const Context& ctx, const std::string& object,
                 const tinygltf::Primitive& primitive, AccessorValues& colors) {
  std::size_t outside = 0, first = 0;
  for (std::size_t i = 0; i < colors.values.size(); ++i) {
    double& value = colors.values[i];
    if (value >= 0.0 && value <= 1.0) continue;
    if (outside++ == 0) first = i;
    value = std::isnan(value) ? 1.0 : std::clamp(value, 0.0, 1.0);
  }
  if (outside == 0) return;
  const auto components = static_cast<std::size_t>(colors.components);
  ctx.warn(object + ".attributes.COLOR_0: " +
           at("accessors", static_cast<std::size_t>(primitive.attributes.at("COLOR_0"))) + " has " +
           std::to_string(outside) + " values outside 0..1 (the first at element " +
           std::to_string(first / components) + "); clamped to 0..1");
}

// Reads the vertex attributes into `mesh`, or returns false (with a warning) when POSITION
// holds non-finite values.
bool readVertices(Context& ctx, const tinygltf::Primitive& primitive, const std::string& object,
                  Mesh& mesh) {
  const int vec2 = TINYGLTF_TYPE_VEC2, vec3 = TINYGLTF_TYPE_VEC3, vec4 = TINYGLTF_TYPE_VEC4;
  using Types = std::span<const int>;
  const Types positionTypes = ctx.quantized ? Types(kQuantized) : Types(kFloatOnly);
  const Types directionTypes = ctx.quantized ? Types(kQuantizedDirection) : Types(kFloatOnly);
  const Types texcoordTypes = ctx.quantized ? Types(kQuantized) : Types(kFloatOrNormalized);
  // Quantized texture coordinates are integers unless flagged normalized (a texture transform
  // scales them); the core specification only has normalized ones.
  const Normalize texcoordNormalize = ctx.quantized ? Normalize::AsFlagged : Normalize::Integers;
  mesh.positions = toVectors<3>(readAttribute(ctx, object, primitive, "POSITION", {vec3},
                                              positionTypes, SIZE_MAX, Normalize::AsFlagged));
  const std::size_t n = mesh.positions.size();
  // Non-finite positions would poison bounds, cameras and shadow ranges: skip the primitive.
  if (std::any_of(mesh.positions.begin(), mesh.positions.end(), [](const glm::vec3& p) {
        return !std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z);
      })) {
    ctx.warn(object + ": POSITION has non-finite values; primitive not drawn");
    return false;
  }
  mesh.normals = toVectors<3>(readAttribute(ctx, object, primitive, "NORMAL", {vec3},
                                            directionTypes, n, Normalize::AsFlagged));
  for (glm::vec3& normal : mesh.normals) {
    const float length = glm::length(normal);
    if (length > 0.0f && std::isfinite(length)) normal /= length;
  }
  mesh.tangents = toVectors<4>(readAttribute(ctx, object, primitive, "TANGENT", {vec4},
                                             directionTypes, n, Normalize::AsFlagged));
  if (ctx.quantized) {
    requireNormalizedIntegers(ctx, object, primitive, "NORMAL");
    requireNormalizedIntegers(ctx, object, primitive, "TANGENT");
  }
  mesh.uv0 = toVectors<2>(readAttribute(ctx, object, primitive, "TEXCOORD_0", {vec2}, texcoordTypes,
                                        n, texcoordNormalize));
  mesh.uv1 = toVectors<2>(readAttribute(ctx, object, primitive, "TEXCOORD_1", {vec2}, texcoordTypes,
                                        n, texcoordNormalize));
  AccessorValues colors = readAttribute(ctx, object, primitive, "COLOR_0", {vec3, vec4},
                                        kFloatOrNormalized, n, Normalize::Integers);
  clampColors(ctx, object, primitive, colors);
  mesh.colors = toVectors<4>(colors);
  if (colors.components == 3) {
    for (glm::vec4& color : mesh.colors) color.a = 1.0f;
  }
  return true;
}

// glTF forbids the largest value of the index type (3.7.2.1): WebGL, WebGPU and Metal always
// restart the primitive there, desktop GL without restart draws a vertex, so the file has no
// one picture. An input error, as for the other values the specification rules out.
void rejectPrimitiveRestart(const Context& ctx, const std::string& object, int accessorIndex,
                            const AccessorValues& values) {
  const int componentType =
      ctx.model.accessors[static_cast<std::size_t>(accessorIndex)].componentType;
  const double restart = componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE    ? 255.0
                         : componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT ? 65535.0
                                                                                   : 4294967295.0;
  const auto found = std::find(values.values.begin(), values.values.end(), restart);
  if (found == values.values.end()) return;
  ctx.fail(object + ".indices",
           at("accessors", static_cast<std::size_t>(accessorIndex)) + " element " +
               std::to_string(found - values.values.begin()) + " is " +
               std::to_string(static_cast<std::uint64_t>(restart)) +
               ", the primitive restart value of " + componentTypeName(componentType) +
               ", which glTF forbids in indices (renderers disagree on what it draws)");
}

// The primitive's indices (0, 1, 2, ... without an index accessor), each checked against the
// vertex count n.
std::vector<std::uint32_t> readIndices(Context& ctx, int accessorIndex, const std::string& object,
                                       std::size_t n) {
  std::vector<std::uint32_t> indices;
  if (accessorIndex >= 0) {
    ctx.checkIndex(object + ".indices", "accessor", accessorIndex, ctx.model.accessors.size());
    const tinygltf::Accessor& accessor =
        ctx.model.accessors[static_cast<std::size_t>(accessorIndex)];
    if (accessor.type != TINYGLTF_TYPE_SCALAR ||
        (accessor.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE &&
         accessor.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
         accessor.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT)) {
      ctx.fail(object + ".indices", at("accessors", static_cast<std::size_t>(accessorIndex)) +
                                        " must be SCALAR unsigned byte, short or int");
    }
    const AccessorValues values = readAccessor(ctx, accessorIndex, Normalize::Never);
    rejectPrimitiveRestart(ctx, object, accessorIndex, values);
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
  return indices;
}

// A zero or non-finite NORMAL (the spec asks for unit length) shades its triangles black: the
// whole primitive gets flat normals instead, with a warning.
void replaceUnusableNormals(Context& ctx, const std::string& object, Mesh& mesh) {
  const auto unusable = std::count_if(mesh.normals.begin(), mesh.normals.end(), [](glm::vec3 n) {
    const float length = glm::length(n);
    return !(length > 0.0f) || !std::isfinite(length);
  });
  if (unusable == 0) return;
  ctx.warn(object + ": " + std::to_string(unusable) +
           " NORMAL values are zero or not finite; generated flat normals");
  mesh.normals.clear();
  mesh.tangents.clear();
  generateNormals(mesh);
}

// Generates what the file left out: flat normals, and tangents where a normal map (the
// material's or its clearcoat's) needs them.
void generateMissing(Context& ctx, const std::string& object, Mesh& mesh) {
  if (mesh.normals.empty()) {
    mesh.tangents.clear();  // the spec says to ignore tangents given without normals
    generateNormals(mesh);
    ctx.warn(object + ": no normals; generated flat normals");
  }
  if (mesh.tangents.empty() && mesh.material >= 0) {
    const TextureSlot& normalMap =
        tangentSpaceNormalMap(ctx.scene.materials[static_cast<std::size_t>(mesh.material)]);
    const std::vector<glm::vec2>& uvs = normalMap.texCoord == 0 ? mesh.uv0 : mesh.uv1;
    if (normalMap.texture >= 0 && !uvs.empty()) generateTangents(mesh, uvs);
  }
}

}  // namespace

std::optional<Mesh> convertPrimitive(Context& ctx, std::size_t meshIndex, std::size_t primIndex) {
  const tinygltf::Mesh& source = ctx.model.meshes[meshIndex];
  const tinygltf::Primitive& primitive = source.primitives[primIndex];
  const std::string object = at("meshes", meshIndex) + "." + at("primitives", primIndex);
  // tinygltf gives TRIANGLES where the file has no mode, so a negative one is the file's own.
  const int mode = primitive.mode;
  if (!isDrawn(ctx, primitive, object, mode)) return std::nullopt;
  warnAboutPositionsWithoutBounds(ctx, object, primitive);

  Mesh mesh;
  mesh.name = nameOrDefault(source.name, "mesh", static_cast<std::size_t>(meshIndex)) + "/" +
              std::to_string(primIndex);
  if (primitive.material >= 0)
    ctx.checkIndex(object, "material", primitive.material, ctx.model.materials.size());
  mesh.material = primitiveMaterial(ctx, primitive, object, std::max(primitive.material, -1));
  ctx.primitive = object;
  decodeDraco(ctx, meshIndex, primIndex);
  const bool drawn = readVertices(ctx, primitive, object, mesh);
  const int indices = indicesAccessor(ctx, meshIndex, primIndex);
  if (drawn) {
    std::vector<std::uint32_t> list = readIndices(ctx, indices, object, mesh.positions.size());
    if (mode == TINYGLTF_MODE_POINTS) {
      mesh.pointIndices = std::move(list);
    } else if (mode < TINYGLTF_MODE_TRIANGLES) {
      mesh.lineIndices = toLinePairs(list, mode);
    } else {
      mesh.indices = toTriangleList(list, mode);
    }
  }
  ctx.dracoAccessors.clear();
  ctx.primitive.clear();
  if (!drawn) return std::nullopt;
  if (mesh.indices.size() % 3 != 0) {
    ctx.warn(object + ": " + std::to_string(mesh.indices.size()) +
             " indices is not a multiple of 3; the last triangle is dropped");
    mesh.indices.resize(mesh.indices.size() / 3 * 3);
  }
  // Points and lines are drawn unlit: they need no normals.
  if (mode >= TINYGLTF_MODE_TRIANGLES) {
    replaceUnusableNormals(ctx, object, mesh);
    generateMissing(ctx, object, mesh);
  }
  for (const glm::vec3& p : mesh.positions) mesh.bounds.extend(p);
  return mesh;
}

std::vector<std::uint32_t> fileTriangleIndices(Context& ctx, std::size_t meshIndex,
                                               std::size_t primIndex) {
  const tinygltf::Primitive& primitive = ctx.model.meshes[meshIndex].primitives[primIndex];
  const std::string object = at("meshes", meshIndex) + "." + at("primitives", primIndex);
  const int mode = primitive.mode < 0 ? TINYGLTF_MODE_TRIANGLES : primitive.mode;
  const std::size_t n =
      ctx.model.accessors[static_cast<std::size_t>(primitive.attributes.at("POSITION"))].count;
  // The same decoded data convertPrimitive() reads (Draco primitives included).
  ctx.primitive = object;
  decodeDraco(ctx, meshIndex, primIndex);
  std::vector<std::uint32_t> indices =
      toTriangleList(readIndices(ctx, indicesAccessor(ctx, meshIndex, primIndex), object, n), mode);
  ctx.dracoAccessors.clear();
  ctx.primitive.clear();
  indices.resize(indices.size() / 3 * 3);
  return indices;
}

}  // namespace omnishadow::gltf_detail
