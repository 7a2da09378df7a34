#include "renderer/output/depth_dump.h"

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfEnvmap.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfOutputFile.h>
#include <OpenEXR/ImfStandardAttributes.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <exception>
#include <stdexcept>
#include <string>
#include <vector>

#include "renderer/core/errors.h"
#include "renderer/output/exr_memory_stream.h"
#include "renderer/output/image_writer.h"
#include "renderer/output/output_transaction.h"

namespace omnishadow {
namespace {

namespace fs = std::filesystem;

std::size_t texelCount(int resolution) {
  return static_cast<std::size_t>(resolution) * static_cast<std::size_t>(resolution);
}

void validate(const CubeDistances& distances, float far) {
  if (distances.resolution <= 0)
    throw std::invalid_argument("writePointShadowDump: empty cube map");
  for (const std::vector<float>& face : distances.faces)
    if (face.size() != texelCount(distances.resolution))
      throw std::invalid_argument("writePointShadowDump: face size does not match resolution");
  if (!(far > 0.0f) || !std::isfinite(far))
    throw std::invalid_argument("writePointShadowDump: far must be positive and finite");
}

// Nearest texel: the texel whose square contains (s, t). s = 1 exactly belongs to the last one.
float sample(const CubeDistances& distances, const glm::vec3& direction) {
  const CubeLookup hit = cubeLookup(direction);
  const int n = distances.resolution;
  auto texel = [n](float coordinate) {
    return std::clamp(static_cast<int>(std::floor(coordinate * static_cast<float>(n))), 0, n - 1);
  };
  return distances.at(hit.face, texel(hit.st.x), texel(hit.st.y));
}

// Preview grey: distance / far, nearer = darker. +inf (nothing rendered) clamps to white; NaN
// should not occur, but is shown as nothing rendered rather than left to an undefined cast.
std::uint8_t grey(float distance, float far) {
  if (std::isnan(distance)) return 255;
  const float ratio = std::clamp(distance / far, 0.0f, 1.0f);
  return static_cast<std::uint8_t>(std::lround(255.0f * ratio));
}

void writeFace(const fs::path& folder, const std::string& lightName, int face,
               const CubeDistances& distances, float far, OutputTransaction& transaction) {
  const int n = distances.resolution;
  const std::vector<float>& texels = distances.faces[face];
  const std::string base = lightName + "_" + kCubeFaceNames[face];
  // The stored rows are already GL texel rows (row 0 = t 0), which is the documented file layout.
  writeExr(transaction.stage(folder / (base + ".exr")),
           FloatImage{n, n, {"Z"}, FloatPixels(texels.begin(), texels.end())}, ExrPixelType::Float);
  std::vector<std::uint8_t> preview(texels.size());
  std::transform(texels.begin(), texels.end(), preview.begin(),
                 [far](float distance) { return grey(distance, far); });
  writePng(transaction.stage(folder / (base + ".png")), n, n, 1, preview);
}

}  // namespace

void writePlanarShadowDump(const fs::path& folder, const std::string& base, int resolution,
                           const std::vector<float>& distances, float far,
                           OutputTransaction& transaction) {
  writeExr(
      transaction.stage(folder / (base + ".exr")),
      FloatImage{resolution, resolution, {"Z"}, FloatPixels(distances.begin(), distances.end())},
      ExrPixelType::Float);
  std::vector<std::uint8_t> preview(distances.size());
  std::transform(distances.begin(), distances.end(), preview.begin(),
                 [far](float distance) { return grey(distance, far); });
  writePng(transaction.stage(folder / (base + ".png")), resolution, resolution, 1, preview);
}

namespace {

// Every pixel of an OpenEXR cube map (faces +X -X +Y -Y +Z -Z stacked vertically, each in
// OpenEXR's orientation), filled with the texel that GL sampling finds in the pixel's direction.
std::vector<float> openExrCubePixels(const CubeDistances& distances) {
  const int n = distances.resolution;
  const Imath::Box2i dataWindow(Imath::V2i(0, 0), Imath::V2i(n - 1, 6 * n - 1));
  // OpenEXR's direction() spreads face positions 0..n-1 over -1..1, i.e. it puts the first and
  // last pixel centres on the cube's edges. Nearest sampling there would hit edge ties (the X
  // face wins them in cubeLookup) and duplicate some texels while dropping others. We ask for
  // the centre of cell p of an n-cell grid instead: same faces and orientation, and every
  // pixel then lands on exactly one GL texel centre, so the cube is a permutation of the texels.
  const float scale = n > 1 ? static_cast<float>(n - 1) / static_cast<float>(n) : 0.0f;
  auto cellCentre = [scale](int p) { return (static_cast<float>(p) + 0.5f) * scale; };
  std::vector<float> pixels(6 * texelCount(n));
  for (int f = 0; f < kCubeFaceCount; ++f) {
    const auto face = static_cast<Imf::CubeMapFace>(f);
    for (int y = 0; y < n; ++y) {
      for (int x = 0; x < n; ++x) {
        // pixelPosition() maps integer face positions to integer pixels (flips and offsets).
        const Imath::V2f pixel = Imf::CubeMap::pixelPosition(
            face, dataWindow, Imath::V2f(static_cast<float>(x), static_cast<float>(y)));
        const Imath::V3f direction =
            Imf::CubeMap::direction(face, dataWindow, Imath::V2f(cellCentre(x), cellCentre(y)));
        const auto index = static_cast<std::size_t>(std::lround(pixel.y)) * n +
                           static_cast<std::size_t>(std::lround(pixel.x));
        pixels[index] = sample(distances, glm::vec3(direction.x, direction.y, direction.z));
      }
    }
  }
  return pixels;
}

// Like writeExr, but with the envmap attribute that marks the image as a cube map. Same header
// policy: ZIP, no time stamps or other attributes, so identical pixels give identical files.
void writeCubeExr(const fs::path& path, int faceSize, const std::vector<float>& pixels) {
  std::string encoded;
  try {
    Imf::Header header(faceSize, 6 * faceSize);
    header.compression() = Imf::ZIP_COMPRESSION;
    header.channels().insert("Z", Imf::Channel(Imf::FLOAT));
    Imf::addEnvmap(header, Imf::ENVMAP_CUBE);
    Imf::FrameBuffer frameBuffer;
    // OpenEXR's Slice takes a non-const pointer for both reading and writing.
    char* base = reinterpret_cast<char*>(const_cast<float*>(pixels.data()));
    frameBuffer.insert("Z", Imf::Slice(Imf::FLOAT, base, sizeof(float),
                                       sizeof(float) * static_cast<std::size_t>(faceSize)));
    ExrMemoryStream stream(OutputTransaction::finalPathOf(path).string());
    {
      Imf::OutputFile file(stream, header);
      file.setFrameBuffer(frameBuffer);
      file.writePixels(6 * faceSize);
    }  // the destructor completes the file (the line offset table)
    encoded = stream.bytes();
  } catch (const std::exception& error) {
    // Iex exceptions derive from std::exception; callers only know RenderError.
    throw RenderError("cannot write " + OutputTransaction::finalPathOf(path).string() + ": " +
                      error.what());
  }
  writeFileBytes(path, encoded);
}

// One cell of the 4x3 cross: what a viewer at the light sees looking along `forward` with
// `up` at the top of the cell. Right = cross(forward, up), so the middle row turns right from
// +X to +Z to -X to -Z, and the +Y / -Y cells share their edges with the +Z cell.
struct CrossCell {
  int column, row;
  glm::vec3 forward, up;
};
const CrossCell kCrossCells[] = {
    {0, 1, {1, 0, 0}, {0, 1, 0}},  {1, 1, {0, 0, 1}, {0, 1, 0}},  {2, 1, {-1, 0, 0}, {0, 1, 0}},
    {3, 1, {0, 0, -1}, {0, 1, 0}}, {1, 0, {0, 1, 0}, {0, 0, -1}}, {1, 2, {0, -1, 0}, {0, 0, 1}},
};

std::vector<std::uint8_t> crossPixels(const CubeDistances& distances, float far) {
  const int n = distances.resolution;
  const int width = 4 * n;
  std::vector<std::uint8_t> pixels(12 * texelCount(n), 0);  // unused cells stay black
  // Pixel centre p of n across a face, as -1..1 along the face's right or up axis.
  auto offset = [n](int p) {
    return 2.0f * (static_cast<float>(p) + 0.5f) / static_cast<float>(n) - 1.0f;
  };
  for (const CrossCell& cell : kCrossCells) {
    const glm::vec3 right = glm::cross(cell.forward, cell.up);
    for (int j = 0; j < n; ++j) {
      for (int i = 0; i < n; ++i) {
        const glm::vec3 direction = cell.forward + offset(i) * right - offset(j) * cell.up;
        const std::size_t index =
            static_cast<std::size_t>(cell.row * n + j) * width + (cell.column * n + i);
        pixels[index] = grey(sample(distances, direction), far);
      }
    }
  }
  return pixels;
}

}  // namespace

void writePointShadowDump(const fs::path& folder, const std::string& lightName,
                          const CubeDistances& distances, float far,
                          OutputTransaction& transaction) {
  validate(distances, far);
  for (int face = 0; face < kCubeFaceCount; ++face)
    writeFace(folder, lightName, face, distances, far, transaction);
  writeCubeExr(transaction.stage(folder / (lightName + "_cube.exr")), distances.resolution,
               openExrCubePixels(distances));
  const int n = distances.resolution;
  writePng(transaction.stage(folder / (lightName + "_cross.png")), 4 * n, 3 * n, 1,
           crossPixels(distances, far));
}

std::string fileSafeName(const std::string& name) {
  std::string safe = name;
  for (char& c : safe) {
    // Explicit ASCII ranges: std::isalnum depends on the locale and on char signedness.
    const bool keep = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
                      c == '-' || c == '_' || c == '.';
    if (!keep) c = '_';
  }
  return safe.empty() ? "light" : safe;
}

}  // namespace omnishadow
