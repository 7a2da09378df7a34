#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>
#include <string>
#include <vector>

namespace tinygltf {
class Model;
}

namespace omnishadow::builder {

// Geometry made in code for test and demo scenes.
struct MeshData {
  std::vector<glm::vec3> positions;
  std::vector<glm::vec3> normals;      // may be empty (the file then has no NORMAL)
  std::vector<glm::vec2> uvs;          // may be empty
  std::vector<std::uint32_t> indices;  // may be empty (non-indexed)
};

// The six faces of an axis-aligned box: outward normal and in-plane axes u, v with
// cross(u, v) = normal, so that corners (-u,-v), (+u,-v), (+u,+v), (-u,+v) run
// counter-clockwise seen from outside.
struct BoxFace {
  glm::vec3 normal, u, v;
};
extern const BoxFace kBoxFaces[6];

// Counter-clockwise triangles seen from outside, unit normals, UVs in [0,1].
MeshData makeBox(glm::vec3 halfExtents);
MeshData makeSphere(float radius, int segments, int rings);
// Square in the XZ plane facing +Y, centered at the origin.
MeshData makePlane(float size, int subdivisions = 1);
// Cylinder along +Y from y=0 to y=height, capped.
MeshData makeCylinder(float radius, float height, int segments);

// Appends `bytes` to buffer 0 (created if needed) as a new buffer view, 4-byte aligned so that
// any accessor may start at it; returns the view's index. target 0 = none (e.g. an image).
// What every scene generator's main() does: outside [minArguments, maxArguments] arguments it
// prints "usage: <usage>" and returns 2; otherwise it runs `generate`, and an exception from it
// is printed after the program's name (usage's first word) and returns 1.
int runGenerator(int argc, char** argv, int minArguments, int maxArguments, const char* usage,
                 const std::function<void(char** arguments)>& generate);

int appendBufferView(tinygltf::Model& model, const std::vector<unsigned char>& bytes,
                     int target = 0, std::size_t byteStride = 0);

struct MaterialDesc {
  std::string name;
  glm::vec4 baseColor{1.0f};
  float metallic = 0.0f;
  float roughness = 0.5f;
  glm::vec3 emissive{0.0f};
  std::string alphaMode = "OPAQUE";  // OPAQUE, MASK, BLEND
  float alphaCutoff = 0.5f;
  bool doubleSided = false;
  int baseColorTexture = -1;  // from addTexture()
  int metallicRoughnessTexture = -1;
  int normalTexture = -1;
  int emissiveTexture = -1;
};

enum class IndexType { U8, U16, U32 };
enum class PrimitiveMode { Triangles = 4, TriangleStrip = 5, TriangleFan = 6 };

struct PrimitiveOptions {
  IndexType indexType = IndexType::U32;  // ignored when the mesh has no indices
  PrimitiveMode mode = PrimitiveMode::Triangles;
  int material = -1;
};

struct Transform {
  glm::vec3 translation{0.0f};
  glm::quat rotation{1.0f, 0.0f, 0.0f, 0.0f};  // w, x, y, z
  glm::vec3 scale{1.0f};
};

enum class FileFormat {
  GltfEmbedded,  // .gltf with buffers and images as data URIs
  GltfExternal,  // .gltf + .bin + .png files next to it
  Glb,           // binary container
};

// Builds a tinygltf::Model step by step and writes it as .gltf/.glb. Indices returned are
// glTF indices of the created object. Every buffer view is tightly packed.
class GltfBuilder {
 public:
  GltfBuilder();
  ~GltfBuilder();
  GltfBuilder(const GltfBuilder&) = delete;
  GltfBuilder& operator=(const GltfBuilder&) = delete;

  // 8-bit RGBA pixels, first row = top; stored as PNG.
  int addTexture(int width, int height, const std::vector<std::uint8_t>& rgba,
                 const std::string& name = "");
  int addMaterial(const MaterialDesc& material);
  // A mesh with one primitive.
  int addMesh(const MeshData& data, const PrimitiveOptions& options = {},
              const std::string& name = "");
  // A mesh with one primitive whose new material's base color is `baseColorTexture`.
  int addTexturedMesh(const MeshData& data, int baseColorTexture);
  // Adds another primitive to an existing mesh.
  void addPrimitive(int mesh, const MeshData& data, const PrimitiveOptions& options = {});

  // Nodes; parent = -1 puts the node in the scene's root list.
  int addNode(const std::string& name, const Transform& transform, int mesh = -1, int parent = -1);
  int addNodeWithMatrix(const std::string& name, const glm::mat4& matrix, int mesh = -1,
                        int parent = -1);
  // Adds a perspective camera on a new node looking from eye to target.
  int addPerspectiveCamera(const std::string& name, glm::vec3 eye, glm::vec3 target,
                           float yfovRadians, float aspectRatio = 0.0f, float znear = 0.05f,
                           float zfar = 0.0f);
  // KHR_lights_punctual light on a new node at `position` pointing along `direction`.
  int addLight(const std::string& name, const std::string& type, glm::vec3 position,
               glm::vec3 direction, glm::vec3 color, float intensity, float range = 0.0f);

  tinygltf::Model& model();
  // Writes the file; throws std::runtime_error on failure.
  void write(const std::filesystem::path& path, FileFormat format);

 private:
  struct Impl;
  Impl* impl_;
};

}  // namespace omnishadow::builder
