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

#ifdef ANISOTROPY
// KHR_materials_anisotropy: the pixel's tangent-space direction of stretched highlights (T, and B
// across it, both in the surface) and strength^2; lighting.frag sets it before its light loop.
// The lobe's alpha along T grows to mix(alpha, 1, strength^2), across it stays alpha: Burley's
// distribution and its height-correlated visibility, as the specification's implementation notes
// write them. With T and B of a tangent frame they give the isotropic lobe when the strength is
// 0.
struct Anisotropy {
  vec3 T, B;
  float stretch;
};
Anisotropy pixelAnisotropy;

float anisotropicLobe(vec3 N, vec3 V, vec3 L, vec3 H, float NdotV, float NdotL, float NdotH,
                      float alpha) {
  vec3 T = pixelAnisotropy.T, B = pixelAnisotropy.B;
  float at = mix(alpha, 1.0, pixelAnisotropy.stretch), ab = alpha;
  float a2 = at * ab;
  vec3 f = vec3(ab * dot(T, H), at * dot(B, H), a2 * NdotH);
  float w2 = a2 / dot(f, f);
  float distribution = a2 * w2 * w2 / PI;
  float ggxV = NdotL * length(vec3(at * dot(T, V), ab * dot(B, V), NdotV));
  float ggxL = NdotV * length(vec3(at * dot(T, L), ab * dot(B, L), NdotL));
  float sum = ggxV + ggxL;
  return distribution * (sum > 0.0 ? 0.5 / sum : 0.0);
}
// The specular lobe (D x V) of the BRDFs below: without ANISOTROPY exactly the products they
// always computed, in the same order.
#define SPECULAR_LOBE(N, V, L, H, NdotV, NdotL, NdotH, alpha) \
  anisotropicLobe(N, V, L, H, NdotV, NdotL, NdotH, alpha)
#else
#define SPECULAR_LOBE(N, V, L, H, NdotV, NdotL, NdotH, alpha) \
  distributionGgx(NdotH, alpha) * visibilitySmithGgxCorrelated(NdotV, NdotL, alpha)
#endif

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
  specular = F * SPECULAR_LOBE(N, V, L, H, NdotV, NdotL, NdotH, alpha) * irradiance;
}

// Metallic-roughness: metals have no diffuse and tint their reflection; dielectrics reflect
// dielectricF0 at normal incidence (4% at glTF's IOR of 1.5; KHR_materials_ior sets others).
void shadePbr(vec3 N, vec3 V, vec3 L, vec3 radiance, vec3 baseColor, float metallic,
              float roughness, float dielectricF0, out vec3 diffuse, out vec3 specular) {
  shadeBrdf(N, V, L, radiance, baseColor, 1.0 - metallic,
            mix(vec3(dielectricF0), baseColor, metallic), roughness, diffuse, specular);
}

// KHR_materials_specular's factors, as its specification writes the dielectric part: Fresnel
// from min(dielectricF0 specularColor, 1) specularWeight at normal incidence to specularWeight
// at grazing, the diffuse weighted by what the brightest channel of it leaves; the metal part as
// in shadePbr. Its first lines repeat shadeBrdf's on purpose: moving them into a shared helper
// changed the float pictures of every scene in the last bits (LLVM contracts the products
// differently), and shadeBrdf's output is kept bit for bit.
void shadePbrSpecular(vec3 N, vec3 V, vec3 L, vec3 radiance, vec3 baseColor, float metallic,
                      float roughness, float dielectricF0, float specularWeight,
                      vec3 specularColor, out vec3 diffuse, out vec3 specular) {
  diffuse = vec3(0.0);
  specular = vec3(0.0);
  float NdotL = dot(N, L);
  if (NdotL <= 0.0) return;
  vec3 H = normalize(L + V);
  float NdotV = max(dot(N, V), 1e-4);
  float NdotH = max(dot(N, H), 0.0);
  float VdotH = max(dot(V, H), 0.0);
  float alpha = max(roughness * roughness, 1e-3);
  vec3 f0 = min(dielectricF0 * specularColor, vec3(1.0)) * specularWeight;
  vec3 dielectricF = f0 + (vec3(specularWeight) - f0) * (fresnelSchlick(vec3(0.0), VdotH).r);
  vec3 F = mix(dielectricF, fresnelSchlick(baseColor, VdotH), metallic);
  vec3 irradiance = radiance * NdotL;
  float diffuseWeight = (1.0 - metallic) *
                        (1.0 - max(dielectricF.r, max(dielectricF.g, dielectricF.b)));
  diffuse = diffuseWeight * baseColor / PI * irradiance;
  specular = F * SPECULAR_LOBE(N, V, L, H, NdotV, NdotL, NdotH, alpha) * irradiance;
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
                vec3 specularF0, out vec3 diffuse, out vec3 specular) {
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
  specular = specularF0 * lobe * irradiance;
}

#ifdef IRIDESCENCE
// KHR_materials_iridescence: a thin film over the material, as its specification's
// implementation notes write it (Belcour and Barla 2017, with Schlick's Fresnel at both
// interfaces and the spectral integral in Fourier space). The film's Fresnel depends on the
// view alone: lighting.frag works it out once per pixel for the dielectric and the metal base.
const mat3 XYZ_TO_REC709 = mat3(3.2404542, -0.9692660, 0.0556434, -1.5371385, 1.8760108,
                                -0.2040259, -0.4985314, 0.0415560, 1.0572252);

vec3 iridescenceSensitivity(float opd, vec3 shift) {
  float phase = 2.0 * PI * opd * 1.0e-9;
  vec3 val = vec3(5.4856e-13, 4.4201e-13, 5.2481e-13);
  vec3 pos = vec3(1.6810e+06, 1.7953e+06, 2.2084e+06);
  vec3 var = vec3(4.3278e+09, 9.3046e+09, 6.6121e+09);
  vec3 xyz = val * sqrt(2.0 * PI * var) * cos(pos * phase + shift) * exp(-phase * phase * var);
  xyz.x += 9.7470e-14 * sqrt(2.0 * PI * 4.5282e+09) * cos(2.2399e+06 * phase + shift[0]) *
           exp(-4.5282e+09 * phase * phase);
  xyz /= 1.0685e-7;
  return XYZ_TO_REC709 * xyz;
}

float schlickScalar(float f0, float c) {
  float x = clamp(1.0 - c, 0.0, 1.0);
  float x2 = x * x;
  return f0 + (1.0 - f0) * (x2 * x2 * x);
}

// The film's Fresnel at cos(theta1) = N.V for a base of reflectance baseF0, the film of index
// filmIor and thickness nanometres, in air. A film of no thickness is no film (the Khronos
// sample viewer's limit, which the specification's formulas approach).
vec3 iridescentFresnel(float filmIor, vec3 baseF0, float thickness, float cosTheta1) {
  float ior = mix(1.0, filmIor, smoothstep(0.0, 0.03, thickness));
  float sinTheta2Sq = (1.0 / (ior * ior)) * (1.0 - cosTheta1 * cosTheta1);
  float cosTheta2Sq = 1.0 - sinTheta2Sq;
  if (cosTheta2Sq < 0.0) return vec3(1.0);  // total internal reflection
  float cosTheta2 = sqrt(cosTheta2Sq);
  float r0 = (ior - 1.0) / (ior + 1.0);
  float R12 = schlickScalar(r0 * r0, cosTheta1);
  float T121 = 1.0 - R12;
  float phi12 = ior < 1.0 ? PI : 0.0;
  float phi21 = PI - phi12;
  vec3 sqrtF0 = sqrt(clamp(baseF0, 0.0, 0.9999));
  vec3 baseIor = (1.0 + sqrtF0) / (1.0 - sqrtF0);
  vec3 r1 = (baseIor - ior) / (baseIor + ior);
  vec3 R1 = r1 * r1;
  vec3 x = vec3(clamp(1.0 - cosTheta2, 0.0, 1.0));
  vec3 R23 = R1 + (1.0 - R1) * (x * x * x * x * x);
  vec3 phi23 = vec3(baseIor.r < ior ? PI : 0.0, baseIor.g < ior ? PI : 0.0,
                    baseIor.b < ior ? PI : 0.0);
  float opd = 2.0 * ior * thickness * cosTheta2;
  vec3 phi = vec3(phi21) + phi23;
  vec3 R123 = clamp(R12 * R23, 1e-5, 0.9999);
  vec3 r123 = sqrt(R123);
  vec3 Rs = T121 * T121 * R23 / (1.0 - R123);
  vec3 I = R12 + Rs;
  vec3 Cm = Rs - T121;
  for (int m = 1; m <= 2; ++m) {
    Cm *= r123;
    I += Cm * 2.0 * iridescenceSensitivity(float(m) * opd, float(m) * phi);
  }
  return max(I, vec3(0.0));
}

// A pixel's film: its strength (factor x texture), and its Fresnel over the dielectric and
// over the metal base.
struct Iridescence {
  float strength;
  vec3 dielectric, metal;
};

// What a light's specular lobe and Fresnel take, as shadeBrdf works them out; false for a light
// behind the surface.
struct LightGeometry {
  vec3 H;
  float NdotL, NdotV, NdotH, VdotH, alpha;
};

bool lightGeometry(vec3 N, vec3 V, vec3 L, float roughness, out LightGeometry g) {
  g.NdotL = dot(N, L);
  g.H = normalize(L + V);
  g.NdotV = max(dot(N, V), 1e-4);
  g.NdotH = max(dot(N, g.H), 0.0);
  g.VdotH = max(dot(V, g.H), 0.0);
  g.alpha = max(roughness * roughness, 1e-3);
  return g.NdotL > 0.0;
}

// shadePbr with the film: the dielectric keeps mix(its Fresnel mix of diffuse and specular,
// rgb_mix(diffuse, specular, film), strength), rgb_mix weighting the diffuse by 1 - the film's
// brightest channel; the metal's Fresnel mixes towards the film's by the strength.
void shadePbrIridescent(vec3 N, vec3 V, vec3 L, vec3 radiance, vec3 baseColor, float metallic,
                        float roughness, float dielectricF0, Iridescence film, out vec3 diffuse,
                        out vec3 specular) {
  diffuse = vec3(0.0);
  specular = vec3(0.0);
  LightGeometry g;
  if (!lightGeometry(N, V, L, roughness, g)) return;
  float dielectricF = schlickScalar(dielectricF0, g.VdotH);
  vec3 dielectric = mix(vec3(dielectricF), film.dielectric, film.strength);
  vec3 metal = mix(fresnelSchlick(baseColor, g.VdotH), film.metal, film.strength);
  float filmMax = max(film.dielectric.r, max(film.dielectric.g, film.dielectric.b));
  float diffuseWeight =
      (1.0 - metallic) * mix(1.0 - dielectricF, 1.0 - filmMax, film.strength);
  vec3 irradiance = radiance * g.NdotL;
  diffuse = diffuseWeight * baseColor / PI * irradiance;
  specular = mix(dielectric, metal, metallic) *
             SPECULAR_LOBE(N, V, L, g.H, g.NdotV, g.NdotL, g.NdotH, g.alpha) * irradiance;
}

#ifdef DIELECTRIC_SPECULAR
// shadePbrSpecular with the film, as the specification writes the two together: the
// dielectric's Fresnel is mix(specularWeight x its Fresnel, the film's (over specularWeight x
// its F0), strength), and the diffuse keeps 1 - its brightest channel.
void shadePbrSpecularIridescent(vec3 N, vec3 V, vec3 L, vec3 radiance, vec3 baseColor,
                                float metallic, float roughness, float dielectricF0,
                                float specularWeight, vec3 specularColor, Iridescence film,
                                out vec3 diffuse, out vec3 specular) {
  diffuse = vec3(0.0);
  specular = vec3(0.0);
  LightGeometry g;
  if (!lightGeometry(N, V, L, roughness, g)) return;
  vec3 f0 = min(dielectricF0 * specularColor, vec3(1.0)) * specularWeight;
  vec3 dielectricF = f0 + (vec3(specularWeight) - f0) * schlickScalar(0.0, g.VdotH);
  vec3 dielectric = mix(dielectricF, film.dielectric, film.strength);
  vec3 metal = mix(fresnelSchlick(baseColor, g.VdotH), film.metal, film.strength);
  vec3 irradiance = radiance * g.NdotL;
  float diffuseWeight =
      (1.0 - metallic) * (1.0 - max(dielectric.r, max(dielectric.g, dielectric.b)));
  diffuse = diffuseWeight * baseColor / PI * irradiance;
  specular = mix(dielectric, metal, metallic) *
             SPECULAR_LOBE(N, V, L, g.H, g.NdotV, g.NdotL, g.NdotH, g.alpha) * irradiance;
}
#endif
#endif

#ifdef SHEEN
// KHR_materials_sheen, as its specification's implementation notes write it: the "Charlie"
// distribution and visibility of Conty and Kulla (2017), layered over the base material by
// albedo scaling. renderer/view/sheen_brdf.h has the same formulas on the CPU, as written there;
// here what depends on the pixel alone is worked out once, before the light loop.
float charlieDistribution(float NdotH, float alphaG) {
  float inverse = 1.0 / alphaG;
  float sin2h = max(1.0 - NdotH * NdotH, 0.0);
  return (2.0 + inverse) * pow(sin2h, 0.5 * inverse) / (2.0 * PI);
}

float charlieLambdaFit(float x, float alphaG) {
  float t = (1.0 - alphaG) * (1.0 - alphaG);
  float a = mix(21.5473, 25.3245, t);
  float b = mix(3.82987, 3.32435, t);
  float c = mix(0.19823, 0.16801, t);
  float d = mix(-1.97760, -1.27393, t);
  float e = mix(-4.32054, -4.85967, t);
  return a / (1.0 + b * pow(x, c)) + d * x + e;
}

// The specification's lambda_sheen: exp(l(x)) below 0.5, exp(2 l(0.5) - l(1 - x)) above, with
// l(0.5) given. Both branches evaluate l at min(x, 1 - x): one l, where llvmpipe would run both.
float charlieLambda(float cosTheta, float alphaG, float lambdaFitHalf) {
  float x = abs(cosTheta);
  float fit = charlieLambdaFit(min(x, 1.0 - x), alphaG);
  return exp(x < 0.5 ? fit : 2.0 * lambdaFitHalf - fit);
}

// E(mu, sheen roughness), the sheen's directional albedo, from the table the build computed
// (renderer/view/sheen_albedo_table.h): bilinear, as sheenAlbedo() there.
uniform vec4 uSheenAlbedo[SHEEN_ALBEDO_COSINES * SHEEN_ALBEDO_ROUGHNESSES / 4];

float sheenAlbedoEntry(int i, int j) {
  int k = j * SHEEN_ALBEDO_COSINES + i;
  return uSheenAlbedo[k >> 2][k & 3];
}

float sheenAlbedo(float mu, float sheenRoughness) {
  float x = clamp(mu, 0.0, 1.0) * float(SHEEN_ALBEDO_COSINES - 1);
  float y = clamp(sheenRoughness, 0.0, 1.0) * float(SHEEN_ALBEDO_ROUGHNESSES - 1);
  int x0 = min(int(x), SHEEN_ALBEDO_COSINES - 2);
  int y0 = min(int(y), SHEEN_ALBEDO_ROUGHNESSES - 2);
  float fx = x - float(x0), fy = y - float(y0);
  float low = mix(sheenAlbedoEntry(x0, y0), sheenAlbedoEntry(x0 + 1, y0), fx);
  float high = mix(sheenAlbedoEntry(x0, y0 + 1), sheenAlbedoEntry(x0 + 1, y0 + 1), fx);
  return mix(low, high, fy);
}

// A pixel's sheen, with what its lights share: alpha_g = roughness^2 (kept above
// MIN_SHEEN_ALPHA, as on the CPU), l(0.5), lambda(N.V), max(color), E(N.V), and the base's
// scaling towards the camera, 1 - max(color) E(N.V).
struct Sheen {
  vec3 color;
  float roughness, alphaG, lambdaFitHalf, lambdaV, strength, albedoV, scalingV;
};

Sheen sheenAt(vec3 color, float roughness, float NdotV) {
  Sheen s;
  s.color = color;
  s.roughness = roughness;
  s.alphaG = max(roughness * roughness, MIN_SHEEN_ALPHA);
  s.lambdaFitHalf = charlieLambdaFit(0.5, s.alphaG);
  s.lambdaV = charlieLambda(NdotV, s.alphaG, s.lambdaFitHalf);
  s.strength = max(color.r, max(color.g, color.b));
  s.albedoV = sheenAlbedo(NdotV, roughness);
  s.scalingV = 1.0 - s.strength * s.albedoV;
  return s;
}

// Adds the sheen to one light's base response (shadeBrdf's diffuse and specular): the base is
// scaled by min(1 - max(color) E(N.V), 1 - max(color) E(N.L)), and the sheen lobe joins the
// specular part.
void addSheen(Sheen s, vec3 N, vec3 V, vec3 L, vec3 radiance, inout vec3 diffuse,
              inout vec3 specular) {
  float NdotL = dot(N, L);
  if (NdotL <= 0.0) return;
  float NdotV = max(dot(N, V), 1e-4);
  float NdotH = max(dot(N, normalize(L + V)), 0.0);
  float visibility = 1.0 / ((1.0 + s.lambdaV + charlieLambda(NdotL, s.alphaG, s.lambdaFitHalf)) *
                            (4.0 * NdotV * NdotL));
  float scaling = min(s.scalingV, 1.0 - s.strength * sheenAlbedo(NdotL, s.roughness));
  diffuse *= scaling;
  specular = specular * scaling +
             s.color * charlieDistribution(NdotH, s.alphaG) * visibility * radiance * NdotL;
}
#endif

#ifdef CLEARCOAT
// KHR_materials_clearcoat, as its specification's implementation notes write it: a GGX lobe of
// the layer's roughness and normal (Appendix B's D and V), over the material by fresnel_coat:
// the layer reflects with weight clearcoat x Fresnel(0.04, |Nc.V|), and everything below it
// (diffuse, specular, sheen, emission, ambient) keeps 1 - weight. A pixel's layer, with what its
// lights share:
struct Clearcoat {
  vec3 N;        // the layer's normal
  float NdotV;   // floored as shadeBrdf floors its own
  float alpha;   // clearcoatRoughness^2, floored as shadeBrdf floors its own
  float weight;  // clearcoat x its Fresnel towards the camera
};

Clearcoat clearcoatAt(float clearcoat, float roughness, vec3 N, vec3 V) {
  Clearcoat c;
  c.N = N;
  c.NdotV = max(dot(N, V), 1e-4);
  c.alpha = max(roughness * roughness, 1e-3);
  c.weight = clearcoat * fresnelSchlick(vec3(0.04), abs(dot(N, V))).r;
  return c;
}

// Layers the clearcoat over one light's response (diffuse and specular of everything below it):
// those keep 1 - weight, and the layer's lobe joins the specular part.
void addClearcoat(Clearcoat c, vec3 V, vec3 L, vec3 radiance, inout vec3 diffuse,
                  inout vec3 specular) {
  diffuse *= 1.0 - c.weight;
  specular *= 1.0 - c.weight;
  float NdotL = dot(c.N, L);
  if (NdotL <= 0.0) return;
  float NdotH = max(dot(c.N, normalize(L + V)), 0.0);
  specular += c.weight * distributionGgx(NdotH, c.alpha) *
              visibilitySmithGgxCorrelated(c.NdotV, NdotL, c.alpha) * NdotL * radiance;
}
#endif

#ifdef TRANSMISSION
// KHR_materials_transmission's specular BTDF for a thin wall, as the Khronos sample viewer
// writes it: light from L on the far side of the surface leaves towards V through a GGX lobe of
// `alpha` around the straight line through the wall (no refraction: the wall is thin; there,
// V = -L, the half vector of V and L mirrored to the camera's side is N). Zero for a light on the
// camera's side. The caller weights it by transmission x base color.
vec3 transmittedRadiance(vec3 N, vec3 V, vec3 L, vec3 radiance, float alpha) {
  float NdotL = dot(N, L);
  if (NdotL >= 0.0) return vec3(0.0);
  vec3 mirrored = L - 2.0 * NdotL * N;
  float NdotH = max(dot(N, normalize(mirrored + V)), 0.0);
  float NdotV = max(dot(N, V), 1e-4);
  return distributionGgx(NdotH, alpha) * visibilitySmithGgxCorrelated(NdotV, -NdotL, alpha) *
         -NdotL * radiance;
}
#endif
