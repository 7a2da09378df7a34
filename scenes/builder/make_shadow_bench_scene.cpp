// Writes one benchmark scene for the shadow benchmarks (scripts/bench-shadows.sh): a closed
// room (floor, four walls, ceiling) filled with a few hundred to a few thousand separate
// objects (spheres, boxes, tori, cylinders; on the floor, stacked, and hanging in the air, plus
// a few pillars), a camera inside looking across the room, and point lights spread through the
// room at various heights in "<stem>.lights.json". Everything is drawn from SEED with our own
// number-to-float conversion on top of std::mt19937 (whose output the standard fixes), so one
// seed gives the same files with any compiler and standard library.
//
// Usage: make_shadow_bench_scene OUT.gltf [--triangles N] [--lights N] [--resolution N]
//            [--seed N] [--range auto|none|METERS] [--lights-per-point K]
// Writes OUT.gltf, OUT.bin and OUT.lights.json, and prints one summary line on stdout.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "scenes/builder/gltf_builder.h"

using namespace omnishadow::builder;

namespace {

constexpr float kPi = std::numbers::pi_v<float>;

// The room: x in [-kHalfW, kHalfW], z in [-kHalfD, kHalfD], y in [0, kHeight] (meters).
constexpr float kHalfW = 12.0f;
constexpr float kHalfD = 8.0f;
constexpr float kHeight = 6.0f;

struct Options {
  std::filesystem::path output;
  long triangles = 250000;
  int lights = 4;
  int resolution = 1024;
  std::uint32_t seed = 1;
  std::string range = "auto";  // auto | none | a number of meters
  int lightsPerPoint = 8;
};

[[noreturn]] void usage(const std::string& message) {
  std::fprintf(stderr,
               "make_shadow_bench_scene: %s\n"
               "usage: make_shadow_bench_scene OUT.gltf [--triangles N (10000..2000000)] "
               "[--lights N (1..256)]\n"
               "         [--resolution N] [--seed N] [--range auto|none|METERS] "
               "[--lights-per-point K]\n",
               message.c_str());
  std::exit(2);
}

long parseInteger(const std::string& name, const std::string& text, long low, long high) {
  char* end = nullptr;
  const long value = std::strtol(text.c_str(), &end, 10);
  if (text.empty() || *end != '\0' || value < low || value > high)
    usage(name + ": expected an integer in " + std::to_string(low) + ".." + std::to_string(high) +
          ", got \"" + text + "\"");
  return value;
}

Options parseOptions(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg.rfind("--", 0) != 0) {
      if (!o.output.empty()) usage("more than one output file");
      o.output = arg;
      continue;
    }
    if (i + 1 >= argc) usage(arg + ": missing value");
    const std::string value = argv[++i];
    if (arg == "--triangles") {
      o.triangles = parseInteger(arg, value, 10000, 2000000);
    } else if (arg == "--lights") {
      o.lights = static_cast<int>(parseInteger(arg, value, 1, 256));
    } else if (arg == "--resolution") {
      o.resolution = static_cast<int>(parseInteger(arg, value, 1, 16384));
    } else if (arg == "--seed") {
      o.seed = static_cast<std::uint32_t>(parseInteger(arg, value, 0, 4294967295L));
    } else if (arg == "--range") {
      if (value != "auto" && value != "none") {
        char* end = nullptr;
        const double meters = std::strtod(value.c_str(), &end);
        if (*end != '\0' || !(meters > 0.0) || !std::isfinite(meters))
          usage("--range: expected auto, none or a positive number of meters");
      }
      o.range = value;
    } else if (arg == "--lights-per-point") {
      o.lightsPerPoint = static_cast<int>(parseInteger(arg, value, 1, 256));
    } else {
      usage("unknown option " + arg);
    }
  }
  if (o.output.empty()) usage("no output file");
  if (o.output.extension() != ".gltf") usage("the output must end in .gltf");
  return o;
}

// Uniform floats from mt19937's (standardized) 32-bit output.
class Random {
 public:
  explicit Random(std::uint32_t seed) : engine_(seed) {}
  float unit() { return static_cast<float>(engine_() >> 8) * (1.0f / 16777216.0f); }  // [0,1)
  float range(float low, float high) { return low + (high - low) * unit(); }
  int below(int n) { return std::min(n - 1, static_cast<int>(unit() * static_cast<float>(n))); }

 private:
  std::mt19937 engine_;
};

// ------------------------------------------------------------------------------------------
// Meshes with a given triangle count (no UVs: the benchmark has no textures)

MeshData sphere(float radius, int segments, int rings) {  // segments * (2 rings - 2) triangles
  MeshData m = makeSphere(radius, segments, rings);
  m.uvs.clear();
  return m;
}

MeshData torus(float major, float minor, int around, int tube) {  // 2 around tube triangles
  MeshData m;
  for (int i = 0; i < around; ++i) {
    const float a = 2.0f * kPi * static_cast<float>(i) / static_cast<float>(around);
    const glm::vec3 dir{std::cos(a), 0.0f, std::sin(a)};
    for (int j = 0; j < tube; ++j) {
      const float b = 2.0f * kPi * static_cast<float>(j) / static_cast<float>(tube);
      const glm::vec3 n = std::cos(b) * dir + glm::vec3(0.0f, std::sin(b), 0.0f);
      m.positions.push_back(major * dir + minor * n);
      m.normals.push_back(n);
    }
  }
  const auto at = [&](int i, int j) {
    return static_cast<std::uint32_t>((i % around) * tube + (j % tube));
  };
  for (int i = 0; i < around; ++i) {
    for (int j = 0; j < tube; ++j) {
      const std::uint32_t a = at(i, j), b = at(i + 1, j), c = at(i + 1, j + 1), d = at(i, j + 1);
      m.indices.insert(m.indices.end(), {a, c, b, a, d, c});  // outward, counter-clockwise
    }
  }
  return m;
}

// A box with every face split into n x n quads: 12 n^2 triangles.
MeshData box(glm::vec3 half, int n) {
  MeshData m;
  for (const BoxFace& f : kBoxFaces) {
    const auto base = static_cast<std::uint32_t>(m.positions.size());
    for (int i = 0; i <= n; ++i) {
      for (int j = 0; j <= n; ++j) {
        const float s = 2.0f * static_cast<float>(j) / static_cast<float>(n) - 1.0f;
        const float t = 2.0f * static_cast<float>(i) / static_cast<float>(n) - 1.0f;
        m.positions.push_back((f.normal + s * f.u + t * f.v) * half);
        m.normals.push_back(f.normal);
      }
    }
    const auto at = [&](int i, int j) {
      return base + static_cast<std::uint32_t>(i * (n + 1) + j);
    };
    for (int i = 0; i < n; ++i) {
      for (int j = 0; j < n; ++j) {
        m.indices.insert(m.indices.end(), {at(i, j), at(i, j + 1), at(i + 1, j + 1), at(i, j),
                                           at(i + 1, j + 1), at(i + 1, j)});
      }
    }
  }
  return m;
}

// A cylinder along +Y from 0 to height with `segments` sides and `stacks` rows: 2 segments
// stacks + 2 segments triangles.
MeshData cylinder(float radius, float height, int segments, int stacks) {
  MeshData m;
  for (int i = 0; i <= stacks; ++i) {
    const float y = height * static_cast<float>(i) / static_cast<float>(stacks);
    for (int j = 0; j < segments; ++j) {
      const float a = 2.0f * kPi * static_cast<float>(j) / static_cast<float>(segments);
      const glm::vec3 n{std::sin(a), 0.0f, std::cos(a)};
      m.positions.push_back(radius * n + glm::vec3(0.0f, y, 0.0f));
      m.normals.push_back(n);
    }
  }
  const auto at = [&](int i, int j) {
    return static_cast<std::uint32_t>(i * segments + (j % segments));
  };
  for (int i = 0; i < stacks; ++i) {
    for (int j = 0; j < segments; ++j) {
      m.indices.insert(m.indices.end(), {at(i, j), at(i, j + 1), at(i + 1, j + 1), at(i, j),
                                         at(i + 1, j + 1), at(i + 1, j)});
    }
  }
  for (const bool top : {true, false}) {
    const float y = top ? height : 0.0f;
    const glm::vec3 n{0.0f, top ? 1.0f : -1.0f, 0.0f};
    const auto center = static_cast<std::uint32_t>(m.positions.size());
    m.positions.push_back({0.0f, y, 0.0f});
    m.normals.push_back(n);
    for (int j = 0; j < segments; ++j) {
      const float a = 2.0f * kPi * static_cast<float>(j) / static_cast<float>(segments);
      m.positions.push_back({radius * std::sin(a), y, radius * std::cos(a)});
      m.normals.push_back(n);
    }
    for (int j = 0; j < segments; ++j) {
      const std::uint32_t p = center + 1 + static_cast<std::uint32_t>(j);
      const std::uint32_t q = center + 1 + static_cast<std::uint32_t>((j + 1) % segments);
      if (top) {
        m.indices.insert(m.indices.end(), {center, p, q});
      } else {
        m.indices.insert(m.indices.end(), {center, q, p});
      }
    }
  }
  return m;
}

// A rectangle of nu x nv quads spanning origin + [0,1] u + [0,1] v, facing cross(u, v).
MeshData quadGrid(glm::vec3 origin, glm::vec3 u, glm::vec3 v, int nu, int nv) {
  MeshData m;
  const glm::vec3 n = glm::normalize(glm::cross(u, v));
  for (int i = 0; i <= nv; ++i) {
    for (int j = 0; j <= nu; ++j) {
      m.positions.push_back(origin + u * (static_cast<float>(j) / static_cast<float>(nu)) +
                            v * (static_cast<float>(i) / static_cast<float>(nv)));
      m.normals.push_back(n);
    }
  }
  const auto at = [&](int i, int j) { return static_cast<std::uint32_t>(i * (nu + 1) + j); };
  for (int i = 0; i < nv; ++i) {
    for (int j = 0; j < nu; ++j) {
      m.indices.insert(m.indices.end(), {at(i, j), at(i, j + 1), at(i + 1, j + 1), at(i, j),
                                         at(i + 1, j + 1), at(i + 1, j)});
    }
  }
  return m;
}

std::size_t triangleCount(const MeshData& m) {
  return m.indices.size() / 3;
}

PrimitiveOptions primitive(const MeshData& m, int material) {
  PrimitiveOptions p;
  p.indexType = m.positions.size() <= 65535 ? IndexType::U16 : IndexType::U32;
  p.material = material;
  return p;
}

// ------------------------------------------------------------------------------------------
// Objects

enum class Shape { Sphere, Box, Torus, Cylinder };

struct Object {
  Shape shape;
  glm::vec3 center;  // of the bounding sphere
  float radius;      // bounding sphere
  float size;        // the shape's own size parameter
  glm::vec3 base;    // node translation
  float yaw;
};

// A mesh of `shape` with about `budget` triangles (at least the shape's minimum).
MeshData shapeMesh(Shape shape, float size, long budget) {
  const auto clampInt = [](double v, int low, int high) {
    return std::clamp(static_cast<int>(std::lround(v)), low, high);
  };
  switch (shape) {
    case Shape::Sphere: {  // segments = 2 rings: 4 r^2 - 4 r triangles
      const int rings = clampInt(0.5 + std::sqrt(0.25 + static_cast<double>(budget) / 4.0), 3, 200);
      return sphere(size, 2 * rings, rings);
    }
    case Shape::Box: {
      const int n = clampInt(std::sqrt(static_cast<double>(budget) / 12.0), 1, 100);
      return box({size, size * 0.8f, size * 0.9f}, n);
    }
    case Shape::Torus: {  // around = 2 tube: 4 tube^2 triangles
      const int tube = clampInt(std::sqrt(static_cast<double>(budget) / 4.0), 3, 200);
      return torus(size * 0.7f, size * 0.28f, 2 * tube, tube);
    }
    case Shape::Cylinder: {  // segments = 4 stacks: 8 s^2 + 8 s triangles
      const int stacks = clampInt(std::sqrt(static_cast<double>(budget) / 8.0), 1, 100);
      return cylinder(size * 0.6f, size * 1.6f, 4 * stacks, stacks);
    }
  }
  throw std::logic_error("shape");
}

float windowedFalloff(float d, float range) {  // KHR_lights_punctual, as the renderer uses it
  float w = 1.0f;
  if (range > 0.0f) {
    const float r = d / range;
    w = std::clamp(1.0f - r * r * r * r, 0.0f, 1.0f);
    w *= w;
  }
  return w / std::max(d * d, 0.25f);
}

void run(const Options& o) {
  Random rng(o.seed);
  GltfBuilder b;

  // Materials: a fixed palette (no textures: the benchmark measures shadows, not sampling).
  std::vector<int> palette;
  for (int i = 0; i < 12; ++i) {
    MaterialDesc m;
    m.name = "object" + std::to_string(i);
    const float hue = static_cast<float>(i) / 12.0f * 2.0f * kPi;
    m.baseColor = {0.45f + 0.3f * std::cos(hue), 0.45f + 0.3f * std::cos(hue - 2.1f),
                   0.45f + 0.3f * std::cos(hue + 2.1f), 1.0f};
    m.roughness = 0.3f + 0.05f * static_cast<float>(i % 8);
    m.metallic = i % 5 == 0 ? 0.8f : 0.0f;
    palette.push_back(b.addMaterial(m));
  }
  MaterialDesc floorMat{
      .name = "floor", .baseColor = {0.55f, 0.5f, 0.45f, 1.0f}, .roughness = 0.8f};
  MaterialDesc wallMat{.name = "walls", .baseColor = {0.7f, 0.7f, 0.68f, 1.0f}, .roughness = 0.9f};
  const int floorMaterial = b.addMaterial(floorMat);
  const int wallMaterial = b.addMaterial(wallMat);

  // The room, facing inwards, about 1 m quads.
  long triangles = 0;
  const auto shell = [&](const std::string& name, glm::vec3 origin, glm::vec3 u, glm::vec3 v,
                         int material) {
    const MeshData m = quadGrid(origin, u, v, std::max(1, static_cast<int>(glm::length(u))),
                                std::max(1, static_cast<int>(glm::length(v))));
    triangles += static_cast<long>(triangleCount(m));
    b.addNode(name, {}, b.addMesh(m, primitive(m, material), name));
  };
  const float W = 2 * kHalfW, D = 2 * kHalfD, H = kHeight;
  shell("floor", {-kHalfW, 0, kHalfD}, {W, 0, 0}, {0, 0, -D}, floorMaterial);
  shell("ceiling", {-kHalfW, H, -kHalfD}, {W, 0, 0}, {0, 0, D}, wallMaterial);
  shell("wall -z", {-kHalfW, 0, -kHalfD}, {W, 0, 0}, {0, H, 0}, wallMaterial);
  shell("wall +z", {kHalfW, 0, kHalfD}, {-W, 0, 0}, {0, H, 0}, wallMaterial);
  shell("wall -x", {-kHalfW, 0, kHalfD}, {0, 0, -D}, {0, H, 0}, wallMaterial);
  shell("wall +x", {kHalfW, 0, -kHalfD}, {0, 0, D}, {0, H, 0}, wallMaterial);

  // The camera: in a corner at eye height, looking across the room's diagonal.
  const glm::vec3 eye{-kHalfW + 1.2f, 2.0f, kHalfD - 1.2f};
  const glm::vec3 target{kHalfW - 5.0f, 0.6f, -kHalfD + 3.0f};
  b.addPerspectiveCamera("camera", eye, target, 65.0f * kPi / 180.0f, 16.0f / 9.0f, 0.05f);

  // How many objects: grows with the triangle count (about 2 sqrt(T)), so that both the number
  // of objects to cull and their detail grow: 10k -> 200, 250k -> 1000, 2M -> ~2800.
  const int objectCount =
      std::clamp(static_cast<int>(2.0 * std::sqrt(static_cast<double>(o.triangles))), 150, 3000);
  const int pillars = 6;
  const int hanging = objectCount / 4;
  const int stacked = objectCount / 8;
  const int onFloor = objectCount - pillars - hanging - stacked;

  std::vector<Object> objects;
  const auto nearCamera = [&](glm::vec3 p, float r) {
    return glm::length(glm::vec2(p.x - eye.x, p.z - eye.z)) < 2.0f + r;
  };
  const auto randomShape = [&]() {
    const float u = rng.unit();
    return u < 0.4f    ? Shape::Sphere
           : u < 0.7f  ? Shape::Box
           : u < 0.85f ? Shape::Torus
                       : Shape::Cylinder;
  };
  // Floor objects on a jittered grid of cells (one object per cell, no overlaps).
  {
    const float cell = std::sqrt(W * D / static_cast<float>(onFloor) * 0.8f);
    const int cols = static_cast<int>(std::ceil(W / cell));
    const int rows = static_cast<int>(std::ceil(D / cell));
    std::vector<int> cells(static_cast<std::size_t>(cols * rows));
    for (std::size_t i = 0; i < cells.size(); ++i) cells[i] = static_cast<int>(i);
    for (std::size_t i = cells.size() - 1; i > 0; --i)
      std::swap(cells[i], cells[static_cast<std::size_t>(rng.below(static_cast<int>(i) + 1))]);
    const float cw = W / static_cast<float>(cols), cd = D / static_cast<float>(rows);
    int placedPillars = 0;
    for (int c : cells) {
      if (static_cast<int>(objects.size()) >= onFloor + pillars) break;
      const float x0 = -kHalfW + cw * static_cast<float>(c % cols);
      const float z0 = -kHalfD + cd * static_cast<float>(c / cols);
      const float maxR = 0.45f * std::min(cw, cd);
      if (placedPillars < pillars) {
        const float r = std::min(0.3f, maxR);
        const glm::vec3 at{x0 + cw * 0.5f, 0.0f, z0 + cd * 0.5f};
        if (nearCamera(at, r)) continue;
        objects.push_back({Shape::Cylinder, {at.x, H * 0.5f, at.z}, H * 0.5f, r, at, -1.0f});
        ++placedPillars;
        continue;
      }
      const Shape shape = randomShape();
      const float size = maxR * rng.range(0.55f, 0.9f);
      const float jitter = std::min(cw, cd) * 0.5f - size;
      const float margin = size * 1.35f;  // keep rotated shapes out of the walls
      const glm::vec3 at{std::clamp(x0 + cw * 0.5f + rng.range(-jitter, jitter) * 0.8f,
                                    -kHalfW + margin, kHalfW - margin),
                         0.0f,
                         std::clamp(z0 + cd * 0.5f + rng.range(-jitter, jitter) * 0.8f,
                                    -kHalfD + margin, kHalfD - margin)};
      if (nearCamera(at, size)) continue;
      float lift = size;  // resting on the floor
      if (shape == Shape::Box) lift = size * 0.8f;
      if (shape == Shape::Torus) lift = size * 0.28f;
      if (shape == Shape::Cylinder) lift = 0.0f;
      const float centerY = shape == Shape::Cylinder ? size * 0.8f : lift;
      objects.push_back({shape,
                         {at.x, centerY, at.z},
                         size * 1.3f,
                         size,
                         {at.x, lift, at.z},
                         rng.range(0.0f, 2.0f * kPi)});
    }
  }
  // Stacked objects: a smaller sphere or box on top of a floor box or cylinder.
  {
    std::vector<std::size_t> supports;
    for (std::size_t i = 0; i < objects.size(); ++i)
      if (objects[i].yaw >= 0.0f &&
          (objects[i].shape == Shape::Box || objects[i].shape == Shape::Cylinder))
        supports.push_back(i);
    for (int i = 0; i < stacked && !supports.empty(); ++i) {
      const std::size_t k = static_cast<std::size_t>(rng.below(static_cast<int>(supports.size())));
      const Object s = objects[supports[k]];
      supports.erase(supports.begin() + static_cast<long>(k));
      const float top = s.shape == Shape::Box ? s.base.y + s.size * 0.8f : s.size * 1.6f;
      const Shape shape = rng.unit() < 0.5f ? Shape::Sphere : Shape::Box;
      const float size = s.size * rng.range(0.4f, 0.6f);
      const float lift = top + (shape == Shape::Box ? size * 0.8f : size);
      objects.push_back({shape,
                         {s.base.x, lift, s.base.z},
                         size * 1.3f,
                         size,
                         {s.base.x, lift, s.base.z},
                         rng.range(0.0f, 2.0f * kPi)});
    }
  }
  // Hanging objects on a jittered 3D grid in the upper part of the room.
  {
    const float low = 2.6f, high = H - 0.6f;
    const float cell = std::cbrt(W * D * (high - low) / static_cast<float>(hanging) * 0.8f);
    const int cols = std::max(1, static_cast<int>(std::ceil(W / cell)));
    const int rows = std::max(1, static_cast<int>(std::ceil(D / cell)));
    const int layers = std::max(1, static_cast<int>(std::ceil((high - low) / cell)));
    std::vector<int> cells(static_cast<std::size_t>(cols * rows * layers));
    for (std::size_t i = 0; i < cells.size(); ++i) cells[i] = static_cast<int>(i);
    for (std::size_t i = cells.size() - 1; i > 0; --i)
      std::swap(cells[i], cells[static_cast<std::size_t>(rng.below(static_cast<int>(i) + 1))]);
    const float cw = W / static_cast<float>(cols), cd = D / static_cast<float>(rows);
    const float ch = (high - low) / static_cast<float>(layers);
    int placed = 0;
    for (int c : cells) {
      if (placed >= hanging) break;
      const float m = std::min({cw, cd, ch});
      const Shape shape = randomShape();
      const float size =
          0.45f * m * rng.range(0.5f, 0.85f) / (shape == Shape::Cylinder ? 1.3f : 1.0f);
      const glm::vec3 at{
          -kHalfW + cw * (static_cast<float>(c % cols) + rng.range(0.35f, 0.65f)),
          low + ch * (static_cast<float>(c / (cols * rows)) + rng.range(0.35f, 0.65f)),
          -kHalfD + cd * (static_cast<float>((c / cols) % rows) + rng.range(0.35f, 0.65f))};
      if (glm::length(at - eye) < 1.5f + size) continue;
      const glm::vec3 base = shape == Shape::Cylinder ? at - glm::vec3(0, size * 0.8f, 0) : at;
      objects.push_back({shape, at, size * 1.3f, size, base, rng.range(0.0f, 2.0f * kPi)});
      ++placed;
    }
  }

  // Triangles: what the room used, the rest shared out among the objects, each taking its share
  // of what is left so the total lands close to the target.
  long remaining = std::max(0L, o.triangles - triangles);
  for (std::size_t i = 0; i < objects.size(); ++i) {
    const Object& obj = objects[i];
    const long share = remaining / static_cast<long>(objects.size() - i);
    MeshData m;
    if (obj.yaw < 0.0f) {  // pillar
      const int stacks =
          std::clamp(static_cast<int>(std::sqrt(static_cast<double>(share) / 4.0)), 1, 60);
      m = cylinder(obj.size, H, std::max(6, 2 * stacks), stacks);
    } else {
      m = shapeMesh(obj.shape, obj.size, share);
    }
    const long made = static_cast<long>(triangleCount(m));
    remaining = std::max(0L, remaining - made);
    triangles += made;
    Transform t;
    t.translation = obj.base;
    if (obj.yaw >= 0.0f) {
      t.rotation = glm::angleAxis(obj.yaw, glm::vec3(0, 1, 0));
      if (obj.shape == Shape::Torus && obj.base.y > 2.0f)  // hanging rings: tilted
        t.rotation = t.rotation * glm::angleAxis(obj.yaw * 0.5f, glm::vec3(1, 0, 0));
    }
    const std::string name = "object" + std::to_string(i);
    const int material =
        palette[static_cast<std::size_t>(rng.below(static_cast<int>(palette.size())))];
    b.addNode(name, t, b.addMesh(m, primitive(m, material), name));
  }

  // Lights: best-candidate sampling (the candidate farthest from the lights placed so far, out
  // of 16) in the room at heights 0.5..H-0.4, never inside an object.
  std::vector<glm::vec3> lights;
  for (int l = 0; l < o.lights; ++l) {
    glm::vec3 best{0.0f};
    float bestDistance = -1.0f;
    for (int candidate = 0, tries = 0; candidate < 16 && tries < 10000; ++tries) {
      const glm::vec3 p{rng.range(-kHalfW + 0.4f, kHalfW - 0.4f), rng.range(0.5f, H - 0.4f),
                        rng.range(-kHalfD + 0.4f, kHalfD - 0.4f)};
      bool inside = false;
      for (const Object& obj : objects) {
        const bool pillar = obj.yaw < 0.0f;
        const float distance = pillar
                                   ? glm::length(glm::vec2(p.x - obj.center.x, p.z - obj.center.z))
                                   : glm::length(p - obj.center);
        if (distance < (pillar ? obj.size : obj.radius) + 0.15f) {
          inside = true;
          break;
        }
      }
      if (inside) continue;
      ++candidate;
      float nearest = 1e30f;
      for (const glm::vec3& q : lights) nearest = std::min(nearest, glm::length(p - q));
      if (nearest > bestDistance) {
        bestDistance = nearest;
        best = p;
      }
    }
    if (bestDistance < 0.0f) throw std::runtime_error("no room left for a light");
    lights.push_back(best);
  }

  // Range: "auto" makes about K lights (--lights-per-point) reach a typical point: the median,
  // over 4096 random points of the room, of the distance to the K-th nearest light. With K or
  // fewer lights every light reaches everything, so none gets a range.
  std::vector<glm::vec3> samples;
  for (int i = 0; i < 4096; ++i)
    samples.push_back({rng.range(-kHalfW, kHalfW), rng.range(0.0f, H), rng.range(-kHalfD, kHalfD)});
  float range = 0.0f;
  if (o.range == "auto") {
    if (o.lights > o.lightsPerPoint) {
      std::vector<float> kth;
      std::vector<float> d(lights.size());
      for (const glm::vec3& s : samples) {
        for (std::size_t i = 0; i < lights.size(); ++i) d[i] = glm::length(s - lights[i]);
        std::nth_element(d.begin(), d.begin() + (o.lightsPerPoint - 1), d.end());
        kth.push_back(d[static_cast<std::size_t>(o.lightsPerPoint - 1)]);
      }
      std::nth_element(kth.begin(), kth.begin() + static_cast<long>(kth.size() / 2), kth.end());
      range = kth[kth.size() / 2];
    }
  } else if (o.range != "none") {
    range = std::stof(o.range);
  }
  double reach = 0.0;  // mean number of lights within range of a sample point
  for (const glm::vec3& s : samples)
    for (const glm::vec3& q : lights)
      if (range <= 0.0f || glm::length(s - q) < range) reach += 1.0;
  reach /= static_cast<double>(samples.size());
  // Intensity: the same for every light, so that the median illuminance over the samples is
  // about 2 lux whatever the number of lights (the images stay comparable).
  std::vector<float> illuminance;
  for (const glm::vec3& s : samples) {
    float e = 0.0f;
    for (const glm::vec3& q : lights) e += windowedFalloff(glm::length(s - q), range);
    illuminance.push_back(e);
  }
  std::nth_element(illuminance.begin(), illuminance.begin() + 2048, illuminance.end());
  const float intensity = 2.0f / std::max(illuminance[2048], 1e-6f);

  b.write(o.output, FileFormat::GltfExternal);

  std::filesystem::path lightsPath = o.output;
  lightsPath.replace_extension(".lights.json");
  std::ofstream out(lightsPath);
  char line[512];
  out << "{\n  \"ambient\": [0.02, 0.02, 0.02],\n  \"lights\": [\n";
  for (std::size_t i = 0; i < lights.size(); ++i) {
    const float warm = rng.unit();  // from cool white to warm white
    const glm::vec3 color =
        glm::mix(glm::vec3(0.75f, 0.85f, 1.0f), glm::vec3(1.0f, 0.85f, 0.7f), warm);
    const glm::vec3& p = lights[i];
    std::string rangeField;
    if (range > 0.0f) {
      char text[48];
      std::snprintf(text, sizeof text, ", \"range\": %.4g", static_cast<double>(range));
      rangeField = text;
    }
    std::snprintf(line, sizeof line,
                  "    {\"name\": \"l%zu\", \"type\": \"point\", \"position\": [%.4f, %.4f, %.4f], "
                  "\"color\": [%.3f, %.3f, %.3f], \"intensity\": %.5g%s, "
                  "\"shadow\": {\"resolution\": %d}}%s\n",
                  i, static_cast<double>(p.x), static_cast<double>(p.y), static_cast<double>(p.z),
                  static_cast<double>(color.r), static_cast<double>(color.g),
                  static_cast<double>(color.b), static_cast<double>(intensity), rangeField.c_str(),
                  o.resolution, i + 1 < lights.size() ? "," : "");
    out << line;
  }
  out << "  ]\n}\n";
  out.close();
  if (!out) throw std::runtime_error("cannot write " + lightsPath.string());

  std::printf(
      "%s: %ld triangles, %zu objects, %zu lights at %d^2, range %s, "
      "%.1f lights reach a point on average, seed %u\n",
      o.output.string().c_str(), triangles, objects.size() + 6, lights.size(), o.resolution,
      range > 0.0f ? (std::to_string(range) + " m").c_str() : "none", reach, o.seed);
}

}  // namespace

int main(int argc, char** argv) {
  const Options options = parseOptions(argc, argv);
  return runGenerator(argc, argv, 0, argc, "make_shadow_bench_scene OUT.gltf [OPTIONS]",
                      [&](char**) { run(options); });
}
