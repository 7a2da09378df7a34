#include "scenes/builder/gltf_builder.h"

#include <tiny_gltf.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <exception>
#include <fstream>
#include <functional>
#include <glm/gtc/type_ptr.hpp>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace omnishadow::builder {

namespace {

constexpr float kPi = std::numbers::pi_v<float>;

// ---------------------------------------------------------------------------------------------
// Procedural geometry helpers

void addQuad(MeshData& mesh, std::uint32_t a, std::uint32_t b, std::uint32_t c, std::uint32_t d) {
  mesh.indices.insert(mesh.indices.end(), {a, b, c, a, c, d});
}

std::uint32_t vertexCount(const MeshData& mesh) {
  return static_cast<std::uint32_t>(mesh.positions.size());
}

// Rotation that turns the local -Z axis into `forward` with local +Y as close to world +Y as
// possible. Looking straight down or up leaves +Y undefined; we then keep the image's top
// pointing to -Z (down) or +Z (up), so that turning the camera slightly never flips the picture.
glm::quat lookRotation(glm::vec3 forward) {
  if (glm::length(forward) < 1e-12f) return glm::quat(1.0f, 0.0f, 0.0f, 0.0f);
  const glm::vec3 f = glm::normalize(forward);
  glm::vec3 up{0.0f, 1.0f, 0.0f};
  if (glm::length(glm::cross(f, up)) < 1e-6f) {
    up = f.y < 0.0f ? glm::vec3(0, 0, -1) : glm::vec3(0, 0, 1);
  }
  const glm::vec3 right = glm::normalize(glm::cross(f, up));
  const glm::vec3 trueUp = glm::cross(right, f);
  const glm::mat3 basis(right, trueUp, -f);
  return glm::normalize(glm::quat_cast(basis));
}

// ---------------------------------------------------------------------------------------------
// Binary packing

template <typename T>
void appendBytes(std::vector<unsigned char>& out, const T* data, std::size_t count) {
  const auto* bytes = reinterpret_cast<const unsigned char*>(data);
  out.insert(out.end(), bytes, bytes + count * sizeof(T));
}

// glTF wants every accessor aligned to its component size; padding every view to 4 bytes
// covers all component types at once.
void alignTo4(std::vector<unsigned char>& data) {
  while (data.size() % 4 != 0) data.push_back(0);
}

std::vector<double> toDoubles(const float* values, int count) {
  return std::vector<double>(values, values + count);
}

// Encodes the image's 8-bit pixels as PNG with the stb_image_write inside libtinygltf (the
// package ships no stb headers). Embedded, tinygltf returns a data URI; otherwise it hands the
// bytes to a "write whole file" callback, which here keeps them in memory.
struct EncodedImage {
  std::vector<unsigned char> png;
  std::string dataUri;
};

EncodedImage encodePng(const tinygltf::Image& image, bool asDataUri) {
  EncodedImage encoded;
  tinygltf::FsCallbacks capture{};
  capture.WriteWholeFile = [](std::string*, const std::string&,
                              const std::vector<unsigned char>& contents, void* user) {
    *static_cast<std::vector<unsigned char>*>(user) = contents;
    return true;
  };
  capture.user_data = &encoded.png;
  const std::string basePath;
  const std::string fileName = "image.png";
  if (!tinygltf::WriteImageData(&basePath, &fileName, &image, asDataUri, &encoded.dataUri,
                                &capture) ||
      (asDataUri ? encoded.dataUri.empty() : encoded.png.empty())) {
    throw std::runtime_error("gltf_builder: cannot encode image \"" + image.name + "\" as PNG");
  }
  return encoded;
}

void writeFile(const std::filesystem::path& path, const std::vector<unsigned char>& bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(bytes.data()),
            static_cast<std::streamsize>(bytes.size()));
  out.close();
  if (!out) throw std::runtime_error("gltf_builder: cannot write " + path.string());
}

}  // namespace

int runGenerator(int argc, char** argv, int minArguments, int maxArguments, const char* usage,
                 const std::function<void(char** arguments)>& generate) {
  const int given = argc - 1;
  if (given < minArguments || given > maxArguments) {
    std::fprintf(stderr, "usage: %s\n", usage);
    return 2;
  }
  try {
    generate(argv);
  } catch (const std::exception& e) {
    const std::string program(usage, std::strcspn(usage, " "));
    std::fprintf(stderr, "%s: %s\n", program.c_str(), e.what());
    return 1;
  }
  return 0;
}

int appendBufferView(tinygltf::Model& model, const std::vector<unsigned char>& bytes, int target,
                     std::size_t byteStride) {
  if (model.buffers.empty()) model.buffers.emplace_back();
  std::vector<unsigned char>& data = model.buffers[0].data;
  alignTo4(data);
  tinygltf::BufferView view;
  view.buffer = 0;
  view.byteOffset = data.size();
  view.byteLength = bytes.size();
  view.byteStride = byteStride;
  view.target = target;
  data.insert(data.end(), bytes.begin(), bytes.end());
  model.bufferViews.push_back(std::move(view));
  return static_cast<int>(model.bufferViews.size()) - 1;
}

// -----------------------------------------------------------------------------------------------
// Procedural meshes

const BoxFace kBoxFaces[6] = {
    {{1, 0, 0}, {0, 0, -1}, {0, 1, 0}}, {{-1, 0, 0}, {0, 0, 1}, {0, 1, 0}},
    {{0, 1, 0}, {1, 0, 0}, {0, 0, -1}}, {{0, -1, 0}, {1, 0, 0}, {0, 0, 1}},
    {{0, 0, 1}, {1, 0, 0}, {0, 1, 0}},  {{0, 0, -1}, {-1, 0, 0}, {0, 1, 0}},
};

MeshData makeBox(glm::vec3 halfExtents) {
  static constexpr float kCorners[4][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
  MeshData mesh;
  for (const BoxFace& face : kBoxFaces) {
    const std::uint32_t base = vertexCount(mesh);
    for (const auto& c : kCorners) {
      mesh.positions.push_back((face.normal + c[0] * face.u + c[1] * face.v) * halfExtents);
      mesh.normals.push_back(face.normal);
      // glTF's v axis points down the image.
      mesh.uvs.push_back({0.5f * (c[0] + 1.0f), 0.5f * (1.0f - c[1])});
    }
    addQuad(mesh, base, base + 1, base + 2, base + 3);
  }
  return mesh;
}

MeshData makeSphere(float radius, int segments, int rings) {
  if (segments < 3 || rings < 2) {
    throw std::invalid_argument("makeSphere: needs segments >= 3 and rings >= 2");
  }
  MeshData mesh;
  // Seam and pole vertices are duplicated so that every vertex has one UV.
  for (int i = 0; i <= rings; ++i) {
    const float theta = kPi * static_cast<float>(i) / static_cast<float>(rings);
    for (int j = 0; j <= segments; ++j) {
      // The seam's and the poles' copies get bit-identical positions (watertight: no
      // cracks, and renderer/mesh_topology.cpp sees a closed solid).
      const float phi =
          2.0f * kPi * static_cast<float>(j % segments) / static_cast<float>(segments);
      const float ring = i == 0 || i == rings ? 0.0f : std::sin(theta);
      const glm::vec3 n{ring * std::sin(phi), std::cos(theta), ring * std::cos(phi)};
      mesh.positions.push_back(radius * n);
      mesh.normals.push_back(n);
      mesh.uvs.push_back({static_cast<float>(j) / static_cast<float>(segments),
                          static_cast<float>(i) / static_cast<float>(rings)});
    }
  }
  const auto at = [segments](int i, int j) {
    return static_cast<std::uint32_t>(i * (segments + 1) + j);
  };
  for (int i = 0; i < rings; ++i) {
    for (int j = 0; j < segments; ++j) {
      const std::uint32_t a = at(i, j), b = at(i + 1, j), c = at(i + 1, j + 1), d = at(i, j + 1);
      // At the poles one triangle of each quad has zero area; leave it out.
      if (i != rings - 1) mesh.indices.insert(mesh.indices.end(), {a, b, c});
      if (i != 0) mesh.indices.insert(mesh.indices.end(), {a, c, d});
    }
  }
  return mesh;
}

MeshData makePlane(float size, int subdivisions) {
  if (subdivisions < 1) throw std::invalid_argument("makePlane: needs subdivisions >= 1");
  MeshData mesh;
  const int n = subdivisions;
  for (int i = 0; i <= n; ++i) {
    for (int j = 0; j <= n; ++j) {
      const float s = static_cast<float>(j) / static_cast<float>(n);
      const float t = static_cast<float>(i) / static_cast<float>(n);
      mesh.positions.push_back({(s - 0.5f) * size, 0.0f, (t - 0.5f) * size});
      mesh.normals.push_back({0.0f, 1.0f, 0.0f});
      mesh.uvs.push_back({s, t});
    }
  }
  const auto at = [n](int i, int j) { return static_cast<std::uint32_t>(i * (n + 1) + j); };
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j)
      addQuad(mesh, at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
  }
  return mesh;
}

MeshData makeCylinder(float radius, float height, int segments) {
  if (segments < 3) throw std::invalid_argument("makeCylinder: needs segments >= 3");
  MeshData mesh;
  // The seam's copies at j = segments repeat j = 0 bit for bit (watertight).
  const auto angle = [segments](int j) {
    return 2.0f * kPi * static_cast<float>(j % segments) / static_cast<float>(segments);
  };
  // Side: a top and a bottom vertex per segment edge, seam duplicated for the UVs.
  for (int j = 0; j <= segments; ++j) {
    const glm::vec3 n{std::sin(angle(j)), 0.0f, std::cos(angle(j))};
    const float u = static_cast<float>(j) / static_cast<float>(segments);
    mesh.positions.push_back(radius * n + glm::vec3(0.0f, height, 0.0f));
    mesh.normals.push_back(n);
    mesh.uvs.push_back({u, 0.0f});
    mesh.positions.push_back(radius * n);
    mesh.normals.push_back(n);
    mesh.uvs.push_back({u, 1.0f});
  }
  for (int j = 0; j < segments; ++j) {
    const auto top = static_cast<std::uint32_t>(2 * j);
    addQuad(mesh, top, top + 1, top + 3, top + 2);
  }
  // Caps: a center vertex and a ring with the cap's own normal (hard edge at the rim).
  for (const bool isTop : {true, false}) {
    const float y = isTop ? height : 0.0f;
    const glm::vec3 n{0.0f, isTop ? 1.0f : -1.0f, 0.0f};
    const std::uint32_t center = vertexCount(mesh);
    mesh.positions.push_back({0.0f, y, 0.0f});
    mesh.normals.push_back(n);
    mesh.uvs.push_back({0.5f, 0.5f});
    for (int j = 0; j <= segments; ++j) {
      const float s = std::sin(angle(j)), c = std::cos(angle(j));
      mesh.positions.push_back({radius * s, y, radius * c});
      mesh.normals.push_back(n);
      mesh.uvs.push_back({0.5f + 0.5f * s, 0.5f - 0.5f * c});
    }
    for (int j = 0; j < segments; ++j) {
      const std::uint32_t p = center + 1 + static_cast<std::uint32_t>(j);
      if (isTop) {
        mesh.indices.insert(mesh.indices.end(), {center, p, p + 1});
      } else {
        mesh.indices.insert(mesh.indices.end(), {center, p + 1, p});
      }
    }
  }
  return mesh;
}

// -----------------------------------------------------------------------------------------------
// GltfBuilder

struct GltfBuilder::Impl {
  tinygltf::Model model;
  std::vector<tinygltf::Value> lights;  // KHR_lights_punctual, mirrored into model.extensions

  int addBufferView(const std::vector<unsigned char>& bytes, int target) {
    return appendBufferView(model, bytes, target);
  }

  template <typename T>
  int addAccessor(const std::vector<T>& values, int componentType, int type, int target) {
    std::vector<unsigned char> bytes;
    appendBytes(bytes, values.data(), values.size());
    tinygltf::Accessor accessor;
    accessor.bufferView = addBufferView(bytes, target);
    accessor.componentType = componentType;
    accessor.type = type;
    accessor.count = values.size();
    model.accessors.push_back(std::move(accessor));
    return static_cast<int>(model.accessors.size()) - 1;
  }

  int addPositions(const std::vector<glm::vec3>& positions) {
    const int index = addAccessor(positions, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3,
                                  TINYGLTF_TARGET_ARRAY_BUFFER);
    glm::vec3 lo{std::numeric_limits<float>::max()}, hi{std::numeric_limits<float>::lowest()};
    for (const glm::vec3& p : positions) {
      lo = glm::min(lo, p);
      hi = glm::max(hi, p);
    }
    if (positions.empty()) lo = hi = glm::vec3(0.0f);
    model.accessors[index].minValues = toDoubles(glm::value_ptr(lo), 3);
    model.accessors[index].maxValues = toDoubles(glm::value_ptr(hi), 3);
    return index;
  }

  int addIndices(const std::vector<std::uint32_t>& indices, IndexType type) {
    // The largest value of each type is reserved for primitive restart by the glTF spec, so it
    // does not fit either.
    const auto convert = [&indices]<typename T>(T) {
      std::vector<T> out;
      out.reserve(indices.size());
      for (std::uint32_t index : indices) {
        if (index >= std::numeric_limits<T>::max()) {
          throw std::out_of_range("gltf_builder: index " + std::to_string(index) +
                                  " does not fit the index type");
        }
        out.push_back(static_cast<T>(index));
      }
      return out;
    };
    constexpr int kTarget = TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER;
    switch (type) {
      case IndexType::U8:
        return addAccessor(convert(std::uint8_t{}), TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE,
                           TINYGLTF_TYPE_SCALAR, kTarget);
      case IndexType::U16:
        return addAccessor(convert(std::uint16_t{}), TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT,
                           TINYGLTF_TYPE_SCALAR, kTarget);
      case IndexType::U32:
        break;
    }
    return addAccessor(convert(std::uint32_t{}), TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT,
                       TINYGLTF_TYPE_SCALAR, kTarget);
  }

  tinygltf::Primitive makePrimitive(const MeshData& data, const PrimitiveOptions& options) {
    const std::size_t n = data.positions.size();
    if ((!data.normals.empty() && data.normals.size() != n) ||
        (!data.uvs.empty() && data.uvs.size() != n)) {
      throw std::invalid_argument("gltf_builder: normals/uvs must match the positions' count");
    }
    if (options.material >= static_cast<int>(model.materials.size())) {
      throw std::out_of_range("gltf_builder: no material " + std::to_string(options.material));
    }
    tinygltf::Primitive primitive;
    primitive.mode = static_cast<int>(options.mode);
    primitive.material = options.material;
    primitive.attributes["POSITION"] = addPositions(data.positions);
    if (!data.normals.empty()) {
      primitive.attributes["NORMAL"] =
          addAccessor(data.normals, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3,
                      TINYGLTF_TARGET_ARRAY_BUFFER);
    }
    if (!data.uvs.empty()) {
      primitive.attributes["TEXCOORD_0"] =
          addAccessor(data.uvs, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC2,
                      TINYGLTF_TARGET_ARRAY_BUFFER);
    }
    // Indices are not checked against the vertex count: tests build broken files on purpose.
    if (!data.indices.empty()) primitive.indices = addIndices(data.indices, options.indexType);
    return primitive;
  }

  int addNode(tinygltf::Node node, int parent) {
    const int index = static_cast<int>(model.nodes.size());
    if (parent >= index) throw std::out_of_range("gltf_builder: no node " + std::to_string(parent));
    if (node.mesh >= static_cast<int>(model.meshes.size())) {
      throw std::out_of_range("gltf_builder: no mesh " + std::to_string(node.mesh));
    }
    model.nodes.push_back(std::move(node));
    if (parent < 0) {
      model.scenes[0].nodes.push_back(index);
    } else {
      model.nodes[parent].children.push_back(index);
    }
    return index;
  }

  void useExtension(const std::string& name) {
    auto& used = model.extensionsUsed;
    if (std::find(used.begin(), used.end(), name) == used.end()) used.push_back(name);
  }

  // Replaces each image's pixels by a PNG stored the way `format` wants it, then writes.
  void write(const std::filesystem::path& path, FileFormat format) const {
    tinygltf::Model out = model;
    const std::string stem = path.stem().string();
    for (std::size_t i = 0; i < out.images.size(); ++i) {
      tinygltf::Image& image = out.images[i];
      // Images a caller placed through model() (a bufferView or URI) are written as they are.
      if (image.bufferView >= 0 || !image.uri.empty()) continue;
      const EncodedImage encoded = encodePng(image, format == FileFormat::GltfEmbedded);
      const std::vector<unsigned char>& png = encoded.png;
      image.image.clear();
      image.mimeType = "image/png";
      switch (format) {
        case FileFormat::GltfEmbedded:
          image.uri = encoded.dataUri;
          break;
        case FileFormat::GltfExternal:
          image.uri = stem + "_image" + std::to_string(i) + ".png";
          writeFile(path.parent_path() / image.uri, png);
          break;
        case FileFormat::Glb: {
          image.bufferView = appendBufferView(out, png, 0);
          break;
        }
      }
    }

    tinygltf::TinyGLTF writer;
    // The images above are already encoded and placed. tinygltf's own image writer would
    // re-encode them, and for external files it names the PNGs but never writes them (2.7.0
    // passes it no file callbacks).
    writer.SetImageWriter(nullptr, nullptr);
    const bool embed = format == FileFormat::GltfEmbedded;
    const bool binary = format == FileFormat::Glb;
    std::error_code ignored;
    std::filesystem::remove(path, ignored);
    if (!writer.WriteGltfSceneToFile(&out, path.string(), /*embedImages=*/embed,
                                     /*embedBuffers=*/embed, /*prettyPrint=*/true,
                                     /*writeBinary=*/binary) ||
        !std::filesystem::is_regular_file(path, ignored) ||
        std::filesystem::file_size(path, ignored) == 0) {
      throw std::runtime_error("gltf_builder: cannot write " + path.string());
    }
  }
};

GltfBuilder::GltfBuilder() : impl_(new Impl) {
  tinygltf::Model& model = impl_->model;
  model.asset.version = "2.0";
  model.asset.generator = "omnishadow gltf_builder";
  model.scenes.emplace_back();
  model.scenes[0].name = "scene";
  model.defaultScene = 0;
}

GltfBuilder::~GltfBuilder() {
  delete impl_;
}

int GltfBuilder::addTexture(int width, int height, const std::vector<std::uint8_t>& rgba,
                            const std::string& name) {
  if (width <= 0 || height <= 0 ||
      rgba.size() != static_cast<std::size_t>(width) * static_cast<std::size_t>(height) * 4) {
    throw std::invalid_argument("gltf_builder: addTexture needs width * height * 4 bytes");
  }
  tinygltf::Model& model = impl_->model;
  tinygltf::Image image;
  image.name = name;
  image.width = width;
  image.height = height;
  image.component = 4;
  image.bits = 8;
  image.pixel_type = TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE;
  image.image = rgba;
  image.mimeType = "image/png";
  model.images.push_back(std::move(image));

  tinygltf::Texture texture;
  texture.name = name;
  texture.source = static_cast<int>(model.images.size()) - 1;
  model.textures.push_back(std::move(texture));
  return static_cast<int>(model.textures.size()) - 1;
}

int GltfBuilder::addMaterial(const MaterialDesc& desc) {
  tinygltf::Model& model = impl_->model;
  for (int texture : {desc.baseColorTexture, desc.metallicRoughnessTexture, desc.normalTexture,
                      desc.emissiveTexture}) {
    if (texture >= static_cast<int>(model.textures.size())) {
      throw std::out_of_range("gltf_builder: no texture " + std::to_string(texture));
    }
  }
  tinygltf::Material material;
  material.name = desc.name;
  auto& pbr = material.pbrMetallicRoughness;
  pbr.baseColorFactor = toDoubles(glm::value_ptr(desc.baseColor), 4);
  pbr.metallicFactor = desc.metallic;
  pbr.roughnessFactor = desc.roughness;
  pbr.baseColorTexture.index = desc.baseColorTexture;
  pbr.metallicRoughnessTexture.index = desc.metallicRoughnessTexture;
  material.normalTexture.index = desc.normalTexture;
  material.emissiveTexture.index = desc.emissiveTexture;
  material.alphaMode = desc.alphaMode;
  material.alphaCutoff = desc.alphaCutoff;
  material.doubleSided = desc.doubleSided;

  // glTF caps emissiveFactor at 1; brighter emission goes through KHR_materials_emissive_strength.
  const float peak = std::max({desc.emissive.r, desc.emissive.g, desc.emissive.b});
  glm::vec3 emissive = desc.emissive;
  if (peak > 1.0f) {
    emissive /= peak;
    tinygltf::Value::Object strength;
    strength["emissiveStrength"] = tinygltf::Value(static_cast<double>(peak));
    material.extensions["KHR_materials_emissive_strength"] = tinygltf::Value(std::move(strength));
    impl_->useExtension("KHR_materials_emissive_strength");
  }
  material.emissiveFactor = toDoubles(glm::value_ptr(emissive), 3);

  model.materials.push_back(std::move(material));
  return static_cast<int>(model.materials.size()) - 1;
}

int GltfBuilder::addTexturedMesh(const MeshData& data, int baseColorTexture) {
  MaterialDesc material;
  material.baseColorTexture = baseColorTexture;
  return addMesh(data, {.material = addMaterial(material)});
}

int GltfBuilder::addMesh(const MeshData& data, const PrimitiveOptions& options,
                         const std::string& name) {
  tinygltf::Mesh mesh;
  mesh.name = name;
  mesh.primitives.push_back(impl_->makePrimitive(data, options));
  impl_->model.meshes.push_back(std::move(mesh));
  return static_cast<int>(impl_->model.meshes.size()) - 1;
}

void GltfBuilder::addPrimitive(int mesh, const MeshData& data, const PrimitiveOptions& options) {
  if (mesh < 0 || mesh >= static_cast<int>(impl_->model.meshes.size())) {
    throw std::out_of_range("gltf_builder: no mesh " + std::to_string(mesh));
  }
  tinygltf::Primitive primitive = impl_->makePrimitive(data, options);
  impl_->model.meshes[mesh].primitives.push_back(std::move(primitive));
}

int GltfBuilder::addNode(const std::string& name, const Transform& transform, int mesh,
                         int parent) {
  tinygltf::Node node;
  node.name = name;
  node.mesh = mesh;
  // Default components are left out, as most exporters do.
  if (transform.translation != glm::vec3(0.0f)) {
    node.translation = toDoubles(glm::value_ptr(transform.translation), 3);
  }
  const glm::quat& q = transform.rotation;
  if (q != glm::quat(1.0f, 0.0f, 0.0f, 0.0f)) node.rotation = {q.x, q.y, q.z, q.w};
  if (transform.scale != glm::vec3(1.0f))
    node.scale = toDoubles(glm::value_ptr(transform.scale), 3);
  return impl_->addNode(std::move(node), parent);
}

int GltfBuilder::addNodeWithMatrix(const std::string& name, const glm::mat4& matrix, int mesh,
                                   int parent) {
  tinygltf::Node node;
  node.name = name;
  node.mesh = mesh;
  node.matrix = toDoubles(glm::value_ptr(matrix), 16);  // both column-major
  return impl_->addNode(std::move(node), parent);
}

int GltfBuilder::addPerspectiveCamera(const std::string& name, glm::vec3 eye, glm::vec3 target,
                                      float yfovRadians, float aspectRatio, float znear,
                                      float zfar) {
  tinygltf::Model& model = impl_->model;
  tinygltf::Camera camera;
  camera.name = name;
  camera.type = "perspective";
  camera.perspective.yfov = yfovRadians;
  camera.perspective.aspectRatio = aspectRatio;
  camera.perspective.znear = znear;
  camera.perspective.zfar = zfar;
  model.cameras.push_back(std::move(camera));
  const int index = static_cast<int>(model.cameras.size()) - 1;

  tinygltf::Node node;
  node.name = name;
  node.camera = index;
  node.translation = toDoubles(glm::value_ptr(eye), 3);
  const glm::quat q = lookRotation(target - eye);
  node.rotation = {q.x, q.y, q.z, q.w};
  impl_->addNode(std::move(node), -1);
  return index;
}

int GltfBuilder::addLight(const std::string& name, const std::string& type, glm::vec3 position,
                          glm::vec3 direction, glm::vec3 color, float intensity, float range) {
  if (type != "point" && type != "spot" && type != "directional") {
    throw std::invalid_argument("gltf_builder: light type must be point, spot or directional");
  }
  using tinygltf::Value;
  Value::Object light;
  if (!name.empty()) light["name"] = Value(name);
  light["type"] = Value(type);
  light["color"] =
      Value(Value::Array{Value(static_cast<double>(color.r)), Value(static_cast<double>(color.g)),
                         Value(static_cast<double>(color.b))});
  light["intensity"] = Value(static_cast<double>(intensity));
  if (range > 0.0f) light["range"] = Value(static_cast<double>(range));
  if (type == "spot") {
    // The extension's defaults, written out so that readers need not know them.
    Value::Object spot;
    spot["innerConeAngle"] = Value(0.0);
    spot["outerConeAngle"] = Value(std::numbers::pi / 4.0);
    light["spot"] = Value(std::move(spot));
  }
  impl_->lights.emplace_back(std::move(light));
  const int index = static_cast<int>(impl_->lights.size()) - 1;

  tinygltf::Model& model = impl_->model;
  Value::Object extension;
  extension["lights"] = Value(impl_->lights);
  model.extensions["KHR_lights_punctual"] = Value(std::move(extension));
  impl_->useExtension("KHR_lights_punctual");

  tinygltf::Node node;
  node.name = name;
  node.translation = toDoubles(glm::value_ptr(position), 3);
  const glm::quat q = lookRotation(direction);
  if (q != glm::quat(1.0f, 0.0f, 0.0f, 0.0f)) node.rotation = {q.x, q.y, q.z, q.w};
  Value::Object link;
  link["light"] = Value(index);
  node.extensions["KHR_lights_punctual"] = Value(std::move(link));
  impl_->addNode(std::move(node), -1);
  return index;
}

tinygltf::Model& GltfBuilder::model() {
  return impl_->model;
}

void GltfBuilder::write(const std::filesystem::path& path, FileFormat format) {
  impl_->write(path, format);
}

}  // namespace omnishadow::builder
