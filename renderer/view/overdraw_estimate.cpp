#include "renderer/view/overdraw_estimate.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>

namespace omnishadow {

namespace {

// A polygon clipped from a triangle by two planes has at most five corners.
constexpr int kMaxClipped = 5;
using Polygon = std::array<glm::vec4, kMaxClipped + 1>;

// Keeps the part of `in` where `distance` is at least 0 (Sutherland-Hodgman, one plane).
template <typename Distance>
int clipPolygon(const Polygon& in, int count, Polygon& out, Distance distance) {
  int kept = 0;
  for (int i = 0; i < count; ++i) {
    const glm::vec4& a = in[static_cast<std::size_t>(i)];
    const glm::vec4& b = in[static_cast<std::size_t>((i + 1) % count)];
    const float da = distance(a), db = distance(b);
    if (da >= 0.0f) out[static_cast<std::size_t>(kept++)] = a;
    if ((da >= 0.0f) != (db >= 0.0f))
      out[static_cast<std::size_t>(kept++)] = a + (b - a) * (da / (da - db));
  }
  return kept;
}

// The depth buffer at the sample points, and the fragments that passed its test.
class SampleGrid {
 public:
  SampleGrid(int width, int height, int step)
      : width_(width),
        height_(height),
        columns_(std::max(1, width / std::max(1, step))),
        rows_(std::max(1, height / std::max(1, step))),
        spacingX_(static_cast<float>(width) / static_cast<float>(columns_)),
        spacingY_(static_cast<float>(height) / static_cast<float>(rows_)),
        depth_(static_cast<std::size_t>(columns_) * static_cast<std::size_t>(rows_), 0.0f),
        covered_(depth_.size(), 0) {}

  // A triangle in window coordinates (x, y in pixels, y up; z the depth).
  void triangle(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c, bool cullBack,
                bool mirrored) {
    glm::vec3 p[3] = {a, b, c};
    const float area = edge(p[0], p[1], p[2]);
    if (area == 0.0f || !std::isfinite(area)) return;
    // Counter-clockwise in window coordinates (y up) is front-facing, clockwise where mirrored.
    if (cullBack && ((area > 0.0f) == mirrored)) return;
    if (area < 0.0f) std::swap(p[1], p[2]);
    const float twiceArea = std::abs(area);
    // The samples whose centres lie in [low, high], clamped before they become ints: a
    // triangle may reach far beyond the frame.
    const auto span = [](float low, float high, float spacing, int count) {
      const float first =
          std::clamp(std::ceil(low / spacing - 0.5f), 0.0f, static_cast<float>(count));
      const float last =
          std::clamp(std::floor(high / spacing - 0.5f), -1.0f, static_cast<float>(count - 1));
      return std::pair{static_cast<int>(first), static_cast<int>(last)};
    };
    const auto [x0, x1] = span(std::min({p[0].x, p[1].x, p[2].x}),
                               std::max({p[0].x, p[1].x, p[2].x}), spacingX_, columns_);
    const auto [y0, y1] = span(std::min({p[0].y, p[1].y, p[2].y}),
                               std::max({p[0].y, p[1].y, p[2].y}), spacingY_, rows_);
    for (int y = y0; y <= y1; ++y) {
      for (int x = x0; x <= x1; ++x) {
        const glm::vec3 s{(static_cast<float>(x) + 0.5f) * spacingX_,
                          (static_cast<float>(y) + 0.5f) * spacingY_, 0.0f};
        const float w0 = edge(p[1], p[2], s), w1 = edge(p[2], p[0], s), w2 = edge(p[0], p[1], s);
        if (w0 < 0.0f || w1 < 0.0f || w2 < 0.0f) continue;
        // From the first corner, so that a plane of one depth interpolates to exactly it.
        const float depth = p[0].z + (w1 * (p[1].z - p[0].z) + w2 * (p[2].z - p[0].z)) / twiceArea;
        const std::size_t i = static_cast<std::size_t>(y) * static_cast<std::size_t>(columns_) +
                              static_cast<std::size_t>(x);
        if (covered_[i] && depth <= depth_[i]) continue;  // GL_GREATER, reversed depth
        covered_[i] = 1;
        depth_[i] = depth;
        ++passed_;
      }
    }
  }

  OverdrawCounts counts(std::uint64_t triangles) const {
    const double pixelsPerSample = static_cast<double>(width_) * static_cast<double>(height_) /
                                   static_cast<double>(depth_.size());
    const auto covered =
        static_cast<std::uint64_t>(std::count(covered_.begin(), covered_.end(), 1));
    return {
        static_cast<std::uint64_t>(std::llround(static_cast<double>(passed_) * pixelsPerSample)),
        static_cast<std::uint64_t>(std::llround(static_cast<double>(covered) * pixelsPerSample)),
        triangles};
  }

  glm::vec3 window(const glm::vec4& clip) const {
    const glm::vec3 ndc = glm::vec3(clip) / clip.w;
    return {(ndc.x * 0.5f + 0.5f) * static_cast<float>(width_),
            (ndc.y * 0.5f + 0.5f) * static_cast<float>(height_), ndc.z};
  }

 private:
  // Twice the signed area of (a, b, c) in window x, y: positive when counter-clockwise.
  static float edge(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c) {
    return (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
  }

  int width_, height_, columns_, rows_;
  float spacingX_, spacingY_;
  std::vector<float> depth_;
  std::vector<std::uint8_t> covered_;
  std::uint64_t passed_ = 0;
};

}  // namespace

OverdrawCounts estimateOverdraw(const std::vector<OverdrawSurface>& inDrawOrder,
                                const glm::mat4& viewProjection, int width, int height,
                                int maxSamples) {
  const double pixelsPerSample =
      static_cast<double>(width) * height / static_cast<double>(std::max(maxSamples, 1));
  SampleGrid grid(width, height,
                  std::max(1, static_cast<int>(std::ceil(std::sqrt(pixelsPerSample)))));
  std::uint64_t triangles = 0;
  // Each vertex once: its clip-space position, its window position when inside the near and
  // far planes, and the sides of the view it lies beyond.
  enum : std::uint8_t { kLeft = 1, kRight = 2, kBottom = 4, kTop = 8, kNear = 16, kFar = 32 };
  std::vector<glm::vec4> clip;
  std::vector<glm::vec3> window;
  std::vector<std::uint8_t> beyond;
  // Reversed depth with GL_ZERO_TO_ONE: the near plane is z = w, the far plane z = 0.
  const auto nearDistance = [](const glm::vec4& v) { return v.w - v.z; };
  const auto farDistance = [](const glm::vec4& v) { return v.z; };
  for (const OverdrawSurface& surface : inDrawOrder) {
    const Mesh& mesh = *surface.mesh;
    triangles += mesh.indices.size() / 3;
    const glm::mat4 toClip = viewProjection * surface.world;
    const std::size_t vertices = mesh.positions.size();
    clip.resize(vertices);
    window.resize(vertices);
    beyond.resize(vertices);
    for (std::size_t i = 0; i < vertices; ++i) {
      const glm::vec4 v = toClip * glm::vec4(mesh.positions[i], 1.0f);
      clip[i] = v;
      std::uint8_t sides = 0;
      if (v.x < -v.w) sides |= kLeft;
      if (v.x > v.w) sides |= kRight;
      if (v.y < -v.w) sides |= kBottom;
      if (v.y > v.w) sides |= kTop;
      if (!(nearDistance(v) >= 0.0f && v.w > 0.0f)) sides |= kNear;
      if (!(farDistance(v) >= 0.0f)) sides |= kFar;
      beyond[i] = sides;
      if (!(sides & (kNear | kFar))) window[i] = grid.window(v);
    }
    for (std::size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
      const std::uint32_t a = mesh.indices[t], b = mesh.indices[t + 1], c = mesh.indices[t + 2];
      if (beyond[a] & beyond[b] & beyond[c]) continue;  // wholly beyond one side of the view
      if (!((beyond[a] | beyond[b] | beyond[c]) & (kNear | kFar))) {
        grid.triangle(window[a], window[b], window[c], surface.cullBackFaces, surface.mirrored);
        continue;
      }
      Polygon corners{clip[a], clip[b], clip[c]}, nearClipped, clipped;
      const int nearCount = clipPolygon(corners, 3, nearClipped, nearDistance);
      const int count = clipPolygon(nearClipped, nearCount, clipped, farDistance);
      for (int i = 1; i + 1 < count; ++i) {
        const glm::vec4& p = clipped[0];
        const glm::vec4& q = clipped[static_cast<std::size_t>(i)];
        const glm::vec4& r = clipped[static_cast<std::size_t>(i) + 1];
        if (p.w > 0.0f && q.w > 0.0f && r.w > 0.0f)
          grid.triangle(grid.window(p), grid.window(q), grid.window(r), surface.cullBackFaces,
                        surface.mirrored);
      }
    }
  }
  return grid.counts(triangles);
}

}  // namespace omnishadow
