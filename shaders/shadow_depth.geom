// The classic single-pass cube shadow: every triangle is projected to all six faces and routed
// with gl_Layer. Kept as the baseline the other strategies are measured against.
layout(triangles) in;
layout(triangle_strip, max_vertices = 18) out;

uniform mat4 uViewProjections[6];

#if defined(ALPHA_MASK) || defined(MOMENTS)
#define SHADOW_VARYINGS
#endif

#ifdef SHADOW_VARYINGS
in ShadowVertex {
  vec3 world;
  vec2 uv0;
  vec2 uv1;
  float alpha;
} gIn[];

out ShadowVertex {
  vec3 world;
  vec2 uv0;
  vec2 uv1;
  float alpha;
} gOut;
#endif

void main() {
  for (int face = 0; face < 6; ++face) {
    gl_Layer = face;
    for (int v = 0; v < 3; ++v) {
#ifdef SHADOW_VARYINGS
      gOut.world = gIn[v].world;
      gOut.uv0 = gIn[v].uv0;
      gOut.uv1 = gIn[v].uv1;
      gOut.alpha = gIn[v].alpha;
#endif
      gl_Position = uViewProjections[face] * gl_in[v].gl_Position;
      EmitVertex();
    }
    EndPrimitive();
  }
}
