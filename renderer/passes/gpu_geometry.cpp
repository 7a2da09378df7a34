#include "renderer/passes/gpu_geometry.h"

#include <algorithm>
#include <array>
#include <cstring>
#include <glm/gtc/type_ptr.hpp>
#include <tuple>

#include "renderer/core/in_parts.h"
#include "renderer/scene/bounds.h"
#include "renderer/scene/mesh_topology.h"
#include "renderer/scene/scene_fingerprint.h"

namespace omnishadow {
namespace {

// Instanced meshes are copied into the world-space caster stream while all their copies
// together stay below this many vertices (12 bytes each); bigger ones are transformed per vertex.
constexpr std::size_t kMaxCopiedInstanceVertices = std::size_t{1} << 16;

// Interleaved vertex; attribute locations match shaders/scene_vertex.glsl.
struct Vertex {
  glm::vec3 position;
  glm::vec3 normal;
  glm::vec4 tangent;
  glm::vec2 uv0;
  glm::vec2 uv1;
  glm::vec4 color;
};

void setAttribute(GLuint vao, GLuint location, GLint size, GLuint offset) {
  glEnableVertexArrayAttrib(vao, location);
  glVertexArrayAttribFormat(vao, location, size, GL_FLOAT, GL_FALSE, offset);
  glVertexArrayAttribBinding(vao, location, 0);
}

}  // namespace

void markRepeatedDraws(std::vector<GpuDraw>& draws) {
  // The transform's bits: -0 and +0, or two NaNs of other payloads, are not the same draw.
  using Key = std::tuple<int, int, std::array<std::uint32_t, 16>>;
  const auto key = [&](std::size_t i) {
    Key k{draws[i].mesh, draws[i].material, {}};
    std::memcpy(std::get<2>(k).data(), glm::value_ptr(draws[i].world), sizeof(glm::mat4));
    return k;
  };
  std::vector<std::pair<Key, std::size_t>> keyed;
  keyed.reserve(draws.size());
  for (std::size_t i = 0; i < draws.size(); ++i) keyed.emplace_back(key(i), i);
  // Equal keys end up next to each other, in the scene's order.
  std::sort(keyed.begin(), keyed.end());
  for (std::size_t k = 1; k < keyed.size(); ++k) {
    if (keyed[k].first != keyed[k - 1].first) continue;
    draws[keyed[k - 1].second].repeatedLater = true;
    draws[keyed[k].second].repeatsEarlier = true;
  }
}

GpuGeometry::GpuGeometry(const Scene& scene) {
  uploadCasterStream(scene, uploadMeshes(scene));
  vertexArrays_ = makeVertexArrays();
}

SceneVertexArrays GpuGeometry::makeVertexArrays() const {
  SceneVertexArrays arrays{gl::createVertexArray(), gl::createVertexArray()};
  const GLuint vao = arrays.scene.get();
  glVertexArrayVertexBuffer(vao, 0, vertices_.get(), 0, sizeof(Vertex));
  glVertexArrayElementBuffer(vao, indices_.get());
  setAttribute(vao, 0, 3, offsetof(Vertex, position));
  setAttribute(vao, 1, 3, offsetof(Vertex, normal));
  setAttribute(vao, 2, 4, offsetof(Vertex, tangent));
  setAttribute(vao, 3, 2, offsetof(Vertex, uv0));
  setAttribute(vao, 4, 2, offsetof(Vertex, uv1));
  setAttribute(vao, 5, 4, offsetof(Vertex, color));
  const GLuint casters = arrays.casters.get();
  glVertexArrayVertexBuffer(casters, 0, casterPositions_.get(), 0, sizeof(glm::vec3));
  glVertexArrayElementBuffer(casters, casterIndices_.get());
  setAttribute(casters, 0, 3, 0);
  return arrays;
}

std::vector<std::optional<std::vector<glm::vec3>>> GpuGeometry::uploadMeshes(const Scene& scene) {
  std::vector<Vertex> vertices;
  std::vector<std::uint32_t> indices;
  std::vector<std::optional<std::vector<glm::vec3>>> welded;
  // Whether each mesh bounds a solid, as it is or welded, and whether it is flat: a look at
  // every edge, most of the upload's CPU in a scene of many meshes, on the machine's threads.
  struct Shape {
    SolidCheck solid;
    std::optional<MeshPlane> plane;
  };
  std::vector<Shape> shapes(scene.meshes.size());
  inParts(scene.meshes.size(), partsFor(scene.meshes.size()),
          [&](std::size_t /*part*/, std::size_t first, std::size_t end) {
            for (std::size_t m = first; m < end; ++m) {
              const Mesh& mesh = scene.meshes[m];
              shapes[m].solid = checkSolid(mesh.positions, mesh.indices);
              // A closed solid encloses a volume, so it is never flat.
              if (!shapes[m].solid.closed)
                shapes[m].plane = flatMeshPlane(mesh.positions, mesh.indices);
            }
          });
  for (std::size_t m = 0; m < scene.meshes.size(); ++m) {
    const Mesh& mesh = scene.meshes[m];
    GpuMeshRange range;
    range.baseVertex = static_cast<GLint>(vertices.size());
    range.firstIndex = static_cast<GLsizei>(indices.size());
    range.indexCount = static_cast<GLsizei>(mesh.indices.size());
    range.hasTangents = !mesh.tangents.empty();
    range.closed = shapes[m].solid.closed;
    range.closedInStream = range.closed || shapes[m].solid.welded.has_value();
    range.plane = shapes[m].plane;
    welded.push_back(std::move(shapes[m].solid.welded));
    for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
      Vertex v;
      v.position = mesh.positions[i];
      v.normal = i < mesh.normals.size() ? mesh.normals[i] : glm::vec3(0, 1, 0);
      v.tangent = i < mesh.tangents.size() ? mesh.tangents[i] : glm::vec4(1, 0, 0, 1);
      v.uv0 = i < mesh.uv0.size() ? mesh.uv0[i] : glm::vec2(0.0f);
      v.uv1 = i < mesh.uv1.size() ? mesh.uv1[i] : glm::vec2(0.0f);
      v.color = i < mesh.colors.size() ? mesh.colors[i] : glm::vec4(1.0f);
      vertices.push_back(v);
    }
    indices.insert(indices.end(), mesh.indices.begin(), mesh.indices.end());
    range.lineIndexCount = static_cast<GLsizei>(mesh.lineIndices.size());
    indices.insert(indices.end(), mesh.lineIndices.begin(), mesh.lineIndices.end());
    range.pointIndexCount = static_cast<GLsizei>(mesh.pointIndices.size());
    indices.insert(indices.end(), mesh.pointIndices.begin(), mesh.pointIndices.end());
    meshes_.push_back(range);
  }
  vertices_ = gl::createBuffer();
  indices_ = gl::createBuffer();
  // Empty scenes still get valid (1-byte) buffers so the vertex array is complete.
  glNamedBufferStorage(vertices_.get(), std::max<GLsizeiptr>(1, vertices.size() * sizeof(Vertex)),
                       vertices.empty() ? nullptr : vertices.data(), 0);
  glNamedBufferStorage(indices_.get(), std::max<GLsizeiptr>(1, indices.size() * 4),
                       indices.empty() ? nullptr : indices.data(), 0);

  std::vector<float> meshRadius;
  for (const Mesh& mesh : scene.meshes) {
    float radius = 0.0f;
    for (const glm::vec3& p : mesh.positions)
      radius = std::max(radius, glm::length(p - mesh.bounds.center()));
    meshRadius.push_back(radius);
  }
  const int defaultMaterial = static_cast<int>(scene.materials.size());
  for (const MeshInstance& instance : scene.instances) {
    const Mesh& mesh = scene.meshes[instance.mesh];
    GpuDraw draw;
    draw.mesh = instance.mesh;
    draw.material = mesh.material >= 0 ? mesh.material : defaultMaterial;
    draw.world = instance.world;
    draw.normalMatrix = glm::transpose(glm::inverse(glm::mat3(instance.world)));
    draw.mirrored = glm::determinant(glm::mat3(instance.world)) < 0.0f;
    // The sphere around the mesh's box center through its farthest vertex (tighter than the
    // box's own sphere: a ball's radius instead of sqrt(3) times it), placed in the world and
    // scaled by the transform's largest axis scale.
    const glm::vec3 center = mesh.bounds.center();
    const float radius = meshRadius[static_cast<std::size_t>(instance.mesh)];
    const glm::mat3 linear(instance.world);
    const float scale =
        std::max({glm::length(linear[0]), glm::length(linear[1]), glm::length(linear[2])});
    draw.boundsCenter = glm::vec3(instance.world * glm::vec4(center, 1.0f));
    draw.boundsRadius = radius * scale * (1.0f + 1e-5f);
    draw.meshBounds = mesh.bounds;
    const std::optional<MeshPlane>& plane = meshes_[static_cast<std::size_t>(instance.mesh)].plane;
    if (plane) draw.plane = transformedPlane(*plane, instance.world);
    draws_.push_back(draw);
  }
  markRepeatedDraws(draws_);
  // World matrices by draw index, for passes that draw many objects in one call.
  std::vector<glm::mat4> models;
  for (const GpuDraw& draw : draws_) models.push_back(draw.world);
  if (models.empty()) models.emplace_back(1.0f);
  models_ = gl::createBuffer();
  glNamedBufferStorage(models_.get(), static_cast<GLsizeiptr>(models.size() * sizeof(glm::mat4)),
                       models.data(), 0);
  return welded;
}

namespace {

// Position along a Z-order curve through the unit cube, 10 bits per axis.
std::uint32_t zOrder(const glm::vec3& unit) {
  const auto spread = [](float t) {
    std::uint32_t v = static_cast<std::uint32_t>(std::clamp(t, 0.0f, 1.0f) * 1023.0f);
    v = (v | v << 16) & 0x030000FFu;
    v = (v | v << 8) & 0x0300F00Fu;
    v = (v | v << 4) & 0x030C30C3u;
    return (v | v << 2) & 0x09249249u;
  };
  return spread(unit.x) | spread(unit.y) << 1 | spread(unit.z) << 2;
}

}  // namespace

void GpuGeometry::uploadCasterStream(
    const Scene& scene, const std::vector<std::optional<std::vector<glm::vec3>>>& welded) {
  std::vector<std::size_t> instancesOf(scene.meshes.size(), 0);
  for (const GpuDraw& draw : draws_) ++instancesOf[static_cast<std::size_t>(draw.mesh)];
  std::vector<std::size_t> copied;
  Bounds centers;
  for (std::size_t d = 0; d < draws_.size(); ++d) {
    const Mesh& mesh = scene.meshes[static_cast<std::size_t>(draws_[d].mesh)];
    const std::size_t copies = instancesOf[static_cast<std::size_t>(draws_[d].mesh)];
    if (copies > 1 && copies * mesh.positions.size() > kMaxCopiedInstanceVertices) continue;
    copied.push_back(d);
    centers.extend(draws_[d].boundsCenter);
  }
  // Copies near each other in space follow each other in the stream (a Z-order curve through
  // their bounding spheres' centres), so that the casters one shadow view sees form long runs,
  // each one command (shadow_draws.h).
  const glm::vec3 extent = glm::max(centers.max - centers.min, glm::vec3(1e-30f));
  std::vector<std::uint32_t> key(draws_.size(), 0u);
  for (const std::size_t d : copied)
    key[d] = zOrder((draws_[d].boundsCenter - centers.min) / extent);
  std::stable_sort(copied.begin(), copied.end(),
                   [&](std::size_t a, std::size_t b) { return key[a] < key[b]; });
  std::vector<glm::vec3> world;
  std::vector<std::uint32_t> indices;
  for (const std::size_t d : copied) {
    GpuDraw& draw = draws_[d];
    const auto m = static_cast<std::size_t>(draw.mesh);
    const Mesh& mesh = scene.meshes[m];
    // Copies of a mesh closed only once welded are made from the welded positions.
    const std::vector<glm::vec3>& positions = welded[m] ? *welded[m] : mesh.positions;
    const auto base = static_cast<std::uint32_t>(world.size());
    draw.casterFirstIndex = static_cast<GLint>(indices.size());
    for (std::size_t v = 0; v < positions.size(); ++v) {
      world.emplace_back(draw.world * glm::vec4(positions[v], 1.0f));
      // Where shadows land: the mesh as the lighting pass draws it.
      receiverBounds_.extend(welded[m] ? glm::vec3(draw.world * glm::vec4(mesh.positions[v], 1.0f))
                                       : world.back());
    }
    for (const std::uint32_t i : mesh.indices) indices.push_back(base + i);
  }
  // The other draws: their mesh's box (from its positions, not trusted from the scene), moved.
  std::vector<std::optional<Bounds>> local(scene.meshes.size());
  for (const GpuDraw& draw : draws_) {
    if (draw.casterFirstIndex >= 0) continue;
    std::optional<Bounds>& box = local[static_cast<std::size_t>(draw.mesh)];
    if (!box) {
      box.emplace();
      for (const glm::vec3& p : scene.meshes[static_cast<std::size_t>(draw.mesh)].positions)
        box->extend(p);
    }
    receiverBounds_.extend(box->transformed(draw.world));
  }
  casterPositions_ = gl::createBuffer();
  glNamedBufferStorage(casterPositions_.get(),
                       std::max<GLsizeiptr>(1, world.size() * sizeof(glm::vec3)),
                       world.empty() ? nullptr : world.data(), 0);
  casterIndices_ = gl::createBuffer();
  glNamedBufferStorage(casterIndices_.get(), std::max<GLsizeiptr>(1, indices.size() * 4),
                       indices.empty() ? nullptr : indices.data(), 0);
}

std::shared_ptr<const GpuGeometry> GeometryCache::find(const Scene& scene,
                                                       const std::vector<MeshDigests>& meshes) {
  const std::uint64_t fingerprint = geometryFingerprint(scene, meshes);
  if (geometry_ && fingerprint == fingerprint_) return geometry_;
  geometry_.reset();  // its buffers go before the new ones are made
  geometry_ = std::make_shared<const GpuGeometry>(scene);
  fingerprint_ = fingerprint;
  return geometry_;
}

}  // namespace omnishadow
