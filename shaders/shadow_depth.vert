// Shadow pass, vertex stage. Model matrices come from a buffer indexed per draw, so one
// glMultiDrawElementsIndirect call draws every visible object. Variants:
//   (none)              "six": one layer per pass, uViewProjections[uView];
//   LAYER_FROM_INSTANCE "instanced": the instance picks the cube face and writes gl_Layer;
//   GEOMETRY_LAYERS     "geometry": shadow_depth.geom projects each triangle to six layers.
#extension GL_ARB_shader_draw_parameters : require
#ifdef LAYER_FROM_INSTANCE
#extension GL_ARB_shader_viewport_layer_array : require
#endif
#include "scene_vertex.glsl"

layout(std430, binding = 1) readonly buffer Models { mat4 uModels[]; };
layout(std430, binding = 2) readonly buffer DrawObjects { uint uDrawObjects[]; };

uniform int uObject;    // >= 0: a single draw of this object; else uDrawObjects per draw
uniform int uDrawBase;  // multi-draw: the call's first entry in uDrawObjects
uniform mat4 uViewProjections[6];
uniform int uView;
uniform int uLayerBase;

out ShadowVertex {
  vec3 world;
  vec2 uv0;
  vec2 uv1;
  float alpha;
} vOut;

void main() {
  int object = uObject >= 0 ? uObject : int(uDrawObjects[uDrawBase + gl_DrawIDARB]);
  vec4 world = uModels[object] * vec4(aPosition, 1.0);
  vOut.world = world.xyz;
  vOut.uv0 = aUv0;
  vOut.uv1 = aUv1;
  vOut.alpha = aColor.a;
#if defined(LAYER_FROM_INSTANCE)
  int view = gl_BaseInstanceARB + gl_InstanceID;
  gl_Layer = uLayerBase + view;
  gl_Position = uViewProjections[view] * world;
#elif defined(GEOMETRY_LAYERS)
  gl_Position = world;
#else
  gl_Position = uViewProjections[uView] * world;
#endif
}
