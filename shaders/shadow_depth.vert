// Shadow pass, vertex stage. With WORLD_POSITIONS the positions are already in world space
// (GpuScene::casterVertexArray); otherwise model matrices come from a buffer indexed per draw.
// Either way one glMultiDrawElementsIndirect call draws every visible object. Layered variants
// draw into a view of the light's own layers, so gl_Layer is the face. Variants:
//   (none)              "six": one layer per pass, uViewProjections[uView];
//   LAYER_FROM_INSTANCE "instanced": the instance picks the cube face and writes gl_Layer;
//     with LAYER_MATRICES "batched": the instance picks a layer of the whole texture, whose
//     view-projection is in a uniform block holding a window of the texture's layers from
//     uLayerBase (many lights at once; a storage buffer made llvmpipe's vertex stage 3x
//     slower: it reads one lane at a time);
//   GEOMETRY_LAYERS     "geometry": shadow_depth.geom projects each triangle to six layers.
#extension GL_ARB_shader_draw_parameters : require
#ifdef LAYER_FROM_INSTANCE
#extension GL_ARB_shader_viewport_layer_array : require
#endif
#include "scene_vertex.glsl"

layout(std430, binding = MODELS_BINDING) readonly buffer Models { mat4 uModels[]; };
layout(std430, binding = DRAW_OBJECTS_BINDING) readonly buffer DrawObjects { uint uDrawObjects[]; };

uniform int uObject;    // >= 0: a single draw of this object; else uDrawObjects per draw
uniform int uDrawBase;  // multi-draw: the call's first entry in uDrawObjects
uniform mat4 uViewProjections[6];
#ifdef LAYER_MATRICES
layout(std140, binding = LAYER_VIEW_PROJECTIONS_UNIFORM_BINDING) uniform LayerViewProjections {
  mat4 uLayerViewProjections[MAX_UNIFORM_VIEW_PROJECTIONS];
};
uniform int uLayerBase;
#endif
uniform int uView;

#if defined(ALPHA_MASK) || defined(MOMENTS) || defined(TRANSMITTANCE)
#define SHADOW_VARYINGS
#endif

#ifdef SHADOW_VARYINGS
out ShadowVertex {
  vec3 world;
  vec2 uv0;
  vec2 uv1;
  float alpha;
#ifdef TRANSMITTANCE
  vec3 color;  // COLOR_0.rgb (shadow_transmittance.frag)
#endif
} vOut;
#endif

void main() {
#ifdef WORLD_POSITIONS
  vec4 world = vec4(aPosition, 1.0);
#else
  int object = uObject >= 0 ? uObject : int(uDrawObjects[uDrawBase + gl_DrawIDARB]);
  vec4 world = uModels[object] * vec4(aPosition, 1.0);
#endif
#ifdef SHADOW_VARYINGS
  vOut.world = world.xyz;
  vOut.uv0 = aUv0;
  vOut.uv1 = aUv1;
  vOut.alpha = aColor.a;
#ifdef TRANSMITTANCE
  vOut.color = aColor.rgb;
#endif
#endif
#if defined(LAYER_FROM_INSTANCE)
  int view = gl_BaseInstanceARB + gl_InstanceID;
  gl_Layer = view;
#ifdef LAYER_MATRICES
  gl_Position = uLayerViewProjections[view - uLayerBase] * world;
#else
  gl_Position = uViewProjections[view] * world;
#endif
#elif defined(GEOMETRY_LAYERS)
  gl_Position = world;
#else
  gl_Position = uViewProjections[uView] * world;
#endif
}
