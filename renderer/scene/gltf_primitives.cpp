#include "renderer/scene/gltf_primitives.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <initializer_list>
#include <span>
#include <string>
#include <vector>

#include "renderer/scene/gltf_accessors.h"
#include "renderer/scene/gltf_draco.h"
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
  const AccessorValues colors = readAttribute(ctx, object, primitive, "COLOR_0", {vec3, vec4},
                                              kFloatOrNormalized, n, Normalize::Integers);
  mesh.colors = toVectors<4>(colors);
  if (colors.components == 3) {
    for (glm::vec4& color : mesh.colors) color.a = 1.0f;
  }
  return true;
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

// Generates what the file left out: flat normals, and tangents where a normal map needs them.
void generateMissing(Context& ctx, const std::string& object, Mesh& mesh) {
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
}

}  // namespace

std::optional<Mesh> convertPrimitive(Context& ctx, std::size_t meshIndex, std::size_t primIndex) {
  const tinygltf::Mesh& source = ctx.model.meshes[meshIndex];
  const tinygltf::Primitive& primitive = source.primitives[primIndex];
  const std::string object = at("meshes", meshIndex) + "." + at("primitives", primIndex);
  // tinygltf gives TRIANGLES where the file has no mode, so a negative one is the file's own.
  const int mode = primitive.mode;
  if (!isDrawn(ctx, primitive, object, mode)) return std::nullopt;

  Mesh mesh;
  mesh.name = (source.name.empty() ? "mesh" + std::to_string(meshIndex) : source.name) + "/" +
              std::to_string(primIndex);
  if (primitive.material >= 0) {
    ctx.checkIndex(object, "material", primitive.material, ctx.model.materials.size());
    mesh.material = primitive.material;
  }
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
