#pragma once

#include <cstddef>
#include <cstdint>
#include <glm/glm.hpp>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "renderer/scene/bounds.h"
#include "renderer/scene/light.h"
#include "renderer/scene/pixel_bytes.h"
#include "renderer/scene/scene_rig.h"

namespace omnishadow {

// CPU-side scene: plain data, filled by the glTF loader, consumed by the GPU upload.

struct Image {
  std::string name;
  int width = 0;
  int height = 0;
  PixelBytes rgba;  // 8-bit RGBA, first row = top of the picture (as in the file); shared by copies
  // What the file was, as decoded: "PNG", "JPEG", "WebP" or "AVIF"; empty for an image that
  // is not decoded (a fallback that no texture draws, or KTX2 and DDS).
  std::string format;
};

// glTF sampler codes (GL enums), with glTF's defaults.
struct SamplerDesc {
  int magFilter = 0x2601;  // GL_LINEAR
  int minFilter = 0x2703;  // GL_LINEAR_MIPMAP_LINEAR
  int wrapS = 0x2901;      // GL_REPEAT
  int wrapT = 0x2901;
};

struct Texture {
  int image = -1;  // index into Scene::images
  SamplerDesc sampler;
};

enum class AlphaMode { Opaque, Mask, Blend };

// Texture slot of a material; texture = -1 when unused. texCoord selects TEXCOORD_n (0 or 1),
// after KHR_texture_transform's override.
struct TextureSlot {
  int texture = -1;
  int texCoord = 0;
  // KHR_texture_transform: the texture is sampled at (uvTransform * vec3(uv, 1)).xy.
  glm::mat3 uvTransform{1.0f};
};

struct Material {
  std::string name;
  glm::vec4 baseColorFactor{1.0f};
  TextureSlot baseColorTexture;  // sRGB
  float metallicFactor = 1.0f;
  float roughnessFactor = 1.0f;
  TextureSlot metallicRoughnessTexture;  // linear; G = roughness, B = metallic
  TextureSlot normalTexture;
  float normalScale = 1.0f;
  TextureSlot occlusionTexture;  // linear; R = occlusion
  float occlusionStrength = 1.0f;
  glm::vec3 emissiveFactor{0.0f};
  float emissiveStrength = 1.0f;  // KHR_materials_emissive_strength
  TextureSlot emissiveTexture;    // sRGB
  AlphaMode alphaMode = AlphaMode::Opaque;
  float alphaCutoff = 0.5f;
  bool doubleSided = false;
  // KHR_materials_unlit: the surface shows its base color as is, lit by nothing.
  bool unlit = false;
  // KHR_materials_pbrSpecularGlossiness, shaded as that extension defines it: the diffuse
  // factor and texture are baseColorFactor and baseColorTexture (same roles: sRGB color and
  // alpha), the specular color and glossiness come from the fields below, and the
  // metallic-roughness fields are unused.
  bool specularGlossiness = false;
  glm::vec3 specularFactor{1.0f};
  float glossinessFactor = 1.0f;
  TextureSlot specularGlossinessTexture;  // sRGB specular color, linear glossiness in A
  // KHR_materials_transmission: the fraction of light that passes through the surface, tinted
  // by its base color; it makes the surface a translucent shadow caster (translucency.h).
  float transmissionFactor = 0.0f;
  TextureSlot transmissionTexture;  // linear; R multiplies transmissionFactor
  // KHR_materials_ior: the index of refraction of the dielectric part, which sets its Fresnel
  // reflectance at normal incidence, ((ior - 1) / (ior + 1))^2 (0.04 at glTF's 1.5).
  float ior = 1.5f;
  // KHR_materials_specular: the dielectric's Fresnel goes from min(F0(ior) x color, 1) x weight
  // at normal incidence to weight at grazing, and its diffuse takes what the brightest channel
  // leaves.
  float specularWeight = 1.0f;          // specularFactor
  TextureSlot specularTexture;          // linear; A multiplies specularFactor
  glm::vec3 specularColorFactor{1.0f};  // linear; may exceed 1
  TextureSlot specularColorTexture;     // sRGB; RGB multiplies specularColorFactor
  // KHR_materials_sheen: a layer of fibers over the metallic-roughness material, shaded with
  // the specification's Charlie BRDF (shaders/brdf.glsl). A sheen color of zero, with or
  // without a texture, is no sheen, as the specification says.
  glm::vec3 sheenColorFactor{0.0f};
  TextureSlot sheenColorTexture;  // sRGB; RGB multiplies sheenColorFactor
  float sheenRoughnessFactor = 0.0f;
  // Linear; A multiplies sheenRoughnessFactor. The same image as sheenColorTexture's (the
  // packing the specification designs for) is read through one texture unit, another image
  // through a unit of its own.
  TextureSlot sheenRoughnessTexture;
  // KHR_materials_clearcoat: a clear layer over the whole material (emission included) with a
  // GGX lobe of its own roughness and normal, weighted by clearcoat x its Fresnel at the view
  // (F0 0.04), which the layers below lose. A factor of zero is no layer.
  float clearcoatFactor = 0.0f;
  TextureSlot clearcoatTexture;  // linear; R multiplies clearcoatFactor
  float clearcoatRoughnessFactor = 0.0f;
  TextureSlot clearcoatRoughnessTexture;  // linear; G multiplies clearcoatRoughnessFactor
  // The layer's own normal map; without one the layer follows the surface's interpolated
  // normal, not the base material's normal map.
  TextureSlot clearcoatNormalTexture;
  float clearcoatNormalScale = 1.0f;
  // KHR_materials_volume: with a transmission, a thickness above 0 makes the surface the
  // boundary of a volume that light crosses refracted (by `ior`) and attenuated (Beer's law:
  // attenuationColor^(distance / attenuationDistance)); 0 is a thin wall.
  float thicknessFactor = 0.0f;  // in the mesh's coordinates
  TextureSlot thicknessTexture;  // linear; G multiplies thicknessFactor
  float attenuationDistance = std::numeric_limits<float>::infinity();  // world units
  glm::vec3 attenuationColor{1.0f};
  // KHR_materials_dispersion, 20 / the Abbe number: a volume's red, green and blue refract with
  // iors spread around `ior` (0: one ior for all).
  float dispersion = 0.0f;
  // KHR_materials_anisotropy: the specular lobe's alpha along a direction of the tangent space
  // (the tangent turned by anisotropyRotation, counter-clockwise towards the bitangent, or the
  // texture's RG direction turned by it) grows to mix(roughness^2, 1, strength^2).
  float anisotropyStrength = 0.0f;
  float anisotropyRotation = 0.0f;  // radians
  TextureSlot anisotropyTexture;    // linear; RG direction in [-1, 1], B multiplies the strength
  // KHR_materials_iridescence: a thin film of index iridescenceIor and a thickness in
  // nanometres (mix(minimum, maximum, the thickness texture's G); the maximum without one) whose
  // interference colors the Fresnel, as strong as factor x texture's R.
  float iridescenceFactor = 0.0f;
  TextureSlot iridescenceTexture;  // linear; R multiplies iridescenceFactor
  float iridescenceIor = 1.3f;
  float iridescenceThicknessMinimum = 100.0f;
  float iridescenceThicknessMaximum = 400.0f;
  TextureSlot iridescenceThicknessTexture;  // linear; G
  // KHR_materials_diffuse_transmission: the fraction of the light entering the surface that
  // leaves it on the other side (factor x texture's A), as Lambert of the color.
  float diffuseTransmissionFactor = 0.0f;
  TextureSlot diffuseTransmissionTexture;  // linear; A multiplies the factor
  glm::vec3 diffuseTransmissionColorFactor{1.0f};
  TextureSlot diffuseTransmissionColorTexture;  // sRGB; RGB multiplies the color factor
};

// The dielectric Fresnel reflectance at normal incidence that `material`'s ior gives (outside
// the surface: air, ior 1), in double so that glTF's 1.5 gives 0.04 exactly as a float.
inline float dielectricF0(const Material& material) {
  const double ior = material.ior, r = (ior - 1.0) / (ior + 1.0);
  return static_cast<float>(r * r);
}

// Whether KHR_materials_specular changes how `material` is shaded: factors other than the
// defaults, or a texture, on a lit metallic-roughness material.
inline bool hasDielectricSpecular(const Material& material) {
  return !material.unlit && !material.specularGlossiness &&
         (material.specularWeight != 1.0f || material.specularColorFactor != glm::vec3(1.0f) ||
          material.specularTexture.texture >= 0 || material.specularColorTexture.texture >= 0);
}

// Whether the lighting pass shades `material` with a sheen layer: a nonzero sheen color on a
// lit metallic-roughness material (the extension excludes unlit and specular-glossiness ones).
inline bool hasSheen(const Material& material) {
  return !material.unlit && !material.specularGlossiness &&
         (material.sheenColorFactor.r > 0.0f || material.sheenColorFactor.g > 0.0f ||
          material.sheenColorFactor.b > 0.0f);
}

// Whether the lighting pass shades `material` with a clearcoat layer: a nonzero factor on a lit
// metallic-roughness material (the extension excludes unlit and specular-glossiness ones).
inline bool hasClearcoat(const Material& material) {
  return !material.unlit && !material.specularGlossiness && material.clearcoatFactor > 0.0f;
}

// Whether the lighting pass draws `material` see-through (KHR_materials_transmission): a nonzero
// transmission factor on a lit metallic-roughness material that is not BLEND. Such a surface is
// drawn after the opaque ones and shows, through its transmission, what they drew behind it
// (thin-walled: no refraction offset). A BLEND material with a transmission factor is blended
// as its alpha says; its transmission only tints shadows (translucency.h).
inline bool hasTransmission(const Material& material) {
  return !material.unlit && !material.specularGlossiness && material.transmissionFactor > 0.0f &&
         material.alphaMode != AlphaMode::Blend;
}

// Whether a see-through `material` (hasTransmission) is drawn as a volume's boundary
// (KHR_materials_volume with a thickness above 0) rather than as a thin wall.
inline bool hasVolume(const Material& material) {
  return hasTransmission(material) && material.thicknessFactor > 0.0f;
}

// Whether a volume (hasVolume) splits the colors it lets through (KHR_materials_dispersion).
inline bool hasDispersion(const Material& material) {
  return hasVolume(material) && material.dispersion > 0.0f;
}

// Whether the lighting pass stretches `material`'s highlights (KHR_materials_anisotropy): a
// nonzero strength on a lit metallic-roughness material (the extension excludes the others).
inline bool hasAnisotropy(const Material& material) {
  return !material.unlit && !material.specularGlossiness && material.anisotropyStrength > 0.0f;
}

// Whether the lighting pass shades `material` with a thin film (KHR_materials_iridescence): a
// nonzero factor on a lit metallic-roughness material (the extension excludes the others).
inline bool hasIridescence(const Material& material) {
  return !material.unlit && !material.specularGlossiness && material.iridescenceFactor > 0.0f;
}

// Whether the lighting pass lets lights through `material` diffusely
// (KHR_materials_diffuse_transmission): a nonzero factor on a lit metallic-roughness material.
inline bool hasDiffuseTransmission(const Material& material) {
  return !material.unlit && !material.specularGlossiness &&
         material.diffuseTransmissionFactor > 0.0f;
}

// The texture slot whose texture coordinates generated tangents follow (texture < 0: none is
// needed): the material's normal map, else its clearcoat's (KHR_materials_clearcoat asks for a
// tangent space either way), else its anisotropy texture, else for an anisotropic material
// without one TEXCOORD_0 (KHR_materials_anisotropy needs a tangent space).
inline const TextureSlot& tangentSpaceNormalMap(const Material& material) {
  // The texture index only says that tangents are needed; generation reads the texCoord.
  static const TextureSlot kFirstUvSet{0, 0, glm::mat3(1.0f)};
  if (material.normalTexture.texture >= 0) return material.normalTexture;
  if (hasClearcoat(material) && material.clearcoatNormalTexture.texture >= 0)
    return material.clearcoatNormalTexture;
  if (hasAnisotropy(material))
    return material.anisotropyTexture.texture >= 0 ? material.anisotropyTexture : kFirstUvSet;
  return material.normalTexture;
}

// One glTF primitive as an indexed triangle list, in the mesh's local space.
// Every attribute array is either empty or has positions.size() entries.
struct Mesh {
  std::string name;  // "<mesh name>/<primitive index>"
  std::vector<glm::vec3> positions;
  std::vector<glm::vec3> normals;   // always filled (generated when the file has none)
  std::vector<glm::vec4> tangents;  // xyz + handedness; filled when normal mapping is possible
  std::vector<glm::vec2> uv0;
  std::vector<glm::vec2> uv1;
  std::vector<glm::vec4> colors;  // COLOR_0 as linear RGBA
  std::vector<std::uint32_t> indices;
  // Points and lines (glTF modes 0-3), drawn one pixel wide in their base color, casting no
  // shadow; they are not triangles, so everything that reads `indices` leaves them out.
  std::vector<std::uint32_t> lineIndices;  // pairs
  std::vector<std::uint32_t> pointIndices;
  int material = -1;  // index into Scene::materials; -1 = the glTF default material
  Bounds bounds;      // local space
};

// The bytes of a mesh's arrays (what the GPU upload copies, and what hashing it reads).
inline std::size_t meshBytes(const Mesh& m) {
  return m.positions.size() * sizeof m.positions[0] + m.normals.size() * sizeof m.normals[0] +
         m.tangents.size() * sizeof m.tangents[0] + m.uv0.size() * sizeof m.uv0[0] +
         m.uv1.size() * sizeof m.uv1[0] + m.colors.size() * sizeof m.colors[0] +
         (m.indices.size() + m.lineIndices.size() + m.pointIndices.size()) * sizeof(std::uint32_t);
}

// A mesh placed in the world by a node.
struct MeshInstance {
  int mesh = -1;  // index into Scene::meshes
  glm::mat4 world{1.0f};
  int node = -1;  // glTF node index
  std::string nodeName;
  // The node's extras "class" (a string), else its nearest ancestor's; for semantic masks; else
  // empty.
  std::string className;
  // EXT_mesh_gpu_instancing: this instance's transform within its node (world = node's world x
  // this), kept so that posing can move every instance with its node; identity otherwise.
  glm::mat4 inNode{1.0f};
};

// A glTF camera as placed by a node that references it.
struct Camera {
  std::string name;  // the camera's name, or else its node's name
  std::string nodeName;
  int index = -1;  // glTF camera index
  int node = -1;   // glTF node that places it
  bool orthographic = false;
  float yfov = 0.8f;               // radians (perspective)
  float aspectRatio = 0.0f;        // 0 = unspecified
  float xmag = 1.0f, ymag = 1.0f;  // half extents (orthographic)
  float znear = 0.01f;
  float zfar = 0.0f;      // 0 = infinite (perspective)
  glm::mat4 world{1.0f};  // camera-to-world; the camera looks down its local -Z, +Y up
};

// A glTF extension the file lists in extensionsUsed (or only in extensionsRequired).
struct ExtensionUse {
  std::string name;
  bool required = false;     // listed in extensionsRequired
  bool supported = false;    // the loader implements it (renderer/scene/gltf_extensions.cpp)
  std::string drawnInstead;  // when not supported: what is drawn without it
};

// What the file held, beyond what the chosen scene draws; filled by the loader, reported by
// `omnishadow info`.
struct SourceSummary {
  std::string format;  // "gltf" or "glb" (by content, not by the file name)
  // The glTF `asset` fields as given (empty when absent).
  std::string version, minVersion, generator, copyright;
  int sceneCount = 0;   // glTF scenes in the file
  int sceneIndex = -1;  // the scene loaded; -1 when the file has no scenes (all roots drawn)
  // KHR_materials_variants: the file's variant names, and the one loaded (-1: the primitives'
  // own materials).
  std::vector<std::string> materialVariants;
  int materialVariant = -1;
  int fileNodes = 0;       // nodes in the file
  int reachedNodes = 0;    // nodes reached from the loaded scene's roots
  int hiddenNodes = 0;     // of those, hidden by KHR_node_visibility (theirs or an ancestor's)
  int gltfMeshes = 0;      // glTF meshes in the file
  int gltfPrimitives = 0;  // primitives of all of them, of any mode
  std::vector<ExtensionUse> extensions;  // in the file's order, extensionsUsed first
};

struct Scene {
  std::string path;  // file it was loaded from, for messages
  SourceSummary source;
  // The scene file and every external file it references (buffers, images), so that outputs
  // never overwrite an input.
  std::vector<std::string> inputFiles;
  std::vector<Image> images;
  std::vector<Texture> textures;
  std::vector<Material> materials;
  std::vector<Mesh> meshes;
  std::vector<MeshInstance> instances;
  std::vector<Camera> cameras;  // sorted by glTF camera index, then by node traversal order
  std::vector<Light> lights;    // KHR_lights_punctual, world space, origin = "glTF"
  Bounds bounds;                // world space, all instances
  std::vector<std::string> warnings;
  // Nodes, skins, morph targets and animations: what poseScene() (scene_pose.h) needs to pose
  // the scene at a time. The loader leaves the scene posed at rest (skins and default morph
  // weights applied, nothing animated).
  SceneRig rig;
  // Which meshes and images these are, for a renderer that draws the scene again: a renderer
  // takes the meshes and images of a scene whose revision is that of the last scene it
  // rendered, and not 0, as that scene's, without hashing their bytes again (the texture
  // digests of a 2048^2 image, 1-2 ms a render). With 0 they are hashed every render.
  // loadGltf() gives each scene a new revision, and poseScene() whenever it deforms a mesh;
  // whoever changes a scene's meshes or images in place gives it newSceneRevision() or 0, as
  // three.js asks for `needsUpdate` (a copy of a scene keeps its revision, and may).
  std::uint64_t revision = 0;
};

// A revision no other scene of this process has (Scene::revision): random, never 0.
std::uint64_t newSceneRevision();

}  // namespace omnishadow
