#include "renderer/output/exr_reader.h"

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfInputFile.h>

#include <algorithm>
#include <cstddef>
#include <exception>
#include <iterator>
#include <string_view>
#include <vector>

#include "renderer/core/errors.h"
#include "renderer/output/image_limits.h"

namespace omnishadow {
namespace {

bool equalsIgnoringCase(std::string_view a, std::string_view b) {
  return std::equal(a.begin(), a.end(), b.begin(), b.end(), [](char x, char y) {
    return std::tolower(static_cast<unsigned char>(x)) ==
           std::tolower(static_cast<unsigned char>(y));
  });
}

struct SplitName {
  std::string_view layer, suffix;
};

SplitName split(std::string_view name) {
  const std::size_t dot = name.rfind('.');
  if (dot == std::string_view::npos) return {{}, name};
  return {name.substr(0, dot), name.substr(dot + 1)};
}

// The rank of a channel's suffix among OpenImageIO's reserved names; the rest come after.
int specialRank(std::string_view suffix, bool positionLayer) {
  static constexpr std::string_view kUsual[] = {
      "R",     "Red", "G",  "Green", "B",  "Blue", "Y",  "real", "imag",  "A",
      "Alpha", "AR",  "RA", "AG",    "GA", "AB",   "BA", "Z",    "Depth", "Zback"};
  static constexpr std::string_view kPosition[] = {
      "R", "Red",   "G",  "Green", "B",  "Blue", "X",  "Y",  "Z",     "real", "imag",
      "A", "Alpha", "AR", "RA",    "AG", "GA",   "AB", "BA", "Depth", "Zback"};
  auto rank = [&](const auto& list) {
    const auto* found = std::find_if(std::begin(list), std::end(list), [&](std::string_view s) {
      return equalsIgnoringCase(s, suffix);
    });
    return found == std::end(list) ? 10000 : static_cast<int>(found - std::begin(list));
  };
  return positionLayer ? rank(kPosition) : rank(kUsual);
}

bool isLuminanceChroma(const std::vector<std::string>& names) {
  if (names.size() < 3 || names.size() > 4) return false;
  auto has = [&](std::string_view suffix) {
    return std::any_of(names.begin(), names.end(), [&](const std::string& n) {
      return equalsIgnoringCase(split(n).suffix, suffix);
    });
  };
  if (!has("Y") || !has("BY") || !has("RY")) return false;
  return names.size() == 3 || has("A") || has("Alpha");
}

}  // namespace

std::vector<std::size_t> exrChannelOrder(const std::vector<std::string>& names) {
  struct Entry {
    std::size_t index;
    SplitName name;
    int rank = 0;
  };
  std::vector<Entry> entries;
  for (std::size_t i = 0; i < names.size(); ++i) entries.push_back({i, split(names[i])});
  std::stable_sort(entries.begin(), entries.end(),
                   [](const Entry& a, const Entry& b) { return a.name.layer < b.name.layer; });
  for (auto begin = entries.begin(); begin != entries.end();) {
    auto end = std::find_if(begin, entries.end(),
                            [&](const Entry& e) { return e.name.layer != begin->name.layer; });
    auto hasSuffix = [&](std::string_view s) {
      return std::any_of(begin, end,
                         [&](const Entry& e) { return equalsIgnoringCase(e.name.suffix, s); });
    };
    const bool position = hasSuffix("X") && (hasSuffix("Y") || hasSuffix("Z"));
    for (auto e = begin; e != end; ++e) e->rank = specialRank(e->name.suffix, position);
    std::sort(begin, end, [](const Entry& a, const Entry& b) {
      if (a.rank != b.rank) return a.rank < b.rank;
      return a.name.suffix < b.name.suffix;
    });
    begin = end;
  }
  std::vector<std::size_t> order;
  for (const Entry& e : entries) order.push_back(e.index);
  return order;
}

std::optional<FloatImage> readExr(const std::string& path) {
  try {
    Imf::InputFile file(path.c_str());
    const Imf::Header& header = file.header();
    std::vector<std::string> names;
    for (auto c = header.channels().begin(); c != header.channels().end(); ++c) {
      if (c.channel().xSampling != 1 || c.channel().ySampling != 1)
        throw InputError(path + ": cannot read image: subsampled channel \"" + c.name() +
                         "\" is not supported");
      names.emplace_back(c.name());
    }
    if (names.empty()) throw InputError(path + ": cannot read image: no channels");
    if (isLuminanceChroma(names)) return std::nullopt;

    const Imath::Box2i window = header.dataWindow();
    FloatImage image;
    image.width = window.max.x - window.min.x + 1;
    image.height = window.max.y - window.min.y + 1;
    if (const std::string problem = imageSizeProblem(
            std::int64_t{window.max.x} - window.min.x + 1,
            std::int64_t{window.max.y} - window.min.y + 1,
            static_cast<std::int64_t>(names.size()));
        !problem.empty())
      throw InputError(path + ": cannot read image: " + problem);
    for (std::size_t index : exrChannelOrder(names)) image.channels.push_back(names[index]);
    const std::size_t channels = image.channels.size();
    image.pixels.resize(static_cast<std::size_t>(image.width) * image.height * channels);

    // OpenEXR addresses the frame buffer by absolute pixel coordinates: shift the base so that
    // the data window's corner lands on pixels[0].
    const std::size_t xStride = sizeof(float) * channels;
    const std::size_t yStride = xStride * static_cast<std::size_t>(image.width);
    const std::ptrdiff_t origin = -static_cast<std::ptrdiff_t>(window.min.x * xStride) -
                                  static_cast<std::ptrdiff_t>(window.min.y * yStride);
    Imf::FrameBuffer frameBuffer;
    for (std::size_t c = 0; c < channels; ++c) {
      char* base = reinterpret_cast<char*>(image.pixels.data() + c) + origin;
      frameBuffer.insert(image.channels[c], Imf::Slice(Imf::FLOAT, base, xStride, yStride));
    }
    file.setFrameBuffer(frameBuffer);
    file.readPixels(window.min.y, window.max.y);
    return image;
  } catch (const InputError&) {
    throw;
  } catch (const std::exception& error) {
    throw InputError(path + ": cannot read image: " + error.what());
  }
}

}  // namespace omnishadow
