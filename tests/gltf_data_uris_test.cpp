// Base64 data: URIs decoded before tinygltf parses the JSON (renderer/scene/gltf_data_uris.h):
// the bytes, the model and the messages must be what tinygltf's own decoding gives, which is
// what the loader had before. tinygltf is the reference here: its decoder and its parse of the
// same text, run beside ours.
#include "renderer/scene/gltf_data_uris.h"

#include <gtest/gtest.h>
#include <tiny_gltf.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <random>
#include <string>
#include <vector>

#include "renderer/scene/gltf_compressed_json.h"
#include "renderer/scene/gltf_file_safety.h"
#include "renderer/scene/gltf_reader.h"
#include "tests/support/base64.h"
#include "tests/support/input_error.h"
#include "tests/support/temp_folder.h"

// Exported by Debian's libtinygltf, declared only in the header's implementation part.
namespace tinygltf {
std::string base64_decode(std::string const& s);
}  // namespace tinygltf

namespace omnishadow::gltf_data_uris_test {
namespace {

using gltf_detail::DataUris;
using gltf_detail::decodeBase64AsTinygltf;
using test_support::base64;
using json = nlohmann::json;
using Bytes = std::vector<unsigned char>;
namespace fs = std::filesystem;

constexpr char kLetters[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
constexpr char kOctetStream[] = "data:application/octet-stream;base64,";

Bytes tinygltfDecoding(const std::string& text) {
  const std::string decoded = tinygltf::base64_decode(text);
  return Bytes(decoded.begin(), decoded.end());
}

Bytes counting(std::size_t size, unsigned char first = 0) {
  Bytes bytes(size);
  for (std::size_t i = 0; i < size; ++i) bytes[i] = static_cast<unsigned char>(first + i);
  return bytes;
}

void write(const fs::path& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
}

TEST(DecodeBase64AsTinygltf, GivesTinygltfsBytesForAnyText) {
  // Letters mostly, and what tinygltf stops at: '=', other ASCII, bytes above 127, NUL.
  const std::string others = std::string("= \n\t-_.,:\"\\\x80\xff\x7f") + '\0';
  std::mt19937 random(20261201);
  for (int n = 0; n < 20000; ++n) {
    std::string text(random() % 40, ' ');
    for (char& c : text)
      c = random() % 5 != 0 ? kLetters[random() % 64] : others[random() % others.size()];
    ASSERT_EQ(decodeBase64AsTinygltf(text), tinygltfDecoding(text)) << '"' << text << '"';
  }
  for (const char* text : {"", "A", "AB", "ABC", "ABCD", "ABCDE", "QQ==", "QUI=", "QUJD",
                           "QR==", "AAAA====", "=AAAA", "AA=A", "AA AA", "////", "++++"}) {
    EXPECT_EQ(decodeBase64AsTinygltf(text), tinygltfDecoding(text)) << text;
  }
  // A megabyte of every byte value: the bytes back, as tinygltf gives them.
  Bytes bytes((1 << 20) + 1);
  for (unsigned char& b : bytes) b = static_cast<unsigned char>(random());
  const std::string text = base64(bytes);
  EXPECT_EQ(decodeBase64AsTinygltf(text), bytes);
  EXPECT_EQ(tinygltfDecoding(text), bytes);
}

// 1200 bytes: 1600 letters, a URI long enough to be taken (shorter ones are left to tinygltf).
const Bytes& long1200() {
  static const Bytes bytes = counting(1200);
  return bytes;
}

TEST(DataUris, TakesTheUrisTinygltfDecodesWithoutAMessageAndLeavesTheRest) {
  const Bytes& bytes = long1200();
  const std::string text = base64(bytes);
  const std::string zeros = std::string(1600, 'A') + "====";  // tinygltf stops at the '='
  const json doc = {
      {"asset", {{"version", "2.0"}}},
      {"buffers",
       {
           {{"byteLength", 1200}, {"uri", kOctetStream + text}},                            // 0
           {{"byteLength", 1200}, {"uri", "data:application/gltf-buffer;base64," + text}},  // 1
           {{"byteLength", 1201}, {"uri", kOctetStream + text}},         // 2: tinygltf's message
           {{"byteLength", 1200.0}, {"uri", kOctetStream + text}},       // 3: tinygltf's message
           {{"byteLength", 1200}, {"uri", kOctetStream + text + "\n"}},  // 4: an escape
           {{"byteLength", 1200}, {"uri", "DATA:application/octet-stream;base64," + text}},  // 5
           {{"byteLength", 1200}, {"uri", kOctetStream + zeros}},                // 6 taken
           {{"byteLength", 0}, {"uri", kOctetStream + std::string(1200, '=')}},  // 7: no bytes
           {{"byteLength", 3}, {"uri", kOctetStream + base64(counting(3))}},     // 8: short
       }},
      {"images",
       {
           {{"uri", "data:image/png;base64," + text}},                      // 0 taken
           {{"uri", "data:image/jpeg;base64," + text}, {"bufferView", 0}},  // 1: both, refused
           {{"uri", "data:image/png;base64,=" + text}},                     // 2: no bytes
           {{"uri", "data:text/plain;base64," + text}},                     // 3 taken
           {{"uri", "data:image/webp;base64," + text}},  // 4: the review retypes WebP first
           {{"uri", kOctetStream + text}},               // 5 taken, no type
       }},
      {"extras", {{"note", kOctetStream + text}}},  // not a URI
  };
  DataUris uris;
  const std::optional<std::string> taken = uris.take(doc.dump());
  ASSERT_TRUE(taken.has_value());
  const json parsed = json::parse(*taken);
  json expected = doc;
  const auto name = [&](const char* array, std::size_t i) {
    return parsed[array][i]["uri"].get<std::string>();
  };
  for (const auto& [array, i, mimeType, decoded] :
       std::vector<std::tuple<const char*, std::size_t, std::string, Bytes>>{
           {"buffers", 0, "", bytes},
           {"buffers", 1, "", bytes},
           {"buffers", 6, "", Bytes(1200, 0)},
           {"images", 0, "image/png", bytes},
           {"images", 3, "text/plain", bytes},
           {"images", 5, "", bytes}}) {
    SCOPED_TRACE(std::string(array) + "[" + std::to_string(i) + "]");
    EXPECT_TRUE(name(array, i).starts_with("omnishadow-data-uri-")) << name(array, i);
    DataUris::Payload* payload = uris.find("/some/folder/" + name(array, i));
    ASSERT_NE(payload, nullptr);
    EXPECT_EQ(payload->bytes, decoded);
    EXPECT_EQ(payload->mimeType, mimeType);
    EXPECT_EQ(payload->image, std::string(array) == "images");
    EXPECT_EQ(payload->uri, payload->image ? "" : doc[array][i]["uri"].get<std::string>());
    expected[array][i]["uri"] = name(array, i);
  }
  // Everything else is as it was.
  EXPECT_EQ(parsed, expected);
  EXPECT_EQ(uris.find("/some/folder/omnishadow-data-uri-999"), nullptr);
  EXPECT_EQ(uris.find("/some/folder/omnishadow-data-uri-0x"), nullptr);
  EXPECT_EQ(uris.find("/some/folder/b.bin"), nullptr);
}

TEST(DataUris, LeavesFilesItCannotReadWhole) {
  const json buffers = {{{"byteLength", 1200}, {"uri", kOctetStream + base64(long1200())}}};
  const std::string good = json{{"buffers", buffers}}.dump();
  DataUris uris;
  EXPECT_TRUE(uris.take(good).has_value());
  // JSON that does not parse, before or after the URI: tinygltf's message says where.
  EXPECT_FALSE(uris.take(good + " x").has_value());
  EXPECT_FALSE(uris.take("{,," + good.substr(1)).has_value());
  EXPECT_FALSE(uris.take(good.substr(0, good.size() - 1)).has_value());
  // A URI with a raw control character is no JSON string; with it beside a URI that could be
  // taken, tinygltf's message would name a position in the shorter JSON.
  std::string control = good;
  control.insert(control.find("base64,") + 7 + 1000, "\x01");
  EXPECT_FALSE(uris.take(control).has_value());
  const std::string beside =
      json{{"buffers", {buffers[0], {{"byteLength", 1200}, {"uri", "@"}}}}}.dump();
  const std::string bad = kOctetStream + std::string(1200, 'A') + "\x01";
  EXPECT_TRUE(uris.take(beside).has_value());
  EXPECT_FALSE(
      uris.take(std::string(beside).replace(beside.find("\"@\""), 3, '"' + bad + '"')).has_value());
  // Text that could be taken for a placeholder anywhere in the file: nothing is taken, so that
  // a file of that name is read as the file it is.
  EXPECT_FALSE(uris.take(json{{"buffers", buffers}, {"extras", "omnishadow-data-uri-0"}}.dump())
                   .has_value());
  EXPECT_FALSE(uris.take(R"({"buffers": [{"byteLength": 3, "uri": "a.bin"}]})").has_value());
}

// tinygltf finds and reads a taken URI through the file callbacks, once.
TEST(DataUris, AreServedOnceByTheFileCallbacks) {
  test_support::TempFolder folder("omnishadow-data-uris");
  const json doc = {
      {"buffers", {{{"byteLength", 1200}, {"uri", kOctetStream + base64(long1200())}}}}};
  DataUris uris;
  const std::optional<std::string> taken = uris.take(doc.dump());
  ASSERT_TRUE(taken.has_value());
  const std::string name = json::parse(*taken)["buffers"][0]["uri"].get<std::string>();
  gltf_detail::UriPolicy policy{folder.path(), false, {}, &uris};
  const std::string path = (folder / name).string();
  EXPECT_TRUE(gltf_detail::existsWithinFolder(path, &policy));
  EXPECT_FALSE(
      gltf_detail::existsWithinFolder((folder / "omnishadow-data-uri-7").string(), &policy));
  std::vector<unsigned char> bytes;
  std::string error;
  ASSERT_TRUE(gltf_detail::readWithinFolder(&bytes, &error, path, &policy));
  EXPECT_EQ(bytes, long1200());
  EXPECT_FALSE(gltf_detail::readWithinFolder(&bytes, &error, path, &policy));
  EXPECT_EQ(error, "a data: URI read twice");
  EXPECT_TRUE(policy.violation.empty());
}

// What readModel() makes of a file against what tinygltf makes of it by itself.
class DataUriModelTest : public ::testing::Test {
 protected:
  test_support::TempFolder folder_{"omnishadow-data-uris"};

  tinygltf::Model read(const fs::path& path) {
    std::vector<std::string> warnings;
    bool binary = false;
    gltf_detail::CompressionFixups fixups;
    return gltf_detail::readModel(path, path.filename().string(), warnings, &binary, false, fixups);
  }

  // tinygltf alone, with the loader's image callback and no data: URI taken out.
  tinygltf::Model tinygltfAlone(const fs::path& path) {
    tinygltf::TinyGLTF reader;
    reader.SetImageLoader(gltf_detail::decodeUriImage, nullptr);
    tinygltf::Model model;
    std::string error, warning;
    const std::string text = test_support::readFile(path);
    const bool ok =
        path.extension() == ".glb"
            ? reader.LoadBinaryFromMemory(
                  &model, &error, &warning, reinterpret_cast<const unsigned char*>(text.data()),
                  static_cast<unsigned>(text.size()), folder_.path().string())
            : reader.LoadASCIIFromString(&model, &error, &warning, text.data(),
                                         static_cast<unsigned>(text.size()),
                                         folder_.path().string());
    EXPECT_TRUE(ok) << error;
    return model;
  }

  static void expectSameBuffersAndImages(const tinygltf::Model& ours,
                                         const tinygltf::Model& reference) {
    ASSERT_EQ(ours.buffers.size(), reference.buffers.size());
    for (std::size_t i = 0; i < ours.buffers.size(); ++i) {
      SCOPED_TRACE("buffers[" + std::to_string(i) + "]");
      EXPECT_EQ(ours.buffers[i].data, reference.buffers[i].data);
      EXPECT_EQ(ours.buffers[i].uri, reference.buffers[i].uri);
    }
    ASSERT_EQ(ours.images.size(), reference.images.size());
    for (std::size_t i = 0; i < ours.images.size(); ++i) {
      SCOPED_TRACE("images[" + std::to_string(i) + "]");
      EXPECT_EQ(ours.images[i].uri, reference.images[i].uri);
      EXPECT_EQ(ours.images[i].name, reference.images[i].name);
      // tinygltf decoded the reference's; ours are kept for the loader's decoding threads, as
      // an image in a file of its own is (the pictures: EmbeddedExternalAndGlbLoad... in
      // gltf_loader_test).
      EXPECT_TRUE(ours.images[i].as_is);
      EXPECT_FALSE(reference.images[i].as_is);
      EXPECT_GT(reference.images[i].width, 0);
    }
  }

  static std::string png() {
    return test_support::readFile(fs::path(OMNISHADOW_SOURCE_DIR) /
                                  "scenes/khronos/TextureTransformTest/Correct.png");
  }
};

TEST_F(DataUriModelTest, AGltfsDataUrisGiveTheModelTinygltfsDecodingGives) {
  const std::string image = png();
  ASSERT_FALSE(image.empty());
  const Bytes imageBytes(image.begin(), image.end());
  const json doc = {
      {"asset", {{"version", "2.0"}}},
      {"buffers",
       {{{"byteLength", 1200}, {"uri", kOctetStream + base64(counting(1200))}},
        {{"byteLength", 1000},
         {"uri", "data:application/gltf-buffer;base64," + base64(counting(1000, 9))}},
        {{"byteLength", 1001}, {"uri", kOctetStream + base64(counting(1001, 1)) + "=="}},
        {{"byteLength", 5}, {"uri", kOctetStream + base64(counting(5, 1))}}}},
      {"images",
       {{{"uri", "data:image/png;base64," + base64(imageBytes)}, {"name", "labelled"}},
        {{"uri", kOctetStream + base64(imageBytes)}},
        {{"uri", "data:image/jpeg;base64," + base64(imageBytes)}}}},  // mislabelled: sniffed
  };
  const fs::path path = folder_ / "scene.gltf";
  write(path, doc.dump());
  const tinygltf::Model ours = read(path);
  expectSameBuffersAndImages(ours, tinygltfAlone(path));
  EXPECT_EQ(ours.buffers[0].data, counting(1200));
  EXPECT_EQ(ours.buffers[1].data, counting(1000, 9));
  EXPECT_EQ(ours.buffers[2].data, counting(1001, 1));
  EXPECT_EQ(ours.buffers[3].data, counting(5, 1));
  for (const tinygltf::Image& decoded : ours.images) EXPECT_EQ(decoded.image, imageBytes);
  // The type the URI gave until the loader sniffs the bytes, as tinygltf leaves it.
  EXPECT_EQ(ours.images[0].mimeType, "image/png");
  EXPECT_EQ(ours.images[1].mimeType, "");
  EXPECT_EQ(ours.images[2].mimeType, "image/jpeg");
}

TEST_F(DataUriModelTest, AGlbsDataUrisGiveTheModelTinygltfsDecodingGives) {
  const json doc = {{"asset", {{"version", "2.0"}}},
                    {"buffers",
                     {{{"byteLength", 4}},
                      {{"byteLength", 1200}, {"uri", kOctetStream + base64(counting(1200, 3))}}}}};
  std::string chunk = doc.dump();
  while (chunk.size() % 4 != 0) chunk += ' ';
  const std::string bin = "\x01\x02\x03\x04";
  std::string glb = "glTF";
  const auto put32 = [&](std::size_t value) {
    for (int i = 0; i < 4; ++i) glb += static_cast<char>((value >> (8 * i)) & 0xFF);
  };
  put32(2);
  put32(12 + 8 + chunk.size() + 8 + bin.size());
  put32(chunk.size());
  glb += "JSON" + chunk;
  put32(bin.size());
  glb += std::string("BIN\0", 4) + bin;
  const fs::path path = folder_ / "scene.glb";
  write(path, glb);
  const tinygltf::Model ours = read(path);
  expectSameBuffersAndImages(ours, tinygltfAlone(path));
  EXPECT_EQ(ours.buffers[0].data, Bytes({1, 2, 3, 4}));
  EXPECT_EQ(ours.buffers[1].data, counting(1200, 3));
}

// A file of the placeholders' form beside the scene is read as the file it is.
TEST_F(DataUriModelTest, AFileNamedLikeAPlaceholderIsReadFromDisk) {
  write(folder_ / "omnishadow-data-uri-0", "\x07\x07\x07");
  const json doc = {{"asset", {{"version", "2.0"}}},
                    {"buffers",
                     {{{"byteLength", 3}, {"uri", "omnishadow-data-uri-0"}},
                      {{"byteLength", 1200}, {"uri", kOctetStream + base64(counting(1200, 5))}}}}};
  const fs::path path = folder_ / "scene.gltf";
  write(path, doc.dump());
  const tinygltf::Model ours = read(path);
  EXPECT_EQ(ours.buffers[0].data, Bytes({7, 7, 7}));
  EXPECT_EQ(ours.buffers[1].data, counting(1200, 5));
  EXPECT_EQ(ours.buffers[0].uri, "omnishadow-data-uri-0");
}

// What tinygltf refuses it still refuses in its own words, with the object named and the URI
// cut short.
TEST_F(DataUriModelTest, BrokenDataUrisGiveTinygltfsMessages) {
  const fs::path path = folder_ / "scene.gltf";
  const auto refused = [&](const json& buffers, const json& images) {
    write(path,
          json{{"asset", {{"version", "2.0"}}}, {"buffers", buffers}, {"images", images}}.dump());
    return test_support::inputError([&] { read(path); });
  };
  const std::string six = base64(counting(6));
  EXPECT_EQ(refused({{{"byteLength", 7}, {"uri", kOctetStream + six}}}, json::array()),
            "scene.gltf: buffers[0]: Failed to decode 'uri' : " + std::string(kOctetStream) + six +
                " in Buffer");
  const std::string many = base64(counting(3000));
  EXPECT_EQ(refused({{{"byteLength", 3}, {"uri", kOctetStream + base64(counting(3))}},
                     {{"byteLength", 2999}, {"uri", kOctetStream + many}}},
                    json::array()),
            "scene.gltf: buffers[1]: Failed to decode 'uri' : " +
                (kOctetStream + many).substr(0, 60) + "... in Buffer");
  EXPECT_EQ(refused({{{"byteLength", 1}, {"uri", std::string(kOctetStream)}}}, json::array()),
            "scene.gltf: buffers[0]: Failed to decode 'uri' : " + std::string(kOctetStream) +
                " in Buffer");
  EXPECT_EQ(refused(json::array(), {{{"uri", "data:image/png;base64,"}}}),
            "scene.gltf: images[0]: Failed to decode 'uri' for image[0] name = []");
}

}  // namespace
}  // namespace omnishadow::gltf_data_uris_test
