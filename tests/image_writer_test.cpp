#include "renderer/output/image_writer.h"

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfInputFile.h>
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <string>
#include <vector>

#include "renderer/core/errors.h"
#include "renderer/output/output_transaction.h"
#include "tests/support/temp_folder.h"

namespace omnishadow::image_writer_test {
namespace {

namespace fs = std::filesystem;

// A fresh folder per test, removed afterwards even when the test fails.
struct TempDir : test_support::TempFolder {
  TempDir() : TempFolder("omnishadow-image") {}
};

std::vector<std::uint8_t> testPattern(int width, int height, int channels) {
  std::vector<std::uint8_t> pixels(static_cast<std::size_t>(width) * height * channels);
  for (std::size_t i = 0; i < pixels.size(); ++i)
    pixels[i] = static_cast<std::uint8_t>(i * 37 + 11);
  return pixels;
}

std::vector<char> fileBytes(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

std::vector<fs::path> folderContents(const fs::path& folder) {
  std::vector<fs::path> entries;
  for (const auto& entry : fs::recursive_directory_iterator(folder))
    entries.push_back(entry.path());
  return entries;
}

// Values that stress half precision: negatives, fractions, large and tiny magnitudes.
FloatImage aovImage() {
  FloatImage image;
  image.width = 5;
  image.height = 3;
  image.channels = {"R", "G", "B", "A", "P.X", "P.Y", "P.Z", "visibility.lamp"};
  image.pixels.resize(std::size_t(image.width) * image.height * image.channels.size());
  for (std::size_t i = 0; i < image.pixels.size(); ++i) {
    float sign = (i % 3 == 0) ? -1.0f : 1.0f;
    image.pixels[i] =
        sign * (0.125f + static_cast<float>(i) * 1.37f) / ((i % 4 == 0) ? 1000.0f : 1.0f);
  }
  return image;
}

void expectNear(float expected, float actual, float relative) {
  EXPECT_NEAR(expected, actual, std::abs(expected) * relative + 1e-6f);
}

void expectSameImage(const FloatImage& expected, const FloatImage& actual, float relative) {
  ASSERT_EQ(expected.width, actual.width);
  ASSERT_EQ(expected.height, actual.height);
  ASSERT_EQ(expected.channels.size(), actual.channels.size());
  for (std::size_t c = 0; c < expected.channels.size(); ++c) {
    // OpenEXR stores channels sorted by name and OIIO may reorder them, so match by name.
    const int ac = actual.channelIndex(expected.channels[c]);
    ASSERT_GE(ac, 0) << "missing channel " << expected.channels[c];
    for (int y = 0; y < expected.height; ++y) {
      for (int x = 0; x < expected.width; ++x) {
        SCOPED_TRACE(expected.channels[c] + " at " + std::to_string(x) + "," + std::to_string(y));
        expectNear(expected.at(x, y, static_cast<int>(c)), actual.at(x, y, ac), relative);
      }
    }
  }
}

// --- FloatImage ---

TEST(FloatImageTest, ChannelIndexFindsNamesAndReportsAbsence) {
  FloatImage image;
  image.channels = {"R", "G", "P.X"};
  EXPECT_EQ(image.channelIndex("R"), 0);
  EXPECT_EQ(image.channelIndex("P.X"), 2);
  EXPECT_EQ(image.channelIndex("B"), -1);
  EXPECT_EQ(image.channelIndex(""), -1);
}

// --- PNG ---

class PngRoundTripTest : public ::testing::TestWithParam<int> {};

TEST_P(PngRoundTripTest, PixelsSurviveWriteAndRead) {
  TempDir dir;
  const int channels = GetParam();
  const int width = 7, height = 4;
  const auto pixels = testPattern(width, height, channels);
  const fs::path path = dir / "image.png";
  writePng(path, width, height, channels, pixels);

  FloatImage image = readImage(path);
  ASSERT_EQ(image.width, width);
  ASSERT_EQ(image.height, height);
  ASSERT_EQ(static_cast<int>(image.channels.size()), channels);
  // First row is the top row: index order must match exactly, no flip.
  for (std::size_t i = 0; i < pixels.size(); ++i)
    ASSERT_EQ(std::lround(image.pixels[i] * 255.0f), pixels[i]) << "at " << i;
}

INSTANTIATE_TEST_SUITE_P(Channels, PngRoundTripTest, ::testing::Values(1, 2, 3, 4));

TEST(PngTest, StraightAlphaIsStoredUnchanged) {
  // OIIO assumes premultiplied alpha by default and would divide (or, on read, multiply) colour
  // by alpha; renders carry straight alpha, so colour under alpha 0 or 128 must survive as is.
  TempDir dir;
  const std::vector<std::uint8_t> pixels = {200, 100, 50, 0, 200, 100, 50, 128};
  writePng(dir / "alpha.png", 2, 1, 4, pixels);
  const FloatImage image = readImage(dir / "alpha.png");
  ASSERT_EQ(image.pixels.size(), pixels.size());
  for (std::size_t i = 0; i < pixels.size(); ++i)
    EXPECT_EQ(std::lround(image.pixels[i] * 255.0f), pixels[i]) << "at " << i;
  EXPECT_EQ(image.channelIndex("A"), 3);
}

TEST(PngTest, IdenticalPixelsGiveIdenticalBytes) {
  TempDir dir;
  const auto pixels = testPattern(16, 9, 4);
  writePng(dir / "a.png", 16, 9, 4, pixels);
  // Cross a second boundary so that any time stamp would differ.
  sleep(1);
  writePng(dir / "b.png", 16, 9, 4, pixels);
  const auto a = fileBytes(dir / "a.png");
  ASSERT_FALSE(a.empty());
  EXPECT_EQ(a, fileBytes(dir / "b.png"));
}

TEST(PngTest, HasNoTextOrTimeChunks) {
  TempDir dir;
  writePng(dir / "a.png", 3, 2, 3, testPattern(3, 2, 3));
  const auto bytes = fileBytes(dir / "a.png");
  const std::string data(bytes.begin(), bytes.end());
  for (const char* chunk : {"tEXt", "zTXt", "iTXt", "tIME"})
    EXPECT_EQ(data.find(chunk), std::string::npos) << chunk;
}

TEST(PngTest, WrongBufferSizeOrChannelCountThrows) {
  TempDir dir;
  EXPECT_THROW(writePng(dir / "a.png", 4, 4, 3, std::vector<std::uint8_t>(47)),
               std::invalid_argument);
  EXPECT_THROW(writePng(dir / "a.png", 1, 1, 5, std::vector<std::uint8_t>(5)),
               std::invalid_argument);
  EXPECT_FALSE(fs::exists(dir / "a.png"));
}

TEST(PngTest, UnwritablePathThrowsRenderError) {
  TempDir dir;
  std::ofstream(dir / "file.txt") << "x";
  try {
    writePng(dir / "file.txt" / "a.png", 1, 1, 1, {0});
    FAIL() << "expected RenderError";
  } catch (const RenderError& error) {
    EXPECT_NE(std::string(error.what()).find("cannot write "), std::string::npos) << error.what();
  }
}

// --- EXR ---

class ExrRoundTripTest : public ::testing::TestWithParam<ExrPixelType> {};

TEST_P(ExrRoundTripTest, NamesAndValuesSurviveViaOpenImageIO) {
  TempDir dir;
  const FloatImage expected = aovImage();
  writeExr(dir / "aov.exr", expected, GetParam());
  const FloatImage actual = readImage(dir / "aov.exr");
  expectSameImage(expected, actual, GetParam() == ExrPixelType::Half ? 1e-3f : 0.0f);
}

TEST_P(ExrRoundTripTest, HeaderHasExactChannelsTypeAndZip) {
  TempDir dir;
  const FloatImage expected = aovImage();
  writeExr(dir / "aov.exr", expected, GetParam());

  Imf::InputFile file((dir / "aov.exr").string().c_str());
  const Imf::Header& header = file.header();
  EXPECT_EQ(header.compression(), Imf::ZIP_COMPRESSION);
  EXPECT_EQ(header.find("capDate"), header.end());
  const Imf::PixelType type = GetParam() == ExrPixelType::Half ? Imf::HALF : Imf::FLOAT;
  std::size_t count = 0;
  for (auto it = header.channels().begin(); it != header.channels().end(); ++it, ++count) {
    EXPECT_NE(expected.channelIndex(it.name()), -1) << "unexpected channel " << it.name();
    EXPECT_EQ(it.channel().type, type);
  }
  EXPECT_EQ(count, expected.channels.size());

  // Read one dotted channel straight through OpenEXR, bypassing OIIO's channel handling.
  const int lamp = expected.channelIndex("visibility.lamp");
  std::vector<float> values(std::size_t(expected.width) * expected.height);
  Imf::FrameBuffer frameBuffer;
  frameBuffer.insert("visibility.lamp",
                     Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(values.data()), sizeof(float),
                                sizeof(float) * expected.width));
  file.setFrameBuffer(frameBuffer);
  file.readPixels(0, expected.height - 1);
  for (int y = 0; y < expected.height; ++y)
    for (int x = 0; x < expected.width; ++x)
      expectNear(expected.at(x, y, lamp), values[std::size_t(y) * expected.width + x],
                 GetParam() == ExrPixelType::Half ? 1e-3f : 0.0f);
}

TEST_P(ExrRoundTripTest, IdenticalPixelsGiveIdenticalBytes) {
  TempDir dir;
  writeExr(dir / "a.exr", aovImage(), GetParam());
  sleep(1);
  writeExr(dir / "b.exr", aovImage(), GetParam());
  const auto a = fileBytes(dir / "a.exr");
  ASSERT_FALSE(a.empty());
  EXPECT_EQ(a, fileBytes(dir / "b.exr"));
}

INSTANTIATE_TEST_SUITE_P(PixelTypes, ExrRoundTripTest,
                         ::testing::Values(ExrPixelType::Half, ExrPixelType::Float),
                         [](const auto& param) {
                           return param.param == ExrPixelType::Half ? "Half" : "Float";
                         });

TEST(ExrTest, MismatchedSizeThrowsInvalidArgument) {
  TempDir dir;
  FloatImage image = aovImage();
  image.pixels.pop_back();
  EXPECT_THROW(writeExr(dir / "a.exr", image, ExrPixelType::Float), std::invalid_argument);
  EXPECT_FALSE(fs::exists(dir / "a.exr"));
}

TEST(ExrTest, DuplicateChannelNamesThrowInvalidArgument) {
  TempDir dir;
  FloatImage image = aovImage();
  image.channels[1] = "R";
  EXPECT_THROW(writeExr(dir / "a.exr", image, ExrPixelType::Half), std::invalid_argument);
}

TEST(ExrTest, UnwritablePathThrowsRenderError) {
  TempDir dir;
  std::ofstream(dir / "file.txt") << "x";
  try {
    writeExr(dir / "file.txt" / "a.exr", aovImage(), ExrPixelType::Half);
    FAIL() << "expected RenderError";
  } catch (const RenderError& error) {
    EXPECT_NE(std::string(error.what()).find("cannot write "), std::string::npos) << error.what();
  }
}

// --- readImage ---

TEST(ReadImageTest, MissingFileThrowsInputError) {
  TempDir dir;
  try {
    readImage(dir / "missing.png");
    FAIL() << "expected InputError";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find("missing.png: cannot read image: "), std::string::npos)
        << error.what();
  }
}

TEST(ReadImageTest, GarbageFileThrowsInputError) {
  TempDir dir;
  std::ofstream(dir / "garbage.png", std::ios::binary) << "this is not a PNG at all";
  std::ofstream(dir / "garbage.exr", std::ios::binary) << "nor an EXR";
  EXPECT_THROW(readImage(dir / "garbage.png"), InputError);
  EXPECT_THROW(readImage(dir / "garbage.exr"), InputError);
}

// --- OutputTransaction ---

TEST(OutputTransactionTest, StagedFilesAppearOnlyOnCommit) {
  TempDir dir;
  const fs::path png = dir / "render.png";
  const fs::path exr = dir / "render.exr";
  {
    OutputTransaction transaction;
    const fs::path pngTemp = transaction.stage(png);
    const fs::path exrTemp = transaction.stage(exr);
    EXPECT_EQ(pngTemp.parent_path(), dir.path());
    EXPECT_EQ(pngTemp.extension(), ".png");
    EXPECT_EQ(exrTemp.extension(), ".exr");
    EXPECT_EQ(pngTemp.filename().string().front(), '.');
    EXPECT_NE(pngTemp, exrTemp);

    writePng(pngTemp, 2, 2, 3, testPattern(2, 2, 3));
    writeExr(exrTemp, aovImage(), ExrPixelType::Half);
    EXPECT_FALSE(fs::exists(png));
    EXPECT_FALSE(fs::exists(exr));

    transaction.commit();
    EXPECT_FALSE(fs::exists(pngTemp));
    EXPECT_FALSE(fs::exists(exrTemp));
  }
  EXPECT_TRUE(fs::exists(png));
  EXPECT_TRUE(fs::exists(exr));
  EXPECT_EQ(folderContents(dir.path()).size(), 2u);
  EXPECT_EQ(readImage(png).width, 2);
}

TEST(OutputTransactionTest, CommitReplacesExistingFile) {
  TempDir dir;
  const fs::path png = dir / "render.png";
  std::ofstream(png) << "old";
  OutputTransaction transaction;
  writePng(transaction.stage(png), 1, 1, 1, {200});
  EXPECT_EQ(fileBytes(png), (std::vector<char>{'o', 'l', 'd'}));
  transaction.commit();
  EXPECT_EQ(std::lround(readImage(png).pixels[0] * 255.0f), 200);
}

TEST(OutputTransactionTest, DestructionWithoutCommitLeavesNothing) {
  TempDir dir;
  {
    OutputTransaction transaction;
    writePng(transaction.stage(dir / "render.png"), 2, 2, 1, testPattern(2, 2, 1));
    transaction.stage(dir / "render.exr");  // staged but never written, as after an exception
  }
  EXPECT_TRUE(folderContents(dir.path()).empty());
}

TEST(OutputTransactionTest, TheTemporariesOfAKilledProcessCanBeRemoved) {
  TempDir dir;
  // What a process 4242 killed while writing render.png leaves, beside other files.
  for (const char* name :
       {".render.png.tmp-4242-0.png", ".render.png.tmp-4242-17.png", ".render.png.tmp-42420-0.png",
        ".render.exr.tmp-4242-1.exr", ".other.png.tmp-4242-2.png", "render.png"})
    std::ofstream(dir / name) << "x";
  OutputTransaction::removeTemporariesOf(dir / "render.png", 4242);
  std::vector<std::string> left;
  for (const fs::path& path : folderContents(dir.path())) left.push_back(path.filename());
  std::sort(left.begin(), left.end());
  EXPECT_EQ(left,
            (std::vector<std::string>{".other.png.tmp-4242-2.png", ".render.exr.tmp-4242-1.exr",
                                      ".render.png.tmp-42420-0.png", "render.png"}));
  OutputTransaction::removeTemporariesOf(dir / "missing" / "render.png", 4242);  // no folder
}

TEST(OutputTransactionTest, TemporariesAreUniquePerCallAndTransaction) {
  TempDir dir;
  OutputTransaction first;
  OutputTransaction second;
  const fs::path a = first.stage(dir / "render.png");
  const fs::path b = second.stage(dir / "render.png");
  EXPECT_NE(a, b);
  EXPECT_NE(a.filename().string().find(std::to_string(::getpid())), std::string::npos);
}

TEST(OutputTransactionTest, RefusesToStageTheSameFinalTwice) {
  TempDir dir;
  OutputTransaction transaction;
  transaction.stage(dir / "render.png");
  EXPECT_THROW(transaction.stage(dir / "sub" / ".." / "render.png"), RenderError);
}

TEST(OutputTransactionTest, CreatesMissingParentFolders) {
  TempDir dir;
  const fs::path png = dir / "a" / "b" / "render.png";
  OutputTransaction transaction;
  const fs::path temporary = transaction.stage(png);
  EXPECT_TRUE(fs::is_directory(dir / "a" / "b"));
  EXPECT_EQ(temporary.parent_path(), png.parent_path());
  writePng(temporary, 1, 1, 1, {1});
  transaction.commit();
  EXPECT_TRUE(fs::exists(png));
}

void expectStageFails(const fs::path& finalPath) {
  OutputTransaction transaction;
  try {
    transaction.stage(finalPath);
    FAIL() << "expected RenderError";
  } catch (const RenderError& error) {
    EXPECT_EQ(std::string(error.what()).rfind("cannot write " + finalPath.string() + ": ", 0), 0u)
        << error.what();
  }
}

TEST(OutputTransactionTest, FileInPlaceOfFolderThrowsAndLeavesNothing) {
  TempDir dir;
  // A regular file as "folder" fails for root too, unlike permission bits.
  std::ofstream(dir / "somefile.txt") << "x";
  expectStageFails(dir / "somefile.txt" / "out.png");
  expectStageFails(dir / "somefile.txt" / "deeper" / "out.png");
  EXPECT_EQ(folderContents(dir.path()), std::vector<fs::path>{dir / "somefile.txt"});
}

TEST(OutputTransactionTest, ReadOnlyFolderThrowsAndLeavesNothing) {
  // Root (as in CI) ignores permission bits: the read-only folder is checked for other users.
  if (::geteuid() != 0) {
    TempDir dir;
    const fs::path locked = dir / "locked";
    fs::create_directory(locked);
    fs::permissions(locked, fs::perms::owner_read | fs::perms::owner_exec);
    expectStageFails(locked / "out.png");
    fs::permissions(locked, fs::perms::owner_all);
    EXPECT_TRUE(folderContents(locked).empty());
  }
  // What no user, root included, may create: a file in /proc, a name longer than NAME_MAX.
  expectStageFails(fs::path("/proc") / "omnishadow-out.png");
  TempDir dir;
  expectStageFails(dir / (std::string(300, 'x') + ".png"));
  EXPECT_TRUE(folderContents(dir.path()).empty());
}

TEST(OutputTransactionTest, CommitOfUnwrittenStageThrowsAndPublishesNothing) {
  TempDir dir;
  OutputTransaction transaction;
  writePng(transaction.stage(dir / "good.png"), 1, 1, 1, {1});
  transaction.stage(dir / "never_written.png");
  EXPECT_THROW(transaction.commit(), RenderError);
  EXPECT_TRUE(folderContents(dir.path()).empty());
}

TEST(OutputTransactionTest, FailedRenameThrowsAndRemovesTemporaries) {
  TempDir dir;
  // A non-empty folder where the final file should go makes rename(2) fail.
  fs::create_directories(dir / "render.png" / "occupied");
  OutputTransaction transaction;
  writePng(transaction.stage(dir / "render.png"), 1, 1, 1, {1});
  EXPECT_THROW(transaction.commit(), RenderError);
  EXPECT_EQ(folderContents(dir.path()),
            (std::vector<fs::path>{dir / "render.png", dir / "render.png" / "occupied"}));
}

}  // namespace
}  // namespace omnishadow::image_writer_test
