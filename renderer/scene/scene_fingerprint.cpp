#include "renderer/scene/scene_fingerprint.h"

#include <bit>
#include <cstdint>
#include <cstring>
#include <thread>
#include <vector>

#include "renderer/scene/translucency.h"

namespace omnishadow {
namespace {

// A 64-bit hash of a sequence of byte strings. Large arrays (a scene's positions and indices:
// megabytes, hashed every frame the shadow cache is asked) go through four independent
// multiply-rotate lanes, 32 bytes a step, so that the multiplications overlap instead of each
// waiting for the one before: byte-wise FNV-1a took 6 ms a frame for the 250k-triangle bench
// room. Deterministic within a process (the value is never stored); every input bit reaches
// the result through odd multipliers and rotations.
class ContentHash {
 public:
  void bytes(const void* data, std::size_t size) {
    const auto* p = static_cast<const unsigned char*>(data);
    const std::size_t length = size;
    if (size >= 32) {
      std::uint64_t lane[4] = {state_ + kPrime1 + kPrime2, state_ + kPrime2, state_,
                               state_ - kPrime1};
      for (; size >= 32; p += 32, size -= 32)
        for (int i = 0; i < 4; ++i) lane[i] = round(lane[i], load(p + 8 * i));
      state_ = std::rotl(lane[0], 1) + std::rotl(lane[1], 7) + std::rotl(lane[2], 12) +
               std::rotl(lane[3], 18);
      for (const std::uint64_t l : lane) state_ = (state_ ^ round(0, l)) * kPrime1 + kPrime4;
    }
    for (; size >= 8; p += 8, size -= 8) mixWord(load(p));
    if (size > 0) {
      std::uint64_t tail = 0;
      std::memcpy(&tail, p, size);
      mixWord(tail);
    }
    // The length keeps ("ab", "c") apart from ("a", "bc") and zero bytes from none.
    state_ = std::rotl(state_ ^ (length * kPrime3), 23) * kPrime2 + kPrime3;
  }
  template <typename T>
  void value(const T& v) {
    bytes(&v, sizeof v);
  }
  template <typename T>
  void vector(const std::vector<T>& v) {
    bytes(v.data(), v.size() * sizeof(T));
  }
  std::uint64_t get() const {
    std::uint64_t h = state_;
    h ^= h >> 33;
    h *= kPrime2;
    h ^= h >> 29;
    h *= kPrime3;
    return h ^ (h >> 32);
  }

 private:
  static constexpr std::uint64_t kPrime1 = 0x9E3779B185EBCA87ull;
  static constexpr std::uint64_t kPrime2 = 0xC2B2AE3D27D4EB4Full;
  static constexpr std::uint64_t kPrime3 = 0x165667B19E3779F9ull;
  static constexpr std::uint64_t kPrime4 = 0x85EBCA77C2B2AE63ull;
  static std::uint64_t load(const unsigned char* p) {
    std::uint64_t w = 0;
    std::memcpy(&w, p, sizeof w);
    return w;
  }
  static std::uint64_t round(std::uint64_t lane, std::uint64_t word) {
    return std::rotl(lane + word * kPrime2, 31) * kPrime1;
  }
  // Words outside the 32-byte blocks go into the state one at a time.
  void mixWord(std::uint64_t word) {
    state_ = std::rotl(state_ ^ round(0, word), 27) * kPrime1 + kPrime4;
  }
  std::uint64_t state_ = 0x27D4EB2F165667C5ull;
};

// Where the instances are, and of which meshes.
void hashInstances(ContentHash& h, const Scene& scene) {
  h.value(scene.instances.size());
  for (const MeshInstance& instance : scene.instances) {
    h.value(instance.mesh);
    h.value(instance.world);
  }
}

// The hash of image `index`'s pixels, from `images` where it is there (and left there).
std::uint64_t imageHash(const Scene& scene, int index, ImageHashes* images) {
  const auto i = static_cast<std::size_t>(index);
  if (images && (*images)[i]) return *(*images)[i];
  const Image& image = scene.images[i];
  ContentHash h;
  h.value(image.width);
  h.bytes(image.rgba.data(), image.rgba.size());
  if (images) (*images)[i] = h.get();
  return h.get();
}

// A material's texture slot; with `withImage`, also the sampler and the pixels of a slot in use.
void hashTextureSlot(ContentHash& h, const Scene& scene, const TextureSlot& slot, bool withImage,
                     ImageHashes* images) {
  h.value(slot.texture);
  h.value(slot.texCoord);
  h.value(slot.uvTransform);
  if (withImage && slot.texture >= 0) {
    const Texture& texture = scene.textures[slot.texture];
    h.value(texture.sampler);
    if (texture.image >= 0) h.value(imageHash(scene, texture.image, images));
  }
}

}  // namespace

std::vector<MeshDigests> meshDigests(const Scene& scene) {
  const auto digest = [](const auto& array) {
    ContentHash h;
    h.vector(array);
    return h.get();
  };
  std::vector<MeshDigests> digests(scene.meshes.size());
  const auto work = [&](std::size_t first, std::size_t end) {
    for (std::size_t i = first; i < end; ++i) {
      const Mesh& mesh = scene.meshes[i];
      digests[i] = {digest(mesh.positions), digest(mesh.normals),     digest(mesh.tangents),
                    digest(mesh.uv0),       digest(mesh.uv1),         digest(mesh.colors),
                    digest(mesh.indices),   digest(mesh.lineIndices), digest(mesh.pointIndices)};
    }
  };
  // Hashing is bound by memory bandwidth, which a second core adds to: from 4 MiB on, a second
  // thread takes the meshes holding the first half of the bytes.
  std::size_t total = 0;
  for (const Mesh& mesh : scene.meshes) total += meshBytes(mesh);
  constexpr std::size_t kTwoThreadBytes = std::size_t{4} << 20;
  if (total < kTwoThreadBytes || std::thread::hardware_concurrency() < 2) {
    work(0, digests.size());
    return digests;
  }
  std::size_t middle = 0;
  for (std::size_t half = 0; middle < digests.size() && half < total / 2; ++middle)
    half += meshBytes(scene.meshes[middle]);
  std::thread helper(work, std::size_t{0}, middle);
  work(middle, digests.size());
  helper.join();
  return digests;
}

std::uint64_t shadowFingerprint(const Scene& scene) {
  return shadowFingerprint(scene, meshDigests(scene));
}

std::uint64_t shadowFingerprint(const Scene& scene, const std::vector<MeshDigests>& meshes,
                                ImageHashes* images) {
  ContentHash h;
  h.value(scene.meshes.size());
  for (std::size_t i = 0; i < scene.meshes.size(); ++i) {
    const Mesh& mesh = scene.meshes[i];
    h.value(meshes[i].positions);
    h.value(meshes[i].indices);
    h.value(mesh.material);
    // Cut-out casters depend on their texture coordinates and vertex alpha too.
    const bool opaque =
        mesh.material < 0 || (scene.materials[mesh.material].alphaMode == AlphaMode::Opaque &&
                              !isTranslucentCaster(scene.materials[mesh.material]));
    if (!opaque) {
      h.value(meshes[i].uv0);
      h.value(meshes[i].uv1);
      h.value(meshes[i].colors);
    }
  }
  hashInstances(h, scene);
  for (const Material& m : scene.materials) {
    h.value(m.alphaMode);
    h.value(m.alphaCutoff);
    h.value(m.doubleSided);
    h.value(m.baseColorFactor.a);
    // Translucent casters tint the transmittance layers with their color.
    h.value(m.transmissionFactor);
    hashTextureSlot(h, scene, m.transmissionTexture, true, images);
    if (isTranslucentCaster(m)) {
      h.value(glm::vec3(m.baseColorFactor));
      // Volumes attenuate and diffuse transmission tints what they let through.
      h.value(m.thicknessFactor);
      h.value(m.attenuationDistance);
      h.value(m.attenuationColor);
      h.value(m.diffuseTransmissionFactor);
      h.value(m.diffuseTransmissionColorFactor);
    }
    const bool translucent = isTranslucentCaster(m);
    hashTextureSlot(h, scene, m.thicknessTexture, translucent && hasVolume(m), images);
    hashTextureSlot(h, scene, m.diffuseTransmissionTexture,
                    translucent && hasDiffuseTransmission(m), images);
    hashTextureSlot(h, scene, m.diffuseTransmissionColorTexture,
                    translucent && hasDiffuseTransmission(m), images);
    hashTextureSlot(h, scene, m.baseColorTexture,
                    m.alphaMode != AlphaMode::Opaque || isTranslucentCaster(m), images);
  }
  return h.get();
}

std::uint64_t geometryFingerprint(const Scene& scene) {
  return geometryFingerprint(scene, meshDigests(scene));
}

std::uint64_t geometryFingerprint(const Scene& scene, const std::vector<MeshDigests>& meshes) {
  ContentHash h;
  h.value(scene.meshes.size());
  for (std::size_t i = 0; i < scene.meshes.size(); ++i) {
    const MeshDigests& d = meshes[i];
    for (const std::uint64_t array : {d.positions, d.normals, d.tangents, d.uv0, d.uv1, d.colors,
                                      d.indices, d.lineIndices, d.pointIndices})
      h.value(array);
    h.value(scene.meshes[i].material);
    h.value(scene.meshes[i].bounds);
  }
  hashInstances(h, scene);
  // The default material's index follows the scene's materials.
  h.value(scene.materials.size());
  return h.get();
}

}  // namespace omnishadow
