#include "scene_vertex.glsl"

uniform mat4 uModel;
uniform mat3 uNormalMatrix;
uniform mat4 uViewProjection;

// The depth pre-pass and the lighting pass must compute bit-identical depths (the lighting
// pass tests GL_GEQUAL against the pre-pass).
invariant gl_Position;

out VertexData {
  vec3 worldPosition;
  vec3 worldNormal;
  vec4 worldTangent;
  vec2 uv0;
  vec2 uv1;
  vec4 color;
} vOut;

void main() {
  vec4 world = uModel * vec4(aPosition, 1.0);
  vOut.worldPosition = world.xyz;
  vOut.worldNormal = uNormalMatrix * aNormal;
  vOut.worldTangent = vec4(mat3(uModel) * aTangent.xyz, aTangent.w);
  vOut.uv0 = aUv0;
  vOut.uv1 = aUv1;
  vOut.color = aColor;
  gl_Position = uViewProjection * world;
}
