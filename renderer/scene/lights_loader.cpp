#include "renderer/scene/lights_loader.h"

#include <algorithm>
#include <array>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <initializer_list>
#include <limits>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <system_error>
#include <utility>

#include "renderer/core/errors.h"
#include "renderer/core/input_file.h"
#include "renderer/core/json_depth.h"

namespace omnishadow {
namespace {

// ordered_json keeps the file's key order, so unknown-field warnings come out in reading order.
using Json = nlohmann::ordered_json;

constexpr float kHalfPi = 1.5707963267948966f;
constexpr int kMaxShadowResolution = 16384;
constexpr double kMaxFilterRadius = 64.0;  // texels
// Values quoted back in messages are cut to this many bytes so that a message stays short.
constexpr std::size_t kMaxQuotedBytes = 40;
constexpr std::size_t kMaxSyntaxReasonBytes = 120;

// ---------------------------------------------------------------------------------------------
// Text helpers for messages

// Cuts `text` to at most `limit` bytes without splitting a UTF-8 sequence.
std::string truncated(std::string_view text, std::size_t limit) {
  if (text.size() <= limit) return std::string(text);
  std::size_t cut = limit;
  while (cut > 0 && (static_cast<unsigned char>(text[cut]) & 0xC0) == 0x80) --cut;
  return std::string(text.substr(0, cut)) + "...";
}

// Messages are printed on one line by the CLI, so no control characters may slip through.
std::string oneLine(std::string text) {
  std::replace_if(
      text.begin(), text.end(), [](char c) { return static_cast<unsigned char>(c) < 0x20; }, ' ');
  return text;
}

// What the file contained, for "got ..." in messages. JSON-dumped, so strings keep their quotes
// and escapes (which also keeps them on one line).
std::string quoted(const Json& value) {
  return truncated(value.dump(-1, ' ', false, Json::error_handler_t::replace), kMaxQuotedBytes);
}

// Shortest text that reads back as the same float: the stored 0.05f prints as "0.05", not as
// 0.05000000074505806.
std::string formatNumber(float value) {
  std::array<char, 32> buffer{};
  const auto result = std::to_chars(buffer.data(), buffer.data() + buffer.size(), value);
  return std::string(buffer.data(), result.ptr);
}

// Field names go into paths as written when they look like identifiers; anything else is quoted
// so that the path stays unambiguous and on one line.
std::string pathComponent(std::string_view key) {
  const bool plain = !key.empty() && std::all_of(key.begin(), key.end(), [](char c) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' ||
           c == '-';
  });
  if (plain) return "." + std::string(key);
  return "[" + quoted(Json(std::string(key))) + "]";
}

// ---------------------------------------------------------------------------------------------
// JSON syntax

// 1-based "line:column" of a byte offset. Columns count bytes, like most editors' byte columns.
std::string lineAndColumn(std::string_view text, std::size_t offset) {
  offset = std::min(offset, text.size());
  const std::string_view before = text.substr(0, offset);
  const auto line = 1 + std::count(before.begin(), before.end(), '\n');
  const std::size_t lastNewline = before.rfind('\n');
  const std::size_t column =
      lastNewline == std::string_view::npos ? offset + 1 : offset - lastNewline;
  return std::to_string(line) + ":" + std::to_string(column);
}

// nlohmann's message reads "[json.exception.parse_error.101] parse error at line 4, column 0:
// syntax error while parsing value - invalid literal; last read: 'tru'". Its position is
// replaced by ours (nlohmann reports column 0 when the offending byte is a newline) and the
// "while parsing value" part says nothing to a user, so only the tail is kept.
std::string shortSyntaxReason(std::string_view what) {
  if (what.starts_with("[json.exception.")) {
    if (const auto end = what.find("] "); end != std::string_view::npos)
      what.remove_prefix(end + 2);
  }
  if (what.starts_with("parse error")) {
    if (const auto colon = what.find(": "); colon != std::string_view::npos) {
      what.remove_prefix(colon + 2);
    }
  }
  if (what.starts_with("syntax error while parsing ")) {
    if (const auto dash = what.find(" - "); dash != std::string_view::npos) {
      what.remove_prefix(dash + 3);
    }
  }
  return oneLine(truncated(what, kMaxSyntaxReasonBytes));
}

// nlohmann rejects a number that overflows a double (1e999) with an out_of_range exception that
// carries no position. Its SAX interface does report one, so on that error the text is run
// through this handler, which does nothing but remember where parsing stopped.
class ErrorLocator : public nlohmann::json_sax<Json> {
 public:
  bool null() override { return true; }
  bool boolean(bool) override { return true; }
  bool number_integer(number_integer_t) override { return true; }
  bool number_unsigned(number_unsigned_t) override { return true; }
  bool number_float(number_float_t, const string_t&) override { return true; }
  bool string(string_t&) override { return true; }
  bool binary(binary_t&) override { return true; }
  bool start_object(std::size_t) override { return true; }
  bool key(string_t&) override { return true; }
  bool end_object() override { return true; }
  bool start_array(std::size_t) override { return true; }
  bool end_array() override { return true; }

  bool parse_error(std::size_t position, const std::string& lastToken,
                   const nlohmann::json::exception&) override {
    // `position` counts the bytes read up to the token's last byte; point at its first byte.
    offset = position >= lastToken.size() ? position - lastToken.size() : 0;
    token = lastToken;
    return false;
  }

  std::size_t offset = 0;
  std::string token;
};

Json parseJson(std::string_view text, const std::string& label) {
  // Before the parser: nlohmann's dump(), which quotes values in messages, recurses per level.
  if (const std::size_t deep = findExcessiveNesting(text); deep != std::string_view::npos) {
    throw InputError(label + ":" + excessiveNestingMessage(text, deep));
  }
  try {
    return Json::parse(text);
  } catch (const Json::parse_error& error) {
    // `byte` is the 1-based index of the byte that made parsing fail.
    const std::size_t offset = error.byte > 0 ? error.byte - 1 : 0;
    throw InputError(label + ":" + lineAndColumn(text, offset) +
                     ": JSON syntax error: " + shortSyntaxReason(error.what()));
  } catch (const Json::out_of_range& error) {
    ErrorLocator locator;
    if (Json::sax_parse(text, &locator)) {
      throw InputError(label + ": JSON error: " + shortSyntaxReason(error.what()));
    }
    throw InputError(label + ":" + lineAndColumn(text, locator.offset) +
                     ": expected a finite number, got " +
                     oneLine(truncated(locator.token, kMaxQuotedBytes)));
  }
}

// ---------------------------------------------------------------------------------------------
// Reading values with their JSON path

// Where messages go: the file label for errors, and the warnings collected so far.
struct MessageContext {
  std::string label;
  std::vector<std::string> warnings;
};

// A JSON value together with its path in the file ("lights[2].position"), so that every message
// can name the field it is about.
class Reader {
 public:
  Reader(const Json& value, std::string path, MessageContext& context)
      : value_(value), path_(std::move(path)), context_(context) {}

  const Json& value() const { return value_; }

  // The path of member `key` of this object, whether or not it is present.
  std::string pathOf(std::string_view key) const {
    std::string component = pathComponent(key);
    // At the top level, paths start with the bare field name: "ambient", not ".ambient".
    if (path_.empty() && component.starts_with('.')) component.erase(0, 1);
    return path_ + component;
  }

  // Member `key` of this object, or nothing when the file leaves it out (the default applies).
  std::optional<Reader> field(std::string_view key) const {
    const auto it = value_.find(key);
    if (it == value_.end()) return std::nullopt;
    return Reader(*it, pathOf(key), context_);
  }

  Reader element(std::size_t index) const { return Reader(value_[index], pathOf(index), context_); }

  std::string pathOf(std::size_t index) const { return path_ + "[" + std::to_string(index) + "]"; }

  // Throws "<label>: <path>: <message>".
  [[noreturn]] void fail(std::string_view message) const { failAt(path_, message); }

  // Same, quoting what the file contained: "<label>: <path>: <expectation>, got <value>".
  [[noreturn]] void failGot(std::string_view expectation) const {
    fail(std::string(expectation) + ", got " + quoted(value_));
  }

  [[noreturn]] void failAt(const std::string& path, std::string_view message) const {
    throw InputError(context_.label + ": " + (path.empty() ? "(top level)" : path) + ": " +
                     std::string(message));
  }

  // Misspelled fields would otherwise be silently ignored, so each one gets a warning.
  void warnUnknownFields(std::initializer_list<std::string_view> known) const {
    for (auto it = value_.begin(); it != value_.end(); ++it) {
      if (std::find(known.begin(), known.end(), it.key()) != known.end()) continue;
      context_.warnings.push_back(context_.label + ": " + pathOf(it.key()) +
                                  ": unknown field, ignored");
    }
  }

 private:
  const Json& value_;
  std::string path_;
  MessageContext& context_;
};

// A number that stays finite once stored as a float: 1e300 is a finite double but not a float.
std::optional<double> finiteNumber(const Json& value) {
  if (!value.is_number()) return std::nullopt;
  const double number = value.get<double>();
  if (!std::isfinite(number) || std::abs(number) > std::numeric_limits<float>::max()) {
    return std::nullopt;
  }
  return number;
}

float readNonNegative(const Reader& reader) {
  const auto number = finiteNumber(reader.value());
  if (!number || *number < 0.0) reader.failGot("expected a finite number >= 0");
  return static_cast<float>(*number);
}

float readInRange(const Reader& reader, double low, double high) {
  const auto number = finiteNumber(reader.value());
  if (!number || *number < low || *number > high) {
    reader.failGot("expected a number in [" + formatNumber(static_cast<float>(low)) + ", " +
                   formatNumber(static_cast<float>(high)) + "]");
  }
  return static_cast<float>(*number);
}

float readPositive(const Reader& reader) {
  const auto number = finiteNumber(reader.value());
  if (!number || *number <= 0.0) reader.failGot("expected a finite number > 0");
  return static_cast<float>(*number);
}

bool readBool(const Reader& reader) {
  if (!reader.value().is_boolean()) reader.failGot("expected true or false");
  return reader.value().get<bool>();
}

std::string readName(const Reader& reader) {
  const Json& value = reader.value();
  if (!value.is_string() || value.get_ref<const std::string&>().empty()) {
    reader.failGot("expected a non-empty string");
  }
  return value.get<std::string>();
}

// One of a fixed set of strings, spelled as toString() in light.h spells them.
template <typename Enum>
Enum readChoice(const Reader& reader, std::initializer_list<Enum> choices,
                std::string_view expectation) {
  if (reader.value().is_string()) {
    const auto& text = reader.value().get_ref<const std::string&>();
    for (const Enum choice : choices) {
      if (text == toString(choice)) return choice;
    }
  }
  reader.failGot(expectation);
}

enum class VectorRule { Any, NonNegative, NonZero };

// Arrays are reported without their content: the fault could be the length or any element.
glm::dvec3 readVector(const Reader& reader, VectorRule rule) {
  const char* expectation = "expected an array of 3 finite numbers";
  if (rule == VectorRule::NonNegative) expectation = "expected an array of 3 finite numbers >= 0";
  if (rule == VectorRule::NonZero) {
    expectation = "expected an array of 3 finite numbers, not all zero";
  }

  const Json& value = reader.value();
  if (!value.is_array() || value.size() != 3) reader.fail(expectation);
  glm::dvec3 vector{0.0};
  for (int i = 0; i < 3; ++i) {
    const auto number = finiteNumber(value[static_cast<std::size_t>(i)]);
    if (!number || (rule == VectorRule::NonNegative && *number < 0.0)) reader.fail(expectation);
    vector[i] = *number;
  }
  if (rule == VectorRule::NonZero && vector == glm::dvec3(0.0)) reader.fail(expectation);
  return vector;
}

glm::vec3 readDirection(const Reader& reader) {
  const glm::dvec3 direction = readVector(reader, VectorRule::NonZero);
  // hypot in double: squaring a tiny float component like 1e-30 would underflow to a zero
  // length and normalize to NaN.
  const double length = std::hypot(direction.x, direction.y, direction.z);
  return glm::vec3(direction / length);
}

// ---------------------------------------------------------------------------------------------
// The file's structure

// An integer in [low, high].
int readInteger(const Reader& reader, int low, int high) {
  const auto number = finiteNumber(reader.value());
  if (!number || *number != std::floor(*number) || *number < low || *number > high) {
    reader.failGot("expected an integer in [" + std::to_string(low) + ", " + std::to_string(high) +
                   "]");
  }
  return static_cast<int>(*number);
}

int readResolution(const Reader& reader) {
  return readInteger(reader, 1, kMaxShadowResolution);
}

float readUnitInterval(const Reader& reader) {
  const auto number = finiteNumber(reader.value());
  if (!number || *number < 0.0 || *number > 1.0) reader.failGot("expected a number in [0, 1]");
  return static_cast<float>(*number);
}

ShadowSettings readShadow(const Reader& reader) {
  ShadowSettings shadow;
  if (reader.value().is_boolean()) {
    shadow.enabled = reader.value().get<bool>();
    return shadow;
  }
  if (!reader.value().is_object()) reader.failGot("expected true, false or an object");
  reader.warnUnknownFields({"enabled", "resolution", "near", "far", "bias", "slopeBias", "minBias",
                            "normalBias", "polygonOffset", "cullFace", "depthFormat", "filter",
                            "filterRadius", "samples", "radius", "bleedReduction", "cascades",
                            "cascadeSplit", "distance"});

  if (auto field = reader.field("enabled")) shadow.enabled = readBool(*field);
  if (auto field = reader.field("resolution")) shadow.resolution = readResolution(*field);
  if (auto field = reader.field("near")) shadow.near = readPositive(*field);
  if (auto field = reader.field("far")) {
    // Compared as stored (float): a far plane that rounds onto the near plane is no range at all.
    const auto far = finiteNumber(field->value());
    if (shadow.near == 0.0f && (!far || !(static_cast<float>(*far) > 0.0f)))
      field->failGot("expected a finite number > 0");
    if (!far || !(static_cast<float>(*far) > shadow.near)) {
      field->failGot("expected a number greater than near (" + formatNumber(shadow.near) + ")");
    }
    shadow.far = static_cast<float>(*far);
  }
  if (auto field = reader.field("bias")) shadow.bias = readNonNegative(*field);
  if (auto field = reader.field("slopeBias")) shadow.slopeBias = readNonNegative(*field);
  if (auto field = reader.field("minBias")) shadow.minBias = readNonNegative(*field);
  if (auto field = reader.field("normalBias")) shadow.normalBias = readNonNegative(*field);
  if (auto field = reader.field("polygonOffset")) {
    const Json& value = field->value();
    if (!value.is_array() || value.size() != 2 || !finiteNumber(value[0]) ||
        !finiteNumber(value[1])) {
      field->failGot("expected [factor, units], two finite numbers");
    }
    shadow.polygonOffsetFactor = static_cast<float>(value[0].get<double>());
    shadow.polygonOffsetUnits = static_cast<float>(value[1].get<double>());
  }
  if (auto field = reader.field("cullFace")) {
    shadow.cullFace = readChoice(*field, {CullFace::None, CullFace::Back, CullFace::Front},
                                 R"(expected "none", "back" or "front")");
  }
  if (auto field = reader.field("depthFormat")) {
    shadow.depthFormat = readChoice(*field, {DepthFormat::Float32, DepthFormat::Fixed24},
                                    R"(expected "32f" or "24")");
  }
  if (auto field = reader.field("filter")) {
    shadow.filter = readChoice(*field,
                               {ShadowFilter::Hard, ShadowFilter::Pcf, ShadowFilter::PcfDisk,
                                ShadowFilter::Poisson, ShadowFilter::Pcss, ShadowFilter::Vsm},
                               R"(expected "hard", "pcf", "pcf-disk", "poisson", "pcss" or "vsm")");
  }
  // vsm blurs with about 2 x filterRadius taps per texel and pass: 1e4 ran for minutes.
  if (auto field = reader.field("filterRadius")) {
    shadow.filterRadius = readInRange(*field, 0.0, kMaxFilterRadius);
  }
  if (auto field = reader.field("samples")) shadow.samples = readInteger(*field, 1, 64);
  if (auto field = reader.field("radius")) shadow.radius = readNonNegative(*field);
  if (auto field = reader.field("bleedReduction")) {
    const auto number = finiteNumber(field->value());
    if (!number || *number < 0.0 || *number >= 1.0) field->failGot("expected a number in [0, 1)");
    shadow.bleedReduction = static_cast<float>(*number);
  }
  if (auto field = reader.field("cascades")) shadow.cascades = readInteger(*field, 1, 4);
  if (auto field = reader.field("cascadeSplit")) shadow.cascadeSplit = readUnitInterval(*field);
  if (auto field = reader.field("distance")) shadow.distance = readNonNegative(*field);
  return shadow;
}

// The spot cone needs 0 <= inner < outer <= pi/2. A violation is reported on a field the file
// actually contains, so that a bad inner angle is not blamed on the default outer one.
void readConeAngles(const Reader& reader, Light& light) {
  const auto innerField = reader.field("innerConeAngle");
  const auto outerField = reader.field("outerConeAngle");
  if (innerField) {
    const auto inner = finiteNumber(innerField->value());
    if (!inner || *inner < 0.0 || !(static_cast<float>(*inner) < kHalfPi)) {
      innerField->failGot("expected a finite number in [0, pi/2)");
    }
    light.innerConeAngle = static_cast<float>(*inner);
  }
  if (outerField) {
    const auto outer = finiteNumber(outerField->value());
    if (!outer || !(static_cast<float>(*outer) > light.innerConeAngle) ||
        static_cast<float>(*outer) > kHalfPi) {
      outerField->failGot("expected a number greater than innerConeAngle (" +
                          formatNumber(light.innerConeAngle) + ") and at most pi/2");
    }
    light.outerConeAngle = static_cast<float>(*outer);
  } else if (innerField && !(light.innerConeAngle < light.outerConeAngle)) {
    innerField->failGot("expected a number less than outerConeAngle (" +
                        formatNumber(light.outerConeAngle) + ")");
  }
}

Light readLight(const Reader& reader, std::size_t index, const std::string& origin) {
  if (!reader.value().is_object()) reader.failGot("expected a light object");
  // Cone angles and direction are accepted (and checked) on every type: switching a light's
  // type should not turn its other fields into warnings.
  reader.warnUnknownFields({"name", "type", "position", "direction", "color", "intensity", "range",
                            "innerConeAngle", "outerConeAngle", "shadow", "translucentShadows"});

  Light light;
  light.name = "light" + std::to_string(index);
  light.origin = origin;
  if (auto field = reader.field("name")) light.name = readName(*field);
  if (auto field = reader.field("type")) {
    light.type = readChoice(*field, {LightType::Point, LightType::Spot, LightType::Directional},
                            R"(expected "point", "spot" or "directional")");
  }
  if (auto field = reader.field("position")) {
    light.position = glm::vec3(readVector(*field, VectorRule::Any));
  }
  if (auto field = reader.field("direction")) light.direction = readDirection(*field);
  if (auto field = reader.field("color")) {
    light.color = glm::vec3(readVector(*field, VectorRule::NonNegative));
  }
  if (auto field = reader.field("intensity")) light.intensity = readNonNegative(*field);
  if (auto field = reader.field("range")) light.range = readPositive(*field);
  readConeAngles(reader, light);
  if (auto field = reader.field("shadow")) light.shadow = readShadow(*field);
  if (auto field = reader.field("translucentShadows")) light.shadow.translucent = readBool(*field);
  return light;
}

std::vector<Light> readLights(const Reader& reader, const std::string& origin) {
  if (!reader.value().is_array()) reader.fail("expected an array of light objects");

  std::vector<Light> lights;
  // Default names take part too: an unnamed lights[1] ("light1") clashes with an explicit
  // "light1" just as two explicit names would.
  std::map<std::string, std::size_t, std::less<>> indexByName;
  for (std::size_t i = 0; i < reader.value().size(); ++i) {
    const Reader element = reader.element(i);
    Light light = readLight(element, i, origin);
    const auto [existing, inserted] = indexByName.emplace(light.name, i);
    if (!inserted) {
      element.failAt(element.pathOf("name"), "duplicate name " + quoted(Json(light.name)) +
                                                 " (also " + reader.pathOf(existing->second) + ")");
    }
    lights.push_back(std::move(light));
  }
  return lights;
}

EnvironmentLight readEnvironment(const Reader& reader, const std::string& origin) {
  if (!reader.value().is_object()) reader.failGot("expected an environment object");
  reader.warnUnknownFields({"image", "color", "intensity", "rotation", "background", "sun"});
  EnvironmentLight environment;
  environment.origin = origin;
  if (auto field = reader.field("image")) {
    const std::string path = readName(*field);
    if (path.find('\0') != std::string::npos) field->failGot("expected a file path");
    environment.image = path;
  }
  if (auto field = reader.field("color")) {
    environment.color = glm::vec3(readVector(*field, VectorRule::NonNegative));
  }
  if (auto field = reader.field("intensity")) environment.intensity = readNonNegative(*field);
  // Degrees in the file, as a person turns a panorama; any finite angle.
  if (auto field = reader.field("rotation")) {
    const auto degrees = finiteNumber(field->value());
    if (!degrees) field->failGot("expected a finite number of degrees");
    environment.rotation = static_cast<float>(glm::radians(std::remainder(*degrees, 360.0)));
  }
  if (auto field = reader.field("background")) environment.background = readBool(*field);
  if (auto field = reader.field("sun")) environment.sun = readBool(*field);
  return environment;
}

// true: the defaults; false: none; or an object of the fields.
std::optional<AmbientOcclusion> readAmbientOcclusion(const Reader& reader) {
  if (reader.value().is_boolean())
    return readBool(reader) ? std::optional(AmbientOcclusion{}) : std::nullopt;
  if (!reader.value().is_object()) reader.failGot("expected true, false or an object");
  reader.warnUnknownFields({"radius", "strength"});
  AmbientOcclusion occlusion;
  if (auto field = reader.field("radius")) occlusion.radius = readPositive(*field);
  if (auto field = reader.field("strength")) occlusion.strength = readUnitInterval(*field);
  return occlusion;
}

LightSetup readSetup(const Reader& root, const std::string& origin) {
  if (!root.value().is_object()) root.fail("expected a JSON object");
  root.warnUnknownFields({"ambient", "environment", "ambient_occlusion", "lights"});

  LightSetup setup;
  if (auto field = root.field("environment")) {
    setup.environment = readEnvironment(*field, origin);
    // The environment lights what the constant ambient stood in for.
    setup.ambient = glm::vec3(0.0f);
  }
  if (auto field = root.field("ambient")) {
    setup.ambient = glm::vec3(readVector(*field, VectorRule::NonNegative));
  }
  if (auto field = root.field("ambient_occlusion"))
    setup.ambientOcclusion = readAmbientOcclusion(*field);
  if (auto field = root.field("lights")) setup.lights = readLights(*field, origin);
  return setup;
}

// ---------------------------------------------------------------------------------------------
// Files

// A lights file is a few KB; the bound keeps -l /dev/zero or a huge file from filling memory.
constexpr std::uint64_t kMaxLightsFileBytes = 64 << 20;

std::string readFile(const std::filesystem::path& path) {
  std::string text;
  int error = 0;
  if (std::string why = readRegularFile(path, kMaxLightsFileBytes, text, &error); !why.empty()) {
    throw InputError(path.string() + ": cannot read lights file: " +
                     (error != 0 ? std::generic_category().message(error) : why));
  }
  return text;
}

}  // namespace

LightSetup loadLightsFile(const std::filesystem::path& path, std::vector<std::string>& warnings) {
  LightSetup setup = parseLights(readFile(path), path.string(), warnings);
  // A file names its environment image as it names it to a person: beside the file.
  if (setup.environment && setup.environment->image.is_relative() &&
      !setup.environment->image.empty())
    setup.environment->image = path.parent_path() / setup.environment->image;
  return setup;
}

LightSetup parseLights(std::string_view text, std::string_view fileLabel,
                       std::vector<std::string>& warnings) {
  MessageContext context{std::string(fileLabel), {}};
  const Json document = parseJson(text, context.label);
  LightSetup setup = readSetup(Reader(document, "", context), context.label);
  // Warnings are handed out only once the file has loaded, so a failed load leaves `warnings`
  // as it was.
  warnings.insert(warnings.end(), context.warnings.begin(), context.warnings.end());
  return setup;
}

}  // namespace omnishadow
