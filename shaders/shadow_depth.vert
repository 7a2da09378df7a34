// Shadow pass: depth only. Alpha-masked materials also need their texture coordinates.
#include "scene_vertex.glsl"

uniform mat4 uModel;
uniform mat4 uViewProjection;

out vec2 vUv0;
out vec2 vUv1;
out float vAlpha;

void main() {
  vUv0 = aUv0;
  vUv1 = aUv1;
  vAlpha = aColor.a;
  gl_Position = uViewProjection * (uModel * vec4(aPosition, 1.0));
}
