#include "renderer/scene/gltf_data_uris.h"

#include <algorithm>
#include <array>
#include <charconv>
#include <cstdint>
#include <nlohmann/json.hpp>

#include "renderer/scene/json_strings.h"

namespace omnishadow::gltf_detail {

namespace {

using Json = nlohmann::json;

// The data: types that tinygltf's IsDataURI and DecodeDataURI know (case and all), with the
// mimeType DecodeDataURI gives an image of each.
struct DataUriType {
  std::string_view header;
  std::string_view mimeType;
};
constexpr DataUriType kDataUriTypes[] = {
    {"data:application/octet-stream;base64,", ""}, {"data:image/jpeg;base64,", "image/jpeg"},
    {"data:image/png;base64,", "image/png"},       {"data:image/bmp;base64,", "image/bmp"},
    {"data:image/gif;base64,", "image/gif"},       {"data:text/plain;base64,", "text/plain"},
    {"data:application/gltf-buffer;base64,", ""},
};

// Placeholders are this and a number; a file whose JSON already has the text is left to
// tinygltf, so that no URI of its own can be mistaken for one.
constexpr std::string_view kDataUriPlaceholder = "omnishadow-data-uri-";

// Shorter URIs are left to tinygltf: for a few bytes its decoding costs less than a file
// lookup, and a file of 200,000 one-byte data: URIs loaded 1.5 times slower taken.
constexpr std::size_t kShortestTaken = 1024;

constexpr unsigned char kNotALetter = 0xFF;
constexpr std::array<unsigned char, 256> kLetterValues = [] {
  std::array<unsigned char, 256> values{};
  values.fill(kNotALetter);
  constexpr std::string_view kLetters =
      "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  for (std::size_t i = 0; i < kLetters.size(); ++i)
    values[static_cast<unsigned char>(kLetters[i])] = static_cast<unsigned char>(i);
  return values;
}();

// decodeBase64AsTinygltf(), and where the letters end in `text`.
std::vector<unsigned char> decodeLetters(std::string_view text, std::size_t* lettersEnd) {
  const auto* in = reinterpret_cast<const unsigned char*>(text.data());
  std::vector<unsigned char> out(text.size() / 4 * 3 + 2);
  unsigned char* o = out.data();
  std::size_t i = 0;
  for (; i + 4 <= text.size(); i += 4) {
    const unsigned a = kLetterValues[in[i]], b = kLetterValues[in[i + 1]],
                   c = kLetterValues[in[i + 2]], d = kLetterValues[in[i + 3]];
    if (((a | b | c | d) & 0x80) != 0) break;  // a letter's value is below 64
    const std::uint32_t bits = a << 18 | b << 12 | c << 6 | d;
    o[0] = static_cast<unsigned char>(bits >> 16);
    o[1] = static_cast<unsigned char>(bits >> 8);
    o[2] = static_cast<unsigned char>(bits);
    o += 3;
  }
  // The last group: fewer than four letters (the loop stopped at a group that has another
  // character, or at the end).
  unsigned group[3] = {0, 0, 0};
  int letters = 0;
  for (; i < text.size() && letters < 3 && kLetterValues[in[i]] != kNotALetter; ++i)
    group[letters++] = kLetterValues[in[i]];
  if (letters >= 2) *o++ = static_cast<unsigned char>(group[0] << 2 | group[1] >> 4);
  if (letters >= 3) *o++ = static_cast<unsigned char>((group[1] & 0xF) << 4 | group[2] >> 2);
  out.resize(static_cast<std::size_t>(o - out.data()));
  *lettersEnd = i;
  return out;
}

std::string placeholderName(std::size_t index) {
  return std::string(kDataUriPlaceholder) + std::to_string(index);
}

// The number whose placeholderName() `name` is, or nullopt.
std::optional<std::size_t> placeholderNumber(std::string_view name) {
  if (!name.starts_with(kDataUriPlaceholder)) return std::nullopt;
  std::size_t number = 0;
  std::from_chars(name.data() + kDataUriPlaceholder.size(), name.data() + name.size(), number);
  if (name != placeholderName(number)) return std::nullopt;
  return number;
}

}  // namespace

std::vector<unsigned char> decodeBase64AsTinygltf(std::string_view text) {
  std::size_t lettersEnd = 0;
  return decodeLetters(text, &lettersEnd);
}

std::optional<std::string> DataUris::take(std::string_view json) {
  payloads_.clear();
  if (json.find("\"data:") == std::string_view::npos ||
      json.find(kDataUriPlaceholder) != std::string_view::npos) {
    return std::nullopt;
  }
  struct Candidate {
    std::size_t open = 0, close = 0;  // the string's quotes
    const DataUriType* type = nullptr;
    enum class Use { None, Buffer, Image } use = Use::None;
    std::uint64_t byteLength = 0;  // a buffer's
  };
  std::vector<Candidate> candidates;
  forEachJsonString(json, [&](std::size_t open, std::size_t close) {
    const std::string_view content = json.substr(open + 1, close - open - 1);
    if (content.size() < kShortestTaken || !content.starts_with("data:")) return;
    for (const DataUriType& type : kDataUriTypes) {
      if (content.starts_with(type.header)) {
        candidates.push_back({open, close, &type});
        return;
      }
    }
  });
  if (candidates.empty()) return std::nullopt;

  // The JSON with the candidates replaced: `taken(i)` says which.
  const auto replaced = [&](const auto& taken) {
    std::string out;
    std::size_t copied = 0;
    for (std::size_t i = 0; i < candidates.size(); ++i) {
      if (!taken(i)) continue;
      out.append(json, copied, candidates[i].open + 1 - copied);
      out += placeholderName(i);
      copied = candidates[i].close;
    }
    out.append(json.substr(copied));
    return out;
  };

  // Where each candidate stands, from the JSON with all of them replaced: small enough to
  // parse. It parses exactly where the file's JSON does (the candidates' content is checked to
  // be plain below), with the same structure.
  const Json root = Json::parse(replaced([](std::size_t) { return true; }), nullptr,
                                /*allow_exceptions=*/false);
  if (!root.is_object()) return std::nullopt;
  const auto each = [&](const char* key, const auto& visit) {
    const auto array = root.find(key);
    if (array == root.end() || !array->is_array()) return;
    for (const Json& object : *array) {
      if (!object.is_object()) continue;
      const auto uri = object.find("uri");
      if (uri == object.end() || !uri->is_string()) continue;
      const std::optional<std::size_t> index =
          placeholderNumber(uri->get_ref<const std::string&>());
      if (index && *index < candidates.size()) visit(object, candidates[*index]);
    }
  };
  each("buffers", [](const Json& buffer, Candidate& candidate) {
    const auto length = buffer.find("byteLength");
    if (length == buffer.end() || !length->is_number_unsigned()) return;
    candidate.use = Candidate::Use::Buffer;
    candidate.byteLength = length->get<std::uint64_t>();
  });
  each("images", [](const Json& image, Candidate& candidate) {
    if (!image.contains("bufferView")) candidate.use = Candidate::Use::Image;
  });

  for (std::size_t i = 0; i < candidates.size(); ++i) {
    Candidate& candidate = candidates[i];
    if (candidate.use == Candidate::Use::None) continue;
    const std::string_view content =
        json.substr(candidate.open + 1, candidate.close - candidate.open - 1);
    const std::string_view text = content.substr(candidate.type->header.size());
    std::size_t lettersEnd = 0;
    std::vector<unsigned char> bytes = decodeLetters(text, &lettersEnd);
    const bool plain = std::all_of(text.begin() + static_cast<std::ptrdiff_t>(lettersEnd),
                                   text.end(), plainStringByte);
    // tinygltf refuses a data: URI without bytes, and a buffer's of another length.
    const bool decodes = !bytes.empty() && (candidate.use == Candidate::Use::Image ||
                                            bytes.size() == candidate.byteLength);
    if (!plain || !decodes) {
      candidate.use = Candidate::Use::None;
      continue;
    }
    Payload payload;
    payload.number = i;
    payload.image = candidate.use == Candidate::Use::Image;
    if (!payload.image) payload.uri = std::string(content);
    payload.mimeType = std::string(candidate.type->mimeType);
    payload.bytes = std::move(bytes);
    payloads_.push_back(std::move(payload));
  }
  // A candidate left in place that is not a valid JSON string (a control character, a bad
  // escape) breaks the JSON; tinygltf's message then gives a position, which the shorter JSON
  // would move. Only strings with other than plain bytes are parsed to know.
  for (const Candidate& candidate : candidates) {
    if (candidate.use != Candidate::Use::None) continue;
    const std::string_view string =
        json.substr(candidate.open, candidate.close - candidate.open + 1);
    if (!std::all_of(string.begin() + 1, string.end() - 1, plainStringByte) &&
        !Json::accept(string)) {
      payloads_.clear();
      return std::nullopt;
    }
  }
  if (payloads_.empty()) return std::nullopt;
  return replaced([&](std::size_t i) { return candidates[i].use != Candidate::Use::None; });
}

std::size_t DataUris::indexNamed(std::string_view name) const {
  // Payloads are in the order of their numbers: found by a binary search, since tinygltf looks
  // up every one of a file's buffers and images.
  const std::optional<std::size_t> number = placeholderNumber(name);
  if (!number) return payloads_.size();
  const auto found =
      std::lower_bound(payloads_.begin(), payloads_.end(), *number,
                       [](const Payload& payload, std::size_t n) { return payload.number < n; });
  return found != payloads_.end() && found->number == *number
             ? static_cast<std::size_t>(found - payloads_.begin())
             : payloads_.size();
}

DataUris::Payload* DataUris::find(std::string_view filepath) {
  const std::size_t slash = filepath.rfind('/');
  const std::size_t i =
      indexNamed(slash == std::string_view::npos ? filepath : filepath.substr(slash + 1));
  return i < payloads_.size() ? &payloads_[i] : nullptr;
}

void DataUris::restore(tinygltf::Model& model) {
  for (tinygltf::Buffer& buffer : model.buffers) {
    const std::size_t i = indexNamed(buffer.uri);
    if (i < payloads_.size() && !payloads_[i].image) buffer.uri = std::move(payloads_[i].uri);
  }
  for (tinygltf::Image& image : model.images) restoreImage(image);
}

bool DataUris::restoreImage(tinygltf::Image& image) const {
  const std::size_t i = indexNamed(image.uri);
  if (i >= payloads_.size() || !payloads_[i].image) return false;
  image.uri.clear();
  image.mimeType = payloads_[i].mimeType;
  return true;
}

}  // namespace omnishadow::gltf_detail
