// glTF 2.0 BRDF (Appendix B of the specification), for metallic-roughness and
// specular-glossiness materials: Lambert diffuse,
// GGX distribution, height-correlated Smith visibility, Schlick Fresnel.
const float PI = 3.14159265358979;

float distributionGgx(float NdotH, float alpha) {
  float a2 = alpha * alpha;
  float d = NdotH * NdotH * (a2 - 1.0) + 1.0;
  return a2 / (PI * d * d);
}

float visibilitySmithGgxCorrelated(float NdotV, float NdotL, float alpha) {
  float a2 = alpha * alpha;
  float ggxV = NdotL * sqrt(NdotV * NdotV * (1.0 - a2) + a2);
  float ggxL = NdotV * sqrt(NdotL * NdotL * (1.0 - a2) + a2);
  float sum = ggxV + ggxL;
  return sum > 0.0 ? 0.5 / sum : 0.0;
}

vec3 fresnelSchlick(vec3 f0, float VdotH) {
  // VdotH may exceed 1 by rounding (camera at the light), hence the clamp. The fifth power by
  // multiplication: llvmpipe computes pow() as exp2(y log2(x)), two polynomials per fragment
  // and light.
  float x = clamp(1.0 - VdotH, 0.0, 1.0);
  float x2 = x * x;
  return f0 + (1.0 - f0) * (x2 * x2 * x);
}

// Outgoing radiance towards V for light arriving from L with the given radiance, split into
// its diffuse and specular parts (the per-light AOV layers report them separately): Lambert
// diffuse of diffuseWeight * diffuseColor where Fresnel leaves light over, GGX specular from f0.
void shadeBrdf(vec3 N, vec3 V, vec3 L, vec3 radiance, vec3 diffuseColor, float diffuseWeight,
               vec3 f0, float roughness, out vec3 diffuse, out vec3 specular) {
  diffuse = vec3(0.0);
  specular = vec3(0.0);
  float NdotL = dot(N, L);
  if (NdotL <= 0.0) return;
  vec3 H = normalize(L + V);
  float NdotV = max(dot(N, V), 1e-4);
  float NdotH = max(dot(N, H), 0.0);
  float VdotH = max(dot(V, H), 0.0);
  float alpha = max(roughness * roughness, 1e-3);
  vec3 F = fresnelSchlick(f0, VdotH);
  vec3 irradiance = radiance * NdotL;
  diffuse = (1.0 - F) * diffuseWeight * diffuseColor / PI * irradiance;
  specular = F * distributionGgx(NdotH, alpha) *
             visibilitySmithGgxCorrelated(NdotV, NdotL, alpha) * irradiance;
}

// Metallic-roughness: metals have no diffuse and tint their reflection; dielectrics reflect 4%.
void shadePbr(vec3 N, vec3 V, vec3 L, vec3 radiance, vec3 baseColor, float metallic,
              float roughness, out vec3 diffuse, out vec3 specular) {
  shadeBrdf(N, V, L, radiance, baseColor, 1.0 - metallic, mix(vec3(0.04), baseColor, metallic),
            roughness, diffuse, specular);
}

// KHR_materials_pbrSpecularGlossiness as its specification defines it: F0 is the specular
// color, the diffuse color is scaled by 1 - max(specular), roughness is 1 - glossiness.
void shadeSpecularGlossiness(vec3 N, vec3 V, vec3 L, vec3 radiance, vec3 diffuseColor,
                             vec3 specularColor, float roughness, out vec3 diffuse,
                             out vec3 specular) {
  float weight = 1.0 - max(specularColor.r, max(specularColor.g, specularColor.b));
  shadeBrdf(N, V, L, radiance, diffuseColor, weight, specularColor, roughness, diffuse, specular);
}

// Blinn-Phong as in the classic point-shadow tutorial, in the same photometric units:
// normalized Blinn-Phong lobe with a shininess derived from roughness.
void shadePhong(vec3 N, vec3 V, vec3 L, vec3 radiance, vec3 baseColor, float roughness,
                out vec3 diffuse, out vec3 specular) {
  diffuse = vec3(0.0);
  specular = vec3(0.0);
  float NdotL = dot(N, L);
  if (NdotL <= 0.0) return;
  vec3 H = normalize(L + V);
  float alpha = max(roughness * roughness, 1e-3);
  float shininess = max(2.0 / (alpha * alpha) - 2.0, 1.0);
  float lobe = (shininess + 8.0) / (8.0 * PI) * pow(max(dot(N, H), 0.0), shininess);
  vec3 irradiance = radiance * NdotL;
  diffuse = baseColor / PI * irradiance;
  specular = vec3(0.04) * lobe * irradiance;
}
