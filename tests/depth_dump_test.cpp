#include "renderer/output/depth_dump.h"

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfEnvmap.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfInputFile.h>
#include <OpenEXR/ImfStandardAttributes.h>
#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include "renderer/view/cube_faces.h"
#include "tests/support/temp_folder.h"

namespace omnishadow::depth_dump_test {
namespace {

namespace fs = std::filesystem;

constexpr float kInf = std::numeric_limits<float>::infinity();

// A fresh folder per test, removed afterwards even when the test fails.
struct TempDir : test_support::TempFolder {
  TempDir() : TempFolder("omnishadow-depth-dump") {}
};

CubeFace faceAt(int face) {
  return static_cast<CubeFace>(face);
}

// Each texel holds a value that names it: face * 1000 + row * n + column + 1 (exact in float
// for n < 31), so a value read back from any file says where it came from.
float code(int face, int column, int row, int n) {
  return static_cast<float>(face * 1000 + row * n + column + 1);
}

// An n x n cube whose texels hold value(face, column, row, n).
template <typename Value>
CubeDistances cubeOf(int n, Value value) {
  CubeDistances cube;
  cube.resolution = n;
  for (int face = 0; face < kCubeFaceCount; ++face)
    for (int row = 0; row < n; ++row)
      for (int column = 0; column < n; ++column)
        cube.faces[face].push_back(static_cast<float>(value(face, column, row, n)));
  return cube;
}

CubeDistances encodedCube(int n) {
  return cubeOf(n, code);
}

// For the 8-bit files: texel index + 1 (1..6n^2 <= 150 for n = 5) with far = 255 turns into
// exactly that grey level, so a PNG pixel still names its source texel.
constexpr float kIndexFar = 255.0f;
int greyCode(int face, int column, int row, int n) {
  return face * n * n + row * n + column + 1;
}

CubeDistances greyCodedCube(int n) {
  return cubeOf(n, greyCode);
}

std::string faceFile(const std::string& light, int face, const std::string& extension) {
  return light + "_" + kCubeFaceNames[face] + extension;
}

std::set<std::string> folderNames(const fs::path& folder) {
  std::set<std::string> names;
  for (const auto& entry : fs::directory_iterator(folder))
    names.insert(entry.path().filename().string());
  return names;
}

std::vector<char> fileBytes(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void dump(const fs::path& folder, const std::string& light, const CubeDistances& cube, float far) {
  OutputTransaction transaction;
  writePointShadowDump(folder, light, cube, far, transaction);
  transaction.commit();
}

struct Exr {
  Imath::Box2i dataWindow;
  std::vector<std::string> channels;
  std::vector<Imf::PixelType> types;
  Imf::Compression compression;
  bool hasEnvmap = false;
  Imf::Envmap envmap = Imf::NUM_ENVMAPTYPES;
  int width = 0, height = 0;
  std::vector<float> z;  // row-major, first row = data window min.y
  float at(int x, int y) const { return z[static_cast<std::size_t>(y) * width + x]; }
};

Exr readExr(const fs::path& path) {
  Imf::InputFile file(path.string().c_str());
  const Imf::Header& header = file.header();
  Exr exr;
  exr.dataWindow = header.dataWindow();
  for (auto it = header.channels().begin(); it != header.channels().end(); ++it) {
    exr.channels.push_back(it.name());
    exr.types.push_back(it.channel().type);
  }
  exr.compression = header.compression();
  exr.hasEnvmap = Imf::hasEnvmap(header);
  if (exr.hasEnvmap) exr.envmap = Imf::envmapAttribute(header).value();
  exr.width = exr.dataWindow.max.x - exr.dataWindow.min.x + 1;
  exr.height = exr.dataWindow.max.y - exr.dataWindow.min.y + 1;
  exr.z.resize(static_cast<std::size_t>(exr.width) * exr.height);
  if (exr.dataWindow.min != Imath::V2i(0, 0)) return exr;  // callers check the window first
  Imf::FrameBuffer frameBuffer;
  frameBuffer.insert("Z", Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(exr.z.data()),
                                     sizeof(float), sizeof(float) * exr.width));
  file.setFrameBuffer(frameBuffer);
  file.readPixels(exr.dataWindow.min.y, exr.dataWindow.max.y);
  return exr;
}

struct Png {
  int width = 0, height = 0, channels = 0;
  OIIO::TypeDesc format;
  std::vector<std::uint8_t> pixels;
  int at(int x, int y) const { return pixels[static_cast<std::size_t>(y) * width + x]; }
};

Png readPng(const fs::path& path) {
  auto input = OIIO::ImageInput::open(path.string());
  if (!input) throw std::runtime_error("cannot open " + path.string());
  const OIIO::ImageSpec& spec = input->spec();
  Png png{spec.width, spec.height, spec.nchannels, spec.format, {}};
  png.pixels.resize(static_cast<std::size_t>(png.width) * png.height * png.channels);
  if (!input->read_image(0, 0, 0, png.channels, OIIO::TypeDesc::UINT8, png.pixels.data()))
    throw std::runtime_error("cannot read " + path.string());
  return png;
}

// ---------------------------------------------------------------------------------------------
// File set and transaction

TEST(DepthDump, WritesExactlyTheDocumentedFilesAndOnlyOnCommit) {
  TempDir dir;
  const std::string light = fileSafeName("my lamp/1");
  ASSERT_EQ(light, "my_lamp_1");
  std::set<std::string> expected = {light + "_cube.exr", light + "_cross.png"};
  for (int face = 0; face < kCubeFaceCount; ++face) {
    expected.insert(faceFile(light, face, ".exr"));
    expected.insert(faceFile(light, face, ".png"));
  }
  ASSERT_EQ(expected.size(), 14u);

  OutputTransaction transaction;
  writePointShadowDump(dir.path(), light, encodedCube(4), 10.0f, transaction);
  // Before commit only the transaction's hidden temporaries exist.
  for (const std::string& name : folderNames(dir.path()))
    EXPECT_EQ(name.front(), '.') << name << " appeared before commit";
  transaction.commit();
  EXPECT_EQ(folderNames(dir.path()), expected);
}

TEST(DepthDump, NothingAppearsWithoutCommit) {
  TempDir dir;
  {
    OutputTransaction transaction;
    writePointShadowDump(dir.path(), "lamp", encodedCube(4), 10.0f, transaction);
  }
  EXPECT_TRUE(folderNames(dir.path()).empty());
}

TEST(DepthDump, RejectsInconsistentInput) {
  TempDir dir;
  OutputTransaction transaction;
  CubeDistances empty;
  EXPECT_THROW(writePointShadowDump(dir.path(), "l", empty, 1.0f, transaction),
               std::invalid_argument);
  CubeDistances ragged = encodedCube(4);
  ragged.faces[3].pop_back();
  EXPECT_THROW(writePointShadowDump(dir.path(), "l", ragged, 1.0f, transaction),
               std::invalid_argument);
  EXPECT_THROW(writePointShadowDump(dir.path(), "l", encodedCube(4), 0.0f, transaction),
               std::invalid_argument);
  EXPECT_THROW(writePointShadowDump(dir.path(), "l", encodedCube(4), kInf, transaction),
               std::invalid_argument);
  EXPECT_TRUE(folderNames(dir.path()).empty());
}

// ---------------------------------------------------------------------------------------------
// Per-face files

TEST(DepthDump, FaceExrsHoldTheDistancesInGlTexelLayout) {
  TempDir dir;
  const int n = 8;
  CubeDistances cube = encodedCube(n);
  cube.faces[2][0] = kInf;          // py, row 0, column 0
  cube.faces[5][n * n - 1] = kInf;  // nz, last texel
  dump(dir.path(), "lamp", cube, 100.0f);
  for (int face = 0; face < kCubeFaceCount; ++face) {
    SCOPED_TRACE(kCubeFaceNames[face]);
    const Exr exr = readExr(dir.path() / faceFile("lamp", face, ".exr"));
    EXPECT_EQ(exr.channels, std::vector<std::string>{"Z"});
    EXPECT_EQ(exr.types, std::vector<Imf::PixelType>{Imf::FLOAT});
    EXPECT_FALSE(exr.hasEnvmap);
    ASSERT_EQ(exr.dataWindow, Imath::Box2i(Imath::V2i(0, 0), Imath::V2i(n - 1, n - 1)));
    for (int row = 0; row < n; ++row)
      for (int column = 0; column < n; ++column)
        ASSERT_EQ(exr.at(column, row), cube.at(faceAt(face), column, row))
            << "column " << column << " row " << row;
  }
  // Spelled out, independent of CubeDistances::at: file row r, column c = code(face, c, r).
  const Exr px = readExr(dir.path() / "lamp_px.exr");
  EXPECT_EQ(px.at(3, 1), code(0, 3, 1, n));
  EXPECT_EQ(readExr(dir.path() / "lamp_py.exr").at(0, 0), kInf);
  EXPECT_EQ(readExr(dir.path() / "lamp_nz.exr").at(n - 1, n - 1), kInf);
}

TEST(DepthDump, FacePngPreviewsMapDistanceOverFarToGrey) {
  TempDir dir;
  const int n = 4;
  CubeDistances cube;
  cube.resolution = n;
  for (auto& face : cube.faces) face.assign(n * n, 5.0f);
  // far = 10: 0 -> black, far -> white, beyond far and +inf -> white, negative -> black,
  // and rounding to nearest (2.5 / 10 * 255 = 63.75 -> 64, 5 / 10 * 255 = 127.5 -> 128).
  cube.faces[4] = {0.0f, 2.5f,  5.0f, 10.0f, 20.0f, kInf, -1.0f, 1.0f,
                   9.9f, 0.02f, 0.0f, 0.0f,  0.0f,  0.0f, 0.0f,  7.5f};
  const std::vector<int> expected = {0, 64, 128, 255, 255, 255, 0, 26, 252, 1, 0, 0, 0, 0, 0, 191};
  dump(dir.path(), "lamp", cube, 10.0f);

  const Png pz = readPng(dir.path() / "lamp_pz.png");
  EXPECT_EQ(pz.width, n);
  EXPECT_EQ(pz.height, n);
  EXPECT_EQ(pz.channels, 1);
  EXPECT_EQ(pz.format, OIIO::TypeDesc::UINT8);
  for (int i = 0; i < n * n; ++i)
    EXPECT_EQ(pz.at(i % n, i / n), expected[i])
        << "texel " << i << " distance " << cube.faces[4][i];
  const Png nx = readPng(dir.path() / "lamp_nx.png");
  EXPECT_EQ(nx.channels, 1);
  EXPECT_TRUE(std::all_of(nx.pixels.begin(), nx.pixels.end(), [](int v) { return v == 128; }));
}

// ---------------------------------------------------------------------------------------------
// OpenEXR cube map

TEST(DepthDump, CubeExrIsAnOpenExrCubeMap) {
  TempDir dir;
  const int n = 8;
  dump(dir.path(), "lamp", encodedCube(n), 100.0f);
  const Exr cube = readExr(dir.path() / "lamp_cube.exr");
  EXPECT_TRUE(cube.hasEnvmap);
  EXPECT_EQ(cube.envmap, Imf::ENVMAP_CUBE);
  EXPECT_EQ(cube.dataWindow, Imath::Box2i(Imath::V2i(0, 0), Imath::V2i(n - 1, 6 * n - 1)));
  EXPECT_EQ(cube.channels, std::vector<std::string>{"Z"});
  EXPECT_EQ(cube.types, std::vector<Imf::PixelType>{Imf::FLOAT});
  EXPECT_EQ(cube.compression, Imf::ZIP_COMPRESSION);
}

// Both grids are n x n per face, so the cube map must use every texel exactly once.
class CubeExrPermutation : public ::testing::TestWithParam<int> {};

TEST_P(CubeExrPermutation, UsesEveryTexelExactlyOnce) {
  TempDir dir;
  const int n = GetParam();
  dump(dir.path(), "lamp", encodedCube(n), 100.0f);
  const Exr cube = readExr(dir.path() / "lamp_cube.exr");
  ASSERT_EQ(cube.z.size(), 6u * n * n);
  std::vector<int> uses(6 * 1000, 0);
  for (float value : cube.z) {
    const int index = static_cast<int>(value) - 1;
    ASSERT_TRUE(value >= 1 && index < 6000 && (index % 1000) < n * n) << value;
    ++uses[index];
  }
  for (int face = 0; face < kCubeFaceCount; ++face)
    for (int texel = 0; texel < n * n; ++texel)
      EXPECT_EQ(uses[face * 1000 + texel], 1)
          << kCubeFaceNames[face] << " column " << texel % n << " row " << texel / n;
}

INSTANTIATE_TEST_SUITE_P(Resolutions, CubeExrPermutation, ::testing::Values(1, 2, 3, 7, 8, 16));

// OpenEXR's own mapping, away from the face borders: there its direction() (which spreads
// pixels 0..n-1 edge to edge) and GL nearest sampling agree on the texel, so this checks the
// cube file against OpenEXR's functions without repeating the writer's centre correction.
TEST(DepthDump, CubeExrFollowsOpenExrDirectionsInsideEachFace) {
  TempDir dir;
  const int n = 8;
  const CubeDistances distances = encodedCube(n);
  dump(dir.path(), "lamp", distances, 100.0f);
  const Exr cube = readExr(dir.path() / "lamp_cube.exr");
  const Imath::Box2i dw = cube.dataWindow;
  for (int f = 0; f < kCubeFaceCount; ++f) {
    const auto face = static_cast<Imf::CubeMapFace>(f);
    for (int y = 1; y < n - 1; ++y) {
      for (int x = 1; x < n - 1; ++x) {
        const Imath::V2f inFace(static_cast<float>(x), static_cast<float>(y));
        const Imath::V2f pixel = Imf::CubeMap::pixelPosition(face, dw, inFace);
        const Imath::V3f d = Imf::CubeMap::direction(face, dw, inFace);
        const CubeLookup hit = cubeLookup(glm::vec3(d.x, d.y, d.z));
        ASSERT_EQ(static_cast<int>(hit.face), f);
        const int column = std::min(static_cast<int>(std::floor(hit.st.x * n)), n - 1);
        const int row = std::min(static_cast<int>(std::floor(hit.st.y * n)), n - 1);
        EXPECT_EQ(cube.at(static_cast<int>(pixel.x), static_cast<int>(pixel.y)),
                  distances.at(hit.face, column, row))
            << "face " << f << " position in face " << x << "," << y;
      }
    }
  }
}

// Facts read off the diagram in ImfEnvmap.h and GL's table (cube_faces.cpp), using neither
// OpenEXR's functions nor cubeLookup. OpenEXR stacks +X -X +Y -Y +Z -Z (the GL order) from the
// top. Per face, the image axes are (right, down): +X (+Z, -Y), -X (-Z, -Y), +Y (+X, -Z),
// -Y (+X, +Z), +Z (-X, -Y), -Z (+X, -Y). Against GL's (s, t) axes that makes every side face a
// left-right mirror of the GL face and the +Y / -Y faces an upside-down copy.
TEST(DepthDump, CubeExrFaceOrderAndOrientationMatchImfEnvmapDiagram) {
  TempDir dir;
  const int n = 7;  // odd: the centre pixel looks exactly along the axis
  const int last = n - 1, mid = n / 2;
  dump(dir.path(), "lamp", encodedCube(n), 100.0f);
  const Exr cube = readExr(dir.path() / "lamp_cube.exr");
  struct Corner {
    int x, y;         // pixel within OpenEXR's face region
    int column, row;  // GL texel of the same face
  };
  struct Expected {
    Corner topLeft, topRight, bottomLeft;
  };
  const Expected expected[kCubeFaceCount] = {
      {{0, 0, last, 0}, {last, 0, 0, 0}, {0, last, last, last}},  // +X
      {{0, 0, last, 0}, {last, 0, 0, 0}, {0, last, last, last}},  // -X
      {{0, 0, 0, last}, {last, 0, last, last}, {0, last, 0, 0}},  // +Y
      {{0, 0, 0, last}, {last, 0, last, last}, {0, last, 0, 0}},  // -Y
      {{0, 0, last, 0}, {last, 0, 0, 0}, {0, last, last, last}},  // +Z
      {{0, 0, last, 0}, {last, 0, 0, 0}, {0, last, last, last}},  // -Z
  };
  for (int face = 0; face < kCubeFaceCount; ++face) {
    SCOPED_TRACE(kCubeFaceNames[face]);
    const int top = face * n;
    EXPECT_EQ(cube.at(mid, top + mid), code(face, mid, mid, n)) << "centre";
    for (const Corner& c :
         {expected[face].topLeft, expected[face].topRight, expected[face].bottomLeft})
      EXPECT_EQ(cube.at(c.x, top + c.y), code(face, c.column, c.row, n))
          << "pixel " << c.x << "," << c.y;
  }
}

// ---------------------------------------------------------------------------------------------
// Cross

TEST(DepthDump, CrossUnfoldsTheCubeAroundAViewerWithYUp) {
  TempDir dir;
  const int n = 5, last = n - 1, mid = n / 2;
  CubeDistances distances = greyCodedCube(n);
  dump(dir.path(), "lamp", distances, kIndexFar);
  const Png cross = readPng(dir.path() / "lamp_cross.png");
  ASSERT_EQ(cross.width, 4 * n);
  ASSERT_EQ(cross.height, 3 * n);
  EXPECT_EQ(cross.channels, 1);
  EXPECT_EQ(cross.format, OIIO::TypeDesc::UINT8);
  auto cellPixel = [&](int cellColumn, int cellRow, int i, int j) {
    return cross.at(cellColumn * n + i, cellRow * n + j);
  };
  const int px = 0, nx = 1, py = 2, ny = 3, pz = 4, nz = 5;
  struct Cell {
    int column, row, face;
  };
  const Cell cells[] = {{0, 1, px}, {1, 1, pz}, {2, 1, nx}, {3, 1, nz}, {1, 0, py}, {1, 2, ny}};

  // Cell centres look straight along the face axis: the face's centre texel.
  for (const Cell& cell : cells)
    EXPECT_EQ(cellPixel(cell.column, cell.row, mid, mid), greyCode(cell.face, mid, mid, n))
        << kCubeFaceNames[cell.face];
  // Every pixel of a cell comes from that cell's face.
  for (const Cell& cell : cells)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i)
        EXPECT_EQ((cellPixel(cell.column, cell.row, i, j) - 1) / (n * n), cell.face)
            << kCubeFaceNames[cell.face] << " pixel " << i << "," << j;
  // Unused cells are black (every texel code is at least 1).
  for (auto [column, row] : {std::pair{0, 0}, {2, 0}, {3, 0}, {0, 2}, {2, 2}, {3, 2}})
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) ASSERT_EQ(cellPixel(column, row, i, j), 0);

  // Continuity across the middle row, including the wrap from -Z back to +X: a side face's
  // right edge is its GL column 0 and its left edge column n-1 (s runs against the viewer's
  // right on all four), and GL column 0 of one face borders column n-1 of the next one to
  // the right; rows (t = -y) line up.
  const int middle[] = {px, pz, nx, nz};
  for (int c = 0; c < 4; ++c) {
    const int next = (c + 1) % 4;
    for (int j = 0; j < n; ++j) {
      EXPECT_EQ(cellPixel(c, 1, last, j), greyCode(middle[c], 0, j, n));
      EXPECT_EQ(cellPixel(next, 1, 0, j), greyCode(middle[next], last, j, n));
    }
  }
  // The example from the layout: row centre of +Z's right edge and the first pixel of -X.
  EXPECT_EQ(cellPixel(1, 1, last, mid), greyCode(pz, 0, mid, n));
  EXPECT_EQ(cellPixel(2, 1, 0, mid), greyCode(nx, last, mid, n));
  // +Y above +Z: +Y's bottom row is its GL row n-1 (t = z = +1), +Z's top row its row 0
  // (t = -y = -1); both run along x = -(viewer's right), so columns run right to left.
  for (int i = 0; i < n; ++i) {
    EXPECT_EQ(cellPixel(1, 0, i, last), greyCode(py, last - i, last, n));
    EXPECT_EQ(cellPixel(1, 1, i, 0), greyCode(pz, last - i, 0, n));
    // -Y below +Z: +Z's bottom row is row n-1 (y = -1), -Y's top row its row 0 (t = -z = -1).
    EXPECT_EQ(cellPixel(1, 1, i, last), greyCode(pz, last - i, last, n));
    EXPECT_EQ(cellPixel(1, 2, i, 0), greyCode(ny, last - i, 0, n));
  }
}

TEST(DepthDump, CrossUsesThePreviewGreyScale) {
  TempDir dir;
  const int n = 5, mid = n / 2;
  CubeDistances distances = greyCodedCube(n);
  distances.faces[4][mid * n + mid] = kInf;     // pz centre: nothing rendered
  distances.faces[2][mid * n + mid] = 1000.0f;  // py centre: beyond far
  dump(dir.path(), "lamp", distances, kIndexFar);
  const Png cross = readPng(dir.path() / "lamp_cross.png");
  const Png pz = readPng(dir.path() / "lamp_pz.png");
  EXPECT_EQ(cross.at(n + mid, n + mid), 255);
  EXPECT_EQ(cross.at(n + mid, mid), 255);
  EXPECT_EQ(pz.at(mid, mid), 255);
  EXPECT_EQ(pz.at(0, 0), greyCode(4, 0, 0, n));
}

// ---------------------------------------------------------------------------------------------
// Reproducibility and names

TEST(DepthDump, IdenticalInputGivesByteIdenticalFiles) {
  TempDir first, second;
  CubeDistances cube = encodedCube(16);
  cube.faces[1][17] = kInf;
  dump(first.path(), "lamp", cube, 2000.0f);
  dump(second.path(), "lamp", cube, 2000.0f);
  const std::set<std::string> names = folderNames(first.path());
  ASSERT_EQ(names.size(), 14u);
  ASSERT_EQ(folderNames(second.path()), names);
  for (const std::string& name : names)
    EXPECT_EQ(fileBytes(first.path() / name), fileBytes(second.path() / name)) << name;
}

TEST(FileSafeName, KeepsLettersDigitsDashUnderscoreDotAndReplacesTheRest) {
  EXPECT_EQ(fileSafeName("my lamp/1"), "my_lamp_1");
  EXPECT_EQ(fileSafeName("Key-Light_2.5"), "Key-Light_2.5");
  EXPECT_EQ(fileSafeName("a\\b:c*?\"<>|"), "a_b_c______");
  EXPECT_EQ(fileSafeName("\t\n"), "__");
  EXPECT_EQ(fileSafeName("l\xC3\xA1mpara"), "l__mpara");  // each byte of a UTF-8 letter
  EXPECT_EQ(fileSafeName("/"), "_");
  EXPECT_EQ(fileSafeName(".."), "..");
  EXPECT_EQ(fileSafeName(""), "light");
}

}  // namespace
}  // namespace omnishadow::depth_dump_test
