#include "renderer/passes/shadow_pass.h"

#include <array>
#include <cmath>
#include <cstdint>

#include "renderer/gl/gl_debug.h"

namespace omnishadow {
namespace {

// glMultiDrawElementsIndirect's command layout.
struct DrawCommand {
  GLuint count;
  GLuint instanceCount;
  GLuint firstIndex;
  GLint baseVertex;
  GLuint baseInstance;
};

// Clip-space planes of a view-projection with a [0,1] depth range, normalized.
struct Frustum {
  std::array<glm::vec4, 6> planes;
  explicit Frustum(const glm::mat4& m) {
    const glm::vec4 r0(m[0][0], m[1][0], m[2][0], m[3][0]);
    const glm::vec4 r1(m[0][1], m[1][1], m[2][1], m[3][1]);
    const glm::vec4 r2(m[0][2], m[1][2], m[2][2], m[3][2]);
    const glm::vec4 r3(m[0][3], m[1][3], m[2][3], m[3][3]);
    planes = {r3 + r0, r3 - r0, r3 + r1, r3 - r1, r2, r3 - r2};
    for (glm::vec4& p : planes) p /= glm::length(glm::vec3(p));
  }
  bool touches(const glm::vec3& center, float radius) const {
    for (const glm::vec4& p : planes)
      if (glm::dot(glm::vec3(p), center) + p.w < -radius) return false;
    return true;
  }
};

// Calls visit(first, count) for each run of consecutive set bits among the low `views` bits of
// `mask`: the faces one instanced draw can cover.
template <typename Visit>
void forEachFaceRun(unsigned mask, int views, Visit visit) {
  for (int v = 0; v < views;) {
    if (!(mask & (1u << v))) {
      ++v;
      continue;
    }
    int end = v;
    while (end < views && (mask & (1u << end))) ++end;
    visit(v, end - v);
    v = end;
  }
}

// Opaque draws are sorted into culling states: both sides, counter-clockwise or clockwise
// front faces (mirrored transforms).
enum Bucket { kNoCull = 0, kCullCcw, kCullCw, kBucketCount };

}  // namespace

ShadowPassStrategy resolveShadowPassStrategy(ShadowPassStrategy requested,
                                             const std::string& glRenderer) {
  if (requested != ShadowPassStrategy::Auto) return requested;
  // Measured with scripts/bench-shadows.sh (docs/performance.md), 250k triangles, 4 point
  // lights at 1024^2, llvmpipe on 2 cores (9853f53): six 305 ms, instanced 336 ms, geometry
  // 677 ms (medians of 9 rounds). llvmpipe runs the geometry shader on the thread that also does
  // all vertex work and setup, while per-face passes keep that thread light and let the
  // rasterizer threads work. No GPU driver has been measured yet; "six" is the safe choice there
  // as well until it is.
  (void)glRenderer;
  return ShadowPassStrategy::Six;
}

ShadowPass::ShadowPass() : framebuffer_(gl::createFramebuffer()) {}
ShadowPass::~ShadowPass() = default;

const ShaderProgram& ShadowPass::program(ShadowPassStrategy strategy, bool masked, bool moments,
                                         bool worldPositions) {
  const int key = static_cast<int>(strategy) * 8 + (worldPositions ? 4 : 0) + (masked ? 2 : 0) +
                  (moments ? 1 : 0);
  auto& slot = programs_[key];
  if (!slot) {
    std::vector<std::string> defines;
    if (masked) defines.emplace_back("ALPHA_MASK");
    if (moments) defines.emplace_back("MOMENTS");
    if (worldPositions) defines.emplace_back("WORLD_POSITIONS");
    std::string geometry;
    if (strategy == ShadowPassStrategy::Instanced) defines.emplace_back("LAYER_FROM_INSTANCE");
    if (strategy == ShadowPassStrategy::Geometry) {
      defines.emplace_back("GEOMETRY_LAYERS");
      geometry = "shadow_depth.geom";
    }
    slot = std::make_unique<ShaderProgram>("shadow_depth.vert", "shadow_depth.frag", defines,
                                           geometry);
  }
  return *slot;
}

void ShadowPass::render(const GpuScene& scene, const Light& light, const LightShadowPlan& plan,
                        const ShadowGroupTextures& target, ShadowPassStrategy strategy) {
  const bool cube = target.key.layout == ShadowLayout::Cube;
  if (!cube || strategy == ShadowPassStrategy::Auto) strategy = ShadowPassStrategy::Six;
  const bool layered = strategy != ShadowPassStrategy::Six;
  const bool moments = target.key.moments;
  const int n = target.key.resolution;
  const int views = plan.layerCount;

  // Which views each object can touch: one bit per view.
  std::vector<Frustum> frusta;
  for (int v = 0; v < views; ++v) frusta.emplace_back(plan.viewProjection[v]);
  const std::vector<GpuDraw>& draws = scene.draws();
  std::vector<unsigned> viewMask(draws.size(), 0u);
  for (std::size_t d = 0; d < draws.size(); ++d)
    for (int v = 0; v < views; ++v)
      if (frusta[v].touches(draws[d].boundsCenter, draws[d].boundsRadius)) viewMask[d] |= 1u << v;

  const ShadowSettings& settings = light.shadow;
  auto isMasked = [&](const GpuDraw& draw) {
    // Blended surfaces cast shadows where they are at least half opaque.
    return scene.materials()[draw.material].desc.alphaMode != AlphaMode::Opaque;
  };
  // Along any ray from a point outside a closed solid the first surface is a front face, so
  // its back faces cannot change a depth: they are skipped even with cullFace "none" (half the
  // triangles to set up and rasterize). "Outside" keeps a margin of the near plane's reach
  // (the frustum corner's distance at depth `near`), so that no front face is clipped away.
  const float t = cube ? 1.0f : plan.tanHalfFov;
  const float nearReach = plan.near * std::sqrt(1.0f + 2.0f * t * t);
  auto seesOnlyFrontFaces = [&](const GpuDraw& draw) {
    if (!scene.meshes()[draw.mesh].closed || isMasked(draw)) return false;
    if (light.type == LightType::Directional) return true;  // the depth range holds the scene
    return glm::distance(light.position, draw.boundsCenter) > draw.boundsRadius + nearReach;
  };
  auto bucketOf = [&](const GpuDraw& draw) {
    const bool userCull =
        settings.cullFace != CullFace::None && !scene.materials()[draw.material].desc.doubleSided;
    if (!userCull && !(settings.cullFace == CullFace::None && seesOnlyFrontFaces(draw)))
      return kNoCull;
    return draw.mirrored ? kCullCw : kCullCcw;
  };
  std::vector<int> buckets(draws.size());
  for (std::size_t d = 0; d < draws.size(); ++d) buckets[d] = bucketOf(draws[d]);

  // Multi-draw calls: (bucket, view or -1 for layered, caster stream or not, first command,
  // command count).
  struct Call {
    int bucket, view;
    bool world;
    int first, count;
  };
  std::vector<Call> calls;
  std::vector<GLuint> commandWords, objects;
  auto addCommand = [&](std::size_t d, GLuint firstView, GLuint viewCount, bool world) {
    const GpuMeshRange& range = scene.meshes()[draws[d].mesh];
    const DrawCommand c{static_cast<GLuint>(range.indexCount), viewCount,
                        static_cast<GLuint>(range.firstIndex),
                        world ? draws[d].casterBaseVertex : range.baseVertex, firstView};
    const auto* words = reinterpret_cast<const GLuint*>(&c);
    commandWords.insert(commandWords.end(), words, words + 5);
    objects.push_back(static_cast<GLuint>(d));
  };
  auto collect = [&](int bucket, int view, bool world) {
    const int first = static_cast<int>(objects.size());
    for (std::size_t d = 0; d < draws.size(); ++d) {
      if (isMasked(draws[d]) || buckets[d] != bucket || viewMask[d] == 0 ||
          (draws[d].casterBaseVertex >= 0) != world)
        continue;
      if (view >= 0) {
        if (viewMask[d] & (1u << view)) addCommand(d, 0, 1, world);
      } else if (strategy == ShadowPassStrategy::Geometry) {
        addCommand(d, 0, 1, world);
      } else {
        // Runs of consecutive faces become one command each.
        forEachFaceRun(viewMask[d], views, [&](int first, int count) {
          addCommand(d, static_cast<GLuint>(first), static_cast<GLuint>(count), world);
        });
      }
    }
    const int count = static_cast<int>(objects.size()) - first;
    if (count > 0) calls.push_back({bucket, view, world, first, count});
  };
  for (int view = layered ? -1 : 0; view < (layered ? 0 : views); ++view)
    for (int bucket = 0; bucket < kBucketCount; ++bucket)
      for (const bool world : {true, false}) collect(bucket, view, world);
  commands_.upload(commandWords);
  drawObjects_.upload(objects);

  // Fixed state of the whole light.
  const GLuint fb = framebuffer_.get();
  glBindFramebuffer(GL_FRAMEBUFFER, fb);
  glViewport(0, 0, n, n);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_GREATER);  // reversed depth: nearer is larger
  glDepthMask(GL_TRUE);
  glDisable(GL_BLEND);
  const GLboolean writeColor = moments ? GL_TRUE : GL_FALSE;
  glColorMask(writeColor, writeColor, GL_FALSE, GL_FALSE);
  glNamedFramebufferDrawBuffer(fb, moments ? GL_COLOR_ATTACHMENT0 : GL_NONE);
  glNamedFramebufferReadBuffer(fb, GL_NONE);
  if (settings.polygonOffsetFactor != 0.0f || settings.polygonOffsetUnits != 0.0f) {
    // Reversed depth: pushing casters away from the light means smaller depth values.
    glEnable(GL_POLYGON_OFFSET_FILL);
    glPolygonOffset(-settings.polygonOffsetFactor, -settings.polygonOffsetUnits);
  }
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, scene.modelBuffer());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 2, drawObjects_.get());
  glBindBuffer(GL_DRAW_INDIRECT_BUFFER, commands_.get());

  // Layers are cleared through the framebuffer, not with glClearTexSubImage: llvmpipe then
  // clears tile by tile in its rasterizer threads, in the pass that draws, instead of sweeping
  // the texture on the calling thread first. Layered strategies attach views of just this
  // light's layers (a layered attachment of the whole texture would clear every light).
  const float zero = 0.0f;
  const float farMoments[4] = {1.0f, 1.0f, 0.0f, 0.0f};
  auto clearAttached = [&] {
    glClearNamedFramebufferfv(fb, GL_DEPTH, 0, &zero);
    if (moments) glClearNamedFramebufferfv(fb, GL_COLOR, 0, farMoments);
  };
  gl::Texture depthLayers, momentLayers;
  auto layersView = [&](const gl::Texture& texture, GLenum format) {
    GLuint id = 0;
    glGenTextures(1, &id);
    glTextureView(id, GL_TEXTURE_2D_ARRAY, texture.get(), format, 0, 1,
                  static_cast<GLuint>(plan.firstLayer), static_cast<GLuint>(views));
    return gl::Texture(id);
  };
  std::vector<bool> cleared(static_cast<std::size_t>(views), false);
  auto attach = [&](int view) {
    if (view < 0) {
      depthLayers = layersView(target.depth, depthInternalFormat(target.key.format));
      glNamedFramebufferTexture(fb, GL_DEPTH_ATTACHMENT, depthLayers.get(), 0);
      if (moments) momentLayers = layersView(target.moments, GL_RG32F);
      glNamedFramebufferTexture(fb, GL_COLOR_ATTACHMENT0, moments ? momentLayers.get() : 0, 0);
      clearAttached();
      return;
    }
    glNamedFramebufferTextureLayer(fb, GL_DEPTH_ATTACHMENT, target.depth.get(), 0,
                                   plan.firstLayer + view);
    if (moments)
      glNamedFramebufferTextureLayer(fb, GL_COLOR_ATTACHMENT0, target.moments.get(), 0,
                                     plan.firstLayer + view);
    else
      glNamedFramebufferTexture(fb, GL_COLOR_ATTACHMENT0, 0, 0);
    if (!cleared[static_cast<std::size_t>(view)]) {
      clearAttached();
      cleared[static_cast<std::size_t>(view)] = true;
    }
  };
  auto setCulling = [&](int bucket) {
    if (bucket == kNoCull) {
      glDisable(GL_CULL_FACE);
      return;
    }
    glEnable(GL_CULL_FACE);
    glCullFace(settings.cullFace == CullFace::Front ? GL_FRONT : GL_BACK);
    glFrontFace(bucket == kCullCw ? GL_CW : GL_CCW);
  };
  auto prepare = [&](const ShaderProgram& p, int view) {
    p.use();
    p.set("uViewProjections", plan.viewProjection.data(), views);
    p.set("uView", std::max(view, 0));
    if (moments) {
      p.set("uLightPosition", light.position);
      p.set("uMomentScale", 1.0f / plan.far);
      p.set("uMomentFromDepth", light.type == LightType::Directional ? 1 : 0);
    }
  };

  if (layered) attach(-1);
  int attachedView = layered ? -1 : -2;

  // Opaque casters: one multi-draw per (view, bucket, vertex source).
  for (const Call& call : calls) {
    if (call.view != attachedView) attach(attachedView = call.view);
    const ShaderProgram& opaque = program(strategy, false, moments, call.world);
    glBindVertexArray(call.world ? scene.casterVertexArray() : scene.vertexArray());
    prepare(opaque, call.view);
    opaque.set("uObject", -1);
    opaque.set("uDrawBase", call.first);
    setCulling(call.bucket);
    glMultiDrawElementsIndirect(GL_TRIANGLES, GL_UNSIGNED_INT,
                                reinterpret_cast<const void*>(
                                    static_cast<std::uintptr_t>(call.first) * sizeof(DrawCommand)),
                                call.count, 0);
  }

  // Alpha-tested casters, each with its own texture.
  glBindVertexArray(scene.vertexArray());
  const ShaderProgram& masked = program(strategy, true, moments, false);
  for (int view = layered ? -1 : 0; view < (layered ? 0 : views); ++view) {
    bool prepared = false;
    for (std::size_t d = 0; d < draws.size(); ++d) {
      const GpuDraw& draw = draws[d];
      if (!isMasked(draw) || viewMask[d] == 0) continue;
      if (view >= 0 && !(viewMask[d] & (1u << view))) continue;
      if (!prepared) {
        if (view != attachedView) attach(attachedView = view);
        prepare(masked, view);
        prepared = true;
      }
      const GpuMaterial& material = scene.materials()[draw.material];
      masked.set("uObject", static_cast<int>(d));
      masked.set("uBaseColorFactor", material.desc.baseColorFactor);
      masked.set("uHasBaseColorTexture", material.baseColor != 0 ? 1 : 0);
      masked.set("uBaseColorTexCoord", material.desc.baseColorTexture.texCoord);
      masked.set("uAlphaCutoff",
                 material.desc.alphaMode == AlphaMode::Mask ? material.desc.alphaCutoff : 0.5f);
      glBindTextureUnit(0, material.baseColor);
      glBindSampler(0, material.baseColorSampler);
      setCulling(buckets[d]);
      const GpuMeshRange& range = scene.meshes()[draw.mesh];
      const void* offset =
          reinterpret_cast<const void*>(static_cast<std::uintptr_t>(range.firstIndex) * 4);
      if (view >= 0 || strategy == ShadowPassStrategy::Geometry) {
        glDrawElementsInstancedBaseVertexBaseInstance(
            GL_TRIANGLES, range.indexCount, GL_UNSIGNED_INT, offset, 1, range.baseVertex, 0);
        continue;
      }
      forEachFaceRun(viewMask[d], views, [&](int first, int count) {
        glDrawElementsInstancedBaseVertexBaseInstance(GL_TRIANGLES, range.indexCount,
                                                      GL_UNSIGNED_INT, offset, count,
                                                      range.baseVertex, static_cast<GLuint>(first));
      });
    }
  }
  // Faces nothing was drawn into still need their clear.
  if (!layered)
    for (int view = 0; view < views; ++view)
      if (!cleared[static_cast<std::size_t>(view)]) attach(view);

  glDisable(GL_POLYGON_OFFSET_FILL);
  glDisable(GL_CULL_FACE);
  glFrontFace(GL_CCW);
  glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  glBindBuffer(GL_DRAW_INDIRECT_BUFFER, 0);
  glNamedFramebufferTexture(fb, GL_DEPTH_ATTACHMENT, 0, 0);
  glNamedFramebufferTexture(fb, GL_COLOR_ATTACHMENT0, 0, 0);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  gl::checkErrors("the shadow pass of light \"" + light.name + "\"");
}

}  // namespace omnishadow
