#include "renderer/scene/lights_loader.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "renderer/core/errors.h"
#include "renderer/scene/light.h"

namespace lights_loader_test {

namespace {

using omnishadow::CullFace;
using omnishadow::DepthFormat;
using omnishadow::InputError;
using omnishadow::Light;
using omnishadow::LightSetup;
using omnishadow::LightType;
using omnishadow::ShadowFilter;
using omnishadow::ShadowSettings;

constexpr std::string_view kLabel = "lights.json";
constexpr float kPi = 3.14159265358979323846f;

LightSetup parse(std::string_view text) {
  std::vector<std::string> warnings;
  return omnishadow::parseLights(text, kLabel, warnings);
}

std::vector<std::string> warningsOf(std::string_view text) {
  std::vector<std::string> warnings;
  omnishadow::parseLights(text, kLabel, warnings);
  return warnings;
}

// The message of the InputError that parsing `text` throws, so that tests can compare it whole.
std::string errorOf(std::string_view text) {
  std::vector<std::string> warnings;
  try {
    omnishadow::parseLights(text, kLabel, warnings);
  } catch (const InputError& error) {
    return error.what();
  }
  return "(no error)";
}

void expectVec3(const glm::vec3& actual, float x, float y, float z) {
  EXPECT_NEAR(actual.x, x, 1e-6f);
  EXPECT_NEAR(actual.y, y, 1e-6f);
  EXPECT_NEAR(actual.z, z, 1e-6f);
}

// The shadow settings most tests look at; `enabled` is expected true.
struct ExpectedShadow {
  int resolution;
  float near, far, bias, slopeBias;
  ShadowFilter filter;
};

void expectShadow(const ShadowSettings& actual, const ExpectedShadow& expected) {
  EXPECT_TRUE(actual.enabled);
  EXPECT_EQ(actual.resolution, expected.resolution);
  EXPECT_FLOAT_EQ(actual.near, expected.near);
  EXPECT_FLOAT_EQ(actual.far, expected.far);
  EXPECT_FLOAT_EQ(actual.bias, expected.bias);
  EXPECT_FLOAT_EQ(actual.slopeBias, expected.slopeBias);
  EXPECT_EQ(actual.filter, expected.filter);
}

// ---------------------------------------------------------------------------------------------
// Valid files

TEST(LightsLoader, ParsesTheDocumentedExample) {
  const LightSetup setup = parse(R"({ "ambient": [0.03, 0.03, 0.03],
    "lights": [
      { "name": "lamp", "type": "point", "position": [0, 2.5, 0],
        "color": [1, 0.9, 0.8], "intensity": 40, "range": 20,
        "shadow": { "resolution": 1024, "near": 0.05, "far": 20, "bias": 0.02, "slopeBias": 2,
                    "filter": "pcf" } } ] })");

  expectVec3(setup.ambient, 0.03f, 0.03f, 0.03f);
  ASSERT_EQ(setup.lights.size(), 1u);
  const Light& lamp = setup.lights[0];
  EXPECT_EQ(lamp.name, "lamp");
  EXPECT_EQ(lamp.type, LightType::Point);
  expectVec3(lamp.position, 0.0f, 2.5f, 0.0f);
  expectVec3(lamp.color, 1.0f, 0.9f, 0.8f);
  EXPECT_FLOAT_EQ(lamp.intensity, 40.0f);
  EXPECT_FLOAT_EQ(lamp.range, 20.0f);
  expectShadow(lamp.shadow, {.resolution = 1024,
                             .near = 0.05f,
                             .far = 20.0f,
                             .bias = 0.02f,
                             .slopeBias = 2.0f,
                             .filter = ShadowFilter::Pcf});
  EXPECT_EQ(lamp.origin, "lights.json");
}

TEST(LightsLoader, EmptyObjectGivesDefaultAmbientAndNoLights) {
  std::vector<std::string> warnings;
  const LightSetup setup = omnishadow::parseLights("{}", kLabel, warnings);
  expectVec3(setup.ambient, 0.03f, 0.03f, 0.03f);
  EXPECT_TRUE(setup.lights.empty());
  EXPECT_TRUE(warnings.empty());
}

TEST(LightsLoader, ReadsEveryEnvironmentField) {
  const LightSetup setup = parse(R"({"environment": {"image": "sky.exr", "color": [1, 0.5, 0.25],
                                     "intensity": 2, "rotation": 90, "background": true,
                                     "sun": true}})");
  ASSERT_TRUE(setup.environment);
  EXPECT_EQ(setup.environment->image, "sky.exr");
  expectVec3(setup.environment->color, 1.0f, 0.5f, 0.25f);
  EXPECT_EQ(setup.environment->intensity, 2.0f);
  EXPECT_NEAR(setup.environment->rotation, kPi / 2.0f, 1e-6f);
  EXPECT_TRUE(setup.environment->background);
  EXPECT_TRUE(setup.environment->sun);
  EXPECT_EQ(setup.environment->origin, kLabel);
}

TEST(LightsLoader, EnvironmentDefaultsToAUniformWhiteOneWithoutAmbient) {
  const LightSetup none = parse("{}");
  EXPECT_FALSE(none.environment);
  const LightSetup setup = parse(R"({"environment": {}})");
  ASSERT_TRUE(setup.environment);
  EXPECT_TRUE(setup.environment->image.empty());
  expectVec3(setup.environment->color, 1.0f, 1.0f, 1.0f);
  EXPECT_EQ(setup.environment->intensity, 1.0f);
  EXPECT_EQ(setup.environment->rotation, 0.0f);
  EXPECT_FALSE(setup.environment->background);
  EXPECT_FALSE(setup.environment->sun);
  // The environment stands in for the constant ambient, unless the file asks for both.
  expectVec3(setup.ambient, 0.0f, 0.0f, 0.0f);
  expectVec3(parse(R"({"ambient": [0.1, 0.1, 0.1], "environment": {}})").ambient, 0.1f, 0.1f, 0.1f);
  expectVec3(parse(R"({"environment": {}, "ambient": [0.1, 0.1, 0.1]})").ambient, 0.1f, 0.1f, 0.1f);
}

TEST(LightsLoader, EnvironmentRotationWrapsToAHalfTurnEitherWay) {
  EXPECT_NEAR(parse(R"({"environment": {"rotation": 450}})").environment->rotation, kPi / 2.0f,
              1e-6f);
  EXPECT_NEAR(parse(R"({"environment": {"rotation": -90}})").environment->rotation, -kPi / 2.0f,
              1e-6f);
  EXPECT_NEAR(parse(R"({"environment": {"rotation": 1e30}})").environment->rotation, 0.0f, kPi);
}

TEST(LightsLoader, WarnsAboutUnknownEnvironmentFields) {
  EXPECT_EQ(warningsOf(R"({"environment": {"imgae": "sky.hdr"}})"),
            std::vector<std::string>{"lights.json: environment.imgae: unknown field, ignored"});
}

TEST(LightsLoader, ReadsAmbientOcclusion) {
  EXPECT_FALSE(parse("{}").ambientOcclusion);
  EXPECT_FALSE(parse(R"({"ambient_occlusion": false})").ambientOcclusion);
  const LightSetup defaults = parse(R"({"ambient_occlusion": true})");
  ASSERT_TRUE(defaults.ambientOcclusion);
  EXPECT_EQ(defaults.ambientOcclusion->radius, 0.0f);  // from the scene's size
  EXPECT_EQ(defaults.ambientOcclusion->strength, 1.0f);
  const LightSetup set = parse(R"({"ambient_occlusion": {"radius": 0.25, "strength": 0.5}})");
  ASSERT_TRUE(set.ambientOcclusion);
  EXPECT_EQ(set.ambientOcclusion->radius, 0.25f);
  EXPECT_EQ(set.ambientOcclusion->strength, 0.5f);
  EXPECT_EQ(parse(R"({"ambient_occlusion": {}})").ambientOcclusion->radius, 0.0f);
  // The ambient stays as it was: the occlusion darkens it, not replaces it.
  expectVec3(defaults.ambient, 0.03f, 0.03f, 0.03f);
  EXPECT_EQ(
      warningsOf(R"({"ambient_occlusion": {"radious": 1}})"),
      std::vector<std::string>{"lights.json: ambient_occlusion.radious: unknown field, ignored"});

  omnishadow::Bounds bounds;
  bounds.extend(glm::vec3(0.0f));
  bounds.extend(glm::vec3(3.0f, 4.0f, 0.0f));  // a diagonal of 5
  EXPECT_FLOAT_EQ(omnishadow::effectiveRadius(omnishadow::AmbientOcclusion{}, bounds), 0.25f);
  EXPECT_EQ(omnishadow::effectiveRadius(omnishadow::AmbientOcclusion{0.5f, 1.0f}, bounds), 0.5f);
  EXPECT_EQ(omnishadow::effectiveRadius(omnishadow::AmbientOcclusion{}, omnishadow::Bounds{}),
            0.0f);
}

TEST(LightsLoader, EmptyLightGetsEveryDefault) {
  const LightSetup setup = parse(R"({"lights": [{}]})");
  ASSERT_EQ(setup.lights.size(), 1u);
  const Light& light = setup.lights[0];
  EXPECT_EQ(light.name, "light0");
  EXPECT_EQ(light.type, LightType::Point);
  expectVec3(light.position, 0.0f, 0.0f, 0.0f);
  expectVec3(light.direction, 0.0f, 0.0f, -1.0f);
  expectVec3(light.color, 1.0f, 1.0f, 1.0f);
  EXPECT_FLOAT_EQ(light.intensity, 1.0f);
  EXPECT_FLOAT_EQ(light.range, 0.0f);
  EXPECT_FLOAT_EQ(light.innerConeAngle, 0.0f);
  EXPECT_FLOAT_EQ(light.outerConeAngle, kPi / 4);
  expectShadow(light.shadow, {.resolution = 1024,
                              .near = 0.0f,
                              .far = 0.0f,
                              .bias = 0.0f,
                              .slopeBias = 2.0f,
                              .filter = ShadowFilter::Pcf});
  EXPECT_EQ(light.origin, "lights.json");
}

TEST(LightsLoader, UnnamedLightsAreNamedByTheirIndex) {
  const LightSetup setup = parse(R"({"lights": [{}, {"name": "key"}, {}]})");
  ASSERT_EQ(setup.lights.size(), 3u);
  EXPECT_EQ(setup.lights[0].name, "light0");
  EXPECT_EQ(setup.lights[1].name, "key");
  EXPECT_EQ(setup.lights[2].name, "light2");
}

TEST(LightsLoader, ParsesSpotLight) {
  const LightSetup setup = parse(R"({"lights": [{"type": "spot", "direction": [0, -2, 0],
      "innerConeAngle": 0.25, "outerConeAngle": 0.5}]})");
  ASSERT_EQ(setup.lights.size(), 1u);
  const Light& spot = setup.lights[0];
  EXPECT_EQ(spot.type, LightType::Spot);
  expectVec3(spot.direction, 0.0f, -1.0f, 0.0f);
  EXPECT_FLOAT_EQ(spot.innerConeAngle, 0.25f);
  EXPECT_FLOAT_EQ(spot.outerConeAngle, 0.5f);
}

TEST(LightsLoader, ParsesDirectionalLight) {
  const LightSetup setup =
      parse(R"({"lights": [{"type": "directional", "direction": [1, 1, 0], "intensity": 3}]})");
  ASSERT_EQ(setup.lights.size(), 1u);
  EXPECT_EQ(setup.lights[0].type, LightType::Directional);
  const float half = std::sqrt(0.5f);
  expectVec3(setup.lights[0].direction, half, half, 0.0f);
  EXPECT_FLOAT_EQ(setup.lights[0].intensity, 3.0f);
}

TEST(LightsLoader, NormalizesDirection) {
  const LightSetup setup = parse(R"({"lights": [{"direction": [0, 3, 4]}]})");
  ASSERT_EQ(setup.lights.size(), 1u);
  expectVec3(setup.lights[0].direction, 0.0f, 0.6f, 0.8f);
}

TEST(LightsLoader, NormalizesTinyDirectionWithoutUnderflow) {
  const LightSetup setup = parse(R"({"lights": [{"direction": [1e-30, 0, -1e-30]}]})");
  ASSERT_EQ(setup.lights.size(), 1u);
  const float half = std::sqrt(0.5f);
  expectVec3(setup.lights[0].direction, half, 0.0f, -half);
}

TEST(LightsLoader, ShadowTrueMeansDefaultShadow) {
  const Light light = parse(R"({"lights": [{"shadow": true}]})").lights.at(0);
  EXPECT_TRUE(light.shadow.enabled);
  EXPECT_EQ(light.shadow.resolution, 1024);
  EXPECT_EQ(light.shadow.filter, ShadowFilter::Pcf);
}

TEST(LightsLoader, ShadowFalseDisablesShadow) {
  const Light light = parse(R"({"lights": [{"shadow": false}]})").lights.at(0);
  EXPECT_FALSE(light.shadow.enabled);
  EXPECT_EQ(light.shadow.resolution, 1024);
}

TEST(LightsLoader, ShadowObjectOverridesOnlyWhatItNames) {
  const Light light =
      parse(R"({"lights": [{"shadow": {"resolution": 512, "filter": "hard"}}]})").lights.at(0);
  expectShadow(light.shadow, {.resolution = 512,
                              .near = 0.0f,
                              .far = 0.0f,
                              .bias = 0.0f,
                              .slopeBias = 2.0f,
                              .filter = ShadowFilter::Hard});
}

TEST(LightsLoader, TranslucentShadowsAreOnUnlessTheLightSaysFalse) {
  const LightSetup setup = parse(
      R"({"lights": [{}, {"translucentShadows": false}, {"translucentShadows": true, "shadow": false}]})");
  EXPECT_TRUE(setup.lights.at(0).shadow.translucent);
  EXPECT_FALSE(setup.lights.at(1).shadow.translucent);
  EXPECT_TRUE(setup.lights.at(2).shadow.translucent);
  EXPECT_FALSE(setup.lights.at(2).shadow.enabled);
  // Read after "shadow", whatever the order in the file.
  EXPECT_FALSE(parse(R"({"lights": [{"translucentShadows": false, "shadow": {"resolution": 64}}]})")
                   .lights.at(0)
                   .shadow.translucent);
}

TEST(LightsLoader, ShadowObjectCanBeDisabled) {
  const Light light = parse(R"({"lights": [{"shadow": {"enabled": false}}]})").lights.at(0);
  EXPECT_FALSE(light.shadow.enabled);
}

struct FilterCase {
  const char* spelling;
  ShadowFilter filter;
};

class ShadowFilterTest : public testing::TestWithParam<FilterCase> {};

TEST_P(ShadowFilterTest, ParsesFilterName) {
  const std::string text =
      std::string(R"({"lights": [{"shadow": {"filter": ")") + GetParam().spelling + R"("}}]})";
  EXPECT_EQ(parse(text).lights.at(0).shadow.filter, GetParam().filter);
}

INSTANTIATE_TEST_SUITE_P(LightsLoader, ShadowFilterTest,
                         testing::Values(FilterCase{"hard", ShadowFilter::Hard},
                                         FilterCase{"pcf", ShadowFilter::Pcf},
                                         FilterCase{"pcf-disk", ShadowFilter::PcfDisk},
                                         FilterCase{"poisson", ShadowFilter::Poisson},
                                         FilterCase{"pcss", ShadowFilter::Pcss},
                                         FilterCase{"vsm", ShadowFilter::Vsm}));

TEST(LightsLoader, ReadsEveryShadowSetting) {
  const Light light = parse(R"({"lights": [{"type": "directional", "shadow": {
      "minBias": 0.25, "normalBias": 2, "polygonOffset": [1.5, -2], "cullFace": "front",
      "depthFormat": "24", "filterRadius": 3, "samples": 32, "radius": 0.2,
      "bleedReduction": 0.4, "cascades": 3, "cascadeSplit": 0.5, "distance": 40}}]})")
                          .lights.at(0);
  const ShadowSettings& s = light.shadow;
  EXPECT_FLOAT_EQ(s.minBias, 0.25f);
  EXPECT_FLOAT_EQ(s.normalBias, 2.0f);
  EXPECT_FLOAT_EQ(s.polygonOffsetFactor, 1.5f);
  EXPECT_FLOAT_EQ(s.polygonOffsetUnits, -2.0f);
  EXPECT_EQ(s.cullFace, CullFace::Front);
  EXPECT_EQ(s.depthFormat, DepthFormat::Fixed24);
  EXPECT_FLOAT_EQ(s.filterRadius, 3.0f);
  EXPECT_EQ(s.samples, 32);
  EXPECT_FLOAT_EQ(s.radius, 0.2f);
  EXPECT_FLOAT_EQ(s.bleedReduction, 0.4f);
  EXPECT_EQ(s.cascades, 3);
  EXPECT_FLOAT_EQ(s.cascadeSplit, 0.5f);
  EXPECT_FLOAT_EQ(s.distance, 40.0f);
}

class IntegerValuedResolutionTest : public testing::TestWithParam<std::pair<const char*, int>> {};

TEST_P(IntegerValuedResolutionTest, AcceptsIntegerValuedNumbers) {
  const std::string text =
      std::string(R"({"lights": [{"shadow": {"resolution": )") + GetParam().first + "}}]}";
  EXPECT_EQ(parse(text).lights.at(0).shadow.resolution, GetParam().second);
}

INSTANTIATE_TEST_SUITE_P(LightsLoader, IntegerValuedResolutionTest,
                         testing::Values(std::pair{"1024", 1024}, std::pair{"1024.0", 1024},
                                         std::pair{"1e3", 1000}, std::pair{"1", 1},
                                         std::pair{"16384", 16384}));

TEST(LightsLoader, AcceptsValuesOnTheBoundaries) {
  const LightSetup setup = parse(R"({"ambient": [0, 0, 0], "lights": [{
      "color": [0, 0, 0], "intensity": 0, "innerConeAngle": 0,
      "outerConeAngle": 1.5707963267948966,
      "shadow": {"near": 0.5, "far": 0.51, "bias": 0, "slopeBias": 0}}]})");
  expectVec3(setup.ambient, 0.0f, 0.0f, 0.0f);
  const Light& light = setup.lights.at(0);
  EXPECT_FLOAT_EQ(light.intensity, 0.0f);
  EXPECT_FLOAT_EQ(light.outerConeAngle, kPi / 2);
  EXPECT_FLOAT_EQ(light.shadow.far, 0.51f);
  EXPECT_FLOAT_EQ(light.shadow.slopeBias, 0.0f);
}

// ---------------------------------------------------------------------------------------------
// Unknown and inapplicable fields

TEST(LightsLoader, WarnsAboutEachUnknownFieldInFileOrder) {
  const std::vector<std::string> warnings = warningsOf(R"({"version": 2, "lights": [
      {"colour": [1, 0, 0], "shadow": {"softness": 3}}, {"intensty": 5}], "comment": "x"})");
  const std::vector<std::string> expected = {
      "lights.json: version: unknown field, ignored",
      "lights.json: comment: unknown field, ignored",
      "lights.json: lights[0].colour: unknown field, ignored",
      "lights.json: lights[0].shadow.softness: unknown field, ignored",
      "lights.json: lights[1].intensty: unknown field, ignored",
  };
  EXPECT_EQ(warnings, expected);
}

TEST(LightsLoader, QuotesUnusualFieldNamesInWarnings) {
  const std::vector<std::string> warnings = warningsOf("{\"lights\": [{\"col our\\n\": 1}]}");
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_EQ(warnings[0], R"(lights.json: lights[0]["col our\n"]: unknown field, ignored)");
}

TEST(LightsLoader, AcceptsFieldsThatDoNotApplyToTheTypeSilently) {
  const std::vector<std::string> warnings = warningsOf(R"({"lights": [
      {"type": "point", "innerConeAngle": 0.1, "outerConeAngle": 0.2, "direction": [0, 1, 0]},
      {"type": "directional", "position": [1, 2, 3], "range": 5}]})");
  EXPECT_TRUE(warnings.empty());
}

TEST(LightsLoader, AppendsWarningsToExistingOnes) {
  std::vector<std::string> warnings = {"earlier"};
  omnishadow::parseLights(R"({"extra": 1})", kLabel, warnings);
  const std::vector<std::string> expected = {"earlier",
                                             "lights.json: extra: unknown field, ignored"};
  EXPECT_EQ(warnings, expected);
}

TEST(LightsLoader, LeavesWarningsUntouchedWhenTheFileIsInvalid) {
  std::vector<std::string> warnings;
  EXPECT_THROW(omnishadow::parseLights(R"({"extra": 1, "lights": 3})", kLabel, warnings),
               InputError);
  EXPECT_TRUE(warnings.empty());
}

// ---------------------------------------------------------------------------------------------
// Invalid content: one row per rule, each with its whole message

struct ErrorCase {
  const char* name;
  const char* json;
  const char* message;  // after "lights.json: "
};

class InvalidContentTest : public testing::TestWithParam<ErrorCase> {};

TEST_P(InvalidContentTest, ReportsFileFieldAndExpectation) {
  const std::string message = errorOf(GetParam().json);
  EXPECT_EQ(message, std::string("lights.json: ") + GetParam().message);
  EXPECT_EQ(message.find('\n'), std::string::npos);
}

const ErrorCase kErrorCases[] = {
    // Structure.
    {"TopLevelArray", "[]", "(top level): expected a JSON object"},
    {"TopLevelString", R"("lamp")", "(top level): expected a JSON object"},
    {"TopLevelNull", "null", "(top level): expected a JSON object"},
    {"LightsObject", R"({"lights": {"name": "lamp"}})",
     "lights: expected an array of light objects"},
    {"LightsNull", R"({"lights": null})", "lights: expected an array of light objects"},
    {"LightNotObject", R"({"lights": [{}, 5]})", "lights[1]: expected a light object, got 5"},
    // environment
    {"EnvironmentNotObject", R"({"environment": "sky.hdr"})",
     "environment: expected an environment object, got \"sky.hdr\""},
    {"EnvironmentImageEmpty", R"({"environment": {"image": ""}})",
     "environment.image: expected a non-empty string, got \"\""},
    {"EnvironmentImageNumber", R"({"environment": {"image": 3}})",
     "environment.image: expected a non-empty string, got 3"},
    {"EnvironmentImageNul", R"({"environment": {"image": "a\u0000b"}})",
     "environment.image: expected a file path, got \"a\\u0000b\""},
    {"EnvironmentColorNegative", R"({"environment": {"color": [1, -1, 1]}})",
     "environment.color: expected an array of 3 finite numbers >= 0"},
    {"EnvironmentIntensityNegative", R"({"environment": {"intensity": -1}})",
     "environment.intensity: expected a finite number >= 0, got -1"},
    {"EnvironmentRotationString", R"({"environment": {"rotation": "90"}})",
     "environment.rotation: expected a finite number of degrees, got \"90\""},
    {"EnvironmentBackgroundNumber", R"({"environment": {"background": 1}})",
     "environment.background: expected true or false, got 1"},
    {"EnvironmentSunString", R"({"environment": {"sun": "yes"}})",
     "environment.sun: expected true or false, got \"yes\""},
    // ambient_occlusion
    {"AmbientOcclusionString", R"({"ambient_occlusion": "on"})",
     "ambient_occlusion: expected true, false or an object, got \"on\""},
    {"AmbientOcclusionRadiusZero", R"({"ambient_occlusion": {"radius": 0}})",
     "ambient_occlusion.radius: expected a finite number > 0, got 0"},
    {"AmbientOcclusionRadiusHuge", R"({"ambient_occlusion": {"radius": 1e300}})",
     "ambient_occlusion.radius: expected a finite number > 0, got 1e+300"},
    {"AmbientOcclusionStrengthAboveOne", R"({"ambient_occlusion": {"strength": 1.5}})",
     "ambient_occlusion.strength: expected a number in [0, 1], got 1.5"},
    // ambient
    {"AmbientTooShort", R"({"ambient": [1, 2]})",
     "ambient: expected an array of 3 finite numbers >= 0"},
    {"AmbientNegative", R"({"ambient": [0, -0.1, 0]})",
     "ambient: expected an array of 3 finite numbers >= 0"},
    {"AmbientString", R"({"ambient": "grey"})",
     "ambient: expected an array of 3 finite numbers >= 0"},
    {"AmbientBeyondFloat", R"({"ambient": [1e300, 0, 0]})",
     "ambient: expected an array of 3 finite numbers >= 0"},
    // name
    {"NameEmpty", R"({"lights": [{"name": ""}]})",
     R"(lights[0].name: expected a non-empty string, got "")"},
    {"NameNumber", R"({"lights": [{"name": 7}]})",
     "lights[0].name: expected a non-empty string, got 7"},
    {"DuplicateName", R"({"lights": [{}, {"name": "lamp"}, {}, {"name": "lamp"}]})",
     R"(lights[3].name: duplicate name "lamp" (also lights[1]))"},
    {"ExplicitNameClashesWithDefault", R"({"lights": [{}, {"name": "light0"}]})",
     R"(lights[1].name: duplicate name "light0" (also lights[0]))"},
    {"DefaultNameClashesWithExplicit", R"({"lights": [{"name": "light1"}, {}]})",
     R"(lights[1].name: duplicate name "light1" (also lights[0]))"},
    // type
    {"TypeUnknown", R"({"lights": [{}, {"type": "area"}]})",
     R"(lights[1].type: expected "point", "spot" or "directional", got "area")"},
    {"TypeWrongCase", R"({"lights": [{"type": "Point"}]})",
     R"(lights[0].type: expected "point", "spot" or "directional", got "Point")"},
    {"TypeNumber", R"({"lights": [{"type": 1}]})",
     R"(lights[0].type: expected "point", "spot" or "directional", got 1)"},
    // position
    {"PositionTooShort", R"({"lights": [{}, {}, {"position": [0, 1]}]})",
     "lights[2].position: expected an array of 3 finite numbers"},
    {"PositionTooLong", R"({"lights": [{"position": [0, 1, 2, 3]}]})",
     "lights[0].position: expected an array of 3 finite numbers"},
    {"PositionNull", R"({"lights": [{"position": [0, 1, null]}]})",
     "lights[0].position: expected an array of 3 finite numbers"},
    {"PositionBool", R"({"lights": [{"position": [0, true, 0]}]})",
     "lights[0].position: expected an array of 3 finite numbers"},
    {"PositionBeyondFloat", R"({"lights": [{"position": [0, -1e39, 0]}]})",
     "lights[0].position: expected an array of 3 finite numbers"},
    // direction
    {"DirectionZero", R"({"lights": [{"direction": [0, 0, 0]}]})",
     "lights[0].direction: expected an array of 3 finite numbers, not all zero"},
    {"DirectionString", R"({"lights": [{"direction": "down"}]})",
     "lights[0].direction: expected an array of 3 finite numbers, not all zero"},
    // color
    {"ColorNegative", R"({"lights": [{"color": [1, -0.5, 1]}]})",
     "lights[0].color: expected an array of 3 finite numbers >= 0"},
    {"ColorTooShort", R"({"lights": [{"color": [1, 1]}]})",
     "lights[0].color: expected an array of 3 finite numbers >= 0"},
    // intensity
    {"IntensityNegative", R"({"lights": [{"intensity": -3}]})",
     "lights[0].intensity: expected a finite number >= 0, got -3"},
    {"IntensityString", R"({"lights": [{"intensity": "bright"}]})",
     R"(lights[0].intensity: expected a finite number >= 0, got "bright")"},
    {"IntensityBeyondFloat", R"({"lights": [{"intensity": 1e39}]})",
     "lights[0].intensity: expected a finite number >= 0, got 1e+39"},
    // range
    {"RangeZero", R"({"lights": [{"range": 0}]})",
     "lights[0].range: expected a finite number > 0, got 0"},
    {"RangeNegative", R"({"lights": [{"range": -1.5}]})",
     "lights[0].range: expected a finite number > 0, got -1.5"},
    // cone angles
    {"InnerConeNegative", R"({"lights": [{"innerConeAngle": -0.1}]})",
     "lights[0].innerConeAngle: expected a finite number in [0, pi/2), got -0.1"},
    {"InnerConeHalfPi", R"({"lights": [{"innerConeAngle": 1.5707963267948966}]})",
     "lights[0].innerConeAngle: expected a finite number in [0, pi/2), got 1.5707963267948966"},
    {"InnerConeNotBelowDefaultOuter", R"({"lights": [{"innerConeAngle": 1}]})",
     "lights[0].innerConeAngle: expected a number less than outerConeAngle (0.7853982), got 1"},
    {"OuterConeAboveHalfPi", R"({"lights": [{"outerConeAngle": 1.6}]})",
     "lights[0].outerConeAngle: expected a number greater than innerConeAngle (0) and at most "
     "pi/2, got 1.6"},
    {"OuterConeZero", R"({"lights": [{"outerConeAngle": 0}]})",
     "lights[0].outerConeAngle: expected a number greater than innerConeAngle (0) and at most "
     "pi/2, got 0"},
    {"OuterConeBelowInner", R"({"lights": [{"innerConeAngle": 0.5, "outerConeAngle": 0.3}]})",
     "lights[0].outerConeAngle: expected a number greater than innerConeAngle (0.5) and at most "
     "pi/2, got 0.3"},
    {"OuterConeEqualsInner", R"({"lights": [{"innerConeAngle": 0.5, "outerConeAngle": 0.5}]})",
     "lights[0].outerConeAngle: expected a number greater than innerConeAngle (0.5) and at most "
     "pi/2, got 0.5"},
    // shadow
    {"ShadowNumber", R"({"lights": [{"shadow": 1}]})",
     "lights[0].shadow: expected true, false or an object, got 1"},
    {"ShadowString", R"({"lights": [{"shadow": "on"}]})",
     R"(lights[0].shadow: expected true, false or an object, got "on")"},
    {"ShadowEnabledNumber", R"({"lights": [{"shadow": {"enabled": 1}}]})",
     "lights[0].shadow.enabled: expected true or false, got 1"},
    {"TranslucentShadowsString", R"({"lights": [{"translucentShadows": "no"}]})",
     R"(lights[0].translucentShadows: expected true or false, got "no")"},
    {"ResolutionFraction", R"({"lights": [{"shadow": {"resolution": 10.5}}]})",
     "lights[0].shadow.resolution: expected an integer in [1, 16384], got 10.5"},
    {"ResolutionZero", R"({"lights": [{"shadow": {"resolution": 0}}]})",
     "lights[0].shadow.resolution: expected an integer in [1, 16384], got 0"},
    {"ResolutionTooLarge", R"({"lights": [{"shadow": {"resolution": 16385}}]})",
     "lights[0].shadow.resolution: expected an integer in [1, 16384], got 16385"},
    {"ResolutionString", R"({"lights": [{"shadow": {"resolution": "1024"}}]})",
     R"(lights[0].shadow.resolution: expected an integer in [1, 16384], got "1024")"},
    {"NearZero", R"({"lights": [{"shadow": {"near": 0}}]})",
     "lights[0].shadow.near: expected a finite number > 0, got 0"},
    {"NearNegative", R"({"lights": [{"shadow": {"near": -0.1}}]})",
     "lights[0].shadow.near: expected a finite number > 0, got -0.1"},
    {"FarZero", R"({"lights": [{"shadow": {"far": 0}}]})",
     "lights[0].shadow.far: expected a finite number > 0, got 0"},
    {"FarNegative", R"({"lights": [{"shadow": {"far": -1}}]})",
     "lights[0].shadow.far: expected a finite number > 0, got -1"},
    {"FarBelowGivenNear", R"({"lights": [{"shadow": {"near": 1, "far": 0.5}}]})",
     "lights[0].shadow.far: expected a number greater than near (1), got 0.5"},
    {"FarEqualsNear", R"({"lights": [{"shadow": {"far": 2, "near": 2}}]})",
     "lights[0].shadow.far: expected a number greater than near (2), got 2"},
    {"FarString", R"({"lights": [{"shadow": {"far": "auto"}}]})",
     R"(lights[0].shadow.far: expected a finite number > 0, got "auto")"},
    {"BiasNegative", R"({"lights": [{"shadow": {"bias": -0.1}}]})",
     "lights[0].shadow.bias: expected a finite number >= 0, got -0.1"},
    {"SlopeBiasNegative", R"({"lights": [{"shadow": {"slopeBias": -1}}]})",
     "lights[0].shadow.slopeBias: expected a finite number >= 0, got -1"},
    {"FilterUnknown", R"({"lights": [{"shadow": {"filter": "box"}}]})",
     R"(lights[0].shadow.filter: expected "hard", "pcf", "pcf-disk", "poisson", "pcss" or "vsm", )"
     R"(got "box")"},
    {"FilterBool", R"({"lights": [{"shadow": {"filter": true}}]})",
     R"(lights[0].shadow.filter: expected "hard", "pcf", "pcf-disk", "poisson", "pcss" or "vsm", )"
     R"(got true)"},
    {"MinBiasNegative", R"({"lights": [{"shadow": {"minBias": -1}}]})",
     "lights[0].shadow.minBias: expected a finite number >= 0, got -1"},
    {"NormalBiasString", R"({"lights": [{"shadow": {"normalBias": "1"}}]})",
     R"(lights[0].shadow.normalBias: expected a finite number >= 0, got "1")"},
    {"PolygonOffsetScalar", R"({"lights": [{"shadow": {"polygonOffset": 2}}]})",
     "lights[0].shadow.polygonOffset: expected [factor, units], two finite numbers, got 2"},
    {"PolygonOffsetThree", R"({"lights": [{"shadow": {"polygonOffset": [1, 2, 3]}}]})",
     "lights[0].shadow.polygonOffset: expected [factor, units], two finite numbers, got [1,2,3]"},
    {"CullFaceUnknown", R"({"lights": [{"shadow": {"cullFace": "both"}}]})",
     R"(lights[0].shadow.cullFace: expected "none", "back" or "front", got "both")"},
    {"DepthFormat16", R"({"lights": [{"shadow": {"depthFormat": "16"}}]})",
     R"(lights[0].shadow.depthFormat: expected "32f" or "24", got "16")"},
    {"SamplesZero", R"({"lights": [{"shadow": {"samples": 0}}]})",
     "lights[0].shadow.samples: expected an integer in [1, 64], got 0"},
    {"SamplesFraction", R"({"lights": [{"shadow": {"samples": 2.5}}]})",
     "lights[0].shadow.samples: expected an integer in [1, 64], got 2.5"},
    {"RadiusNegative", R"({"lights": [{"shadow": {"radius": -0.1}}]})",
     "lights[0].shadow.radius: expected a finite number >= 0, got -0.1"},
    {"BleedReductionOne", R"({"lights": [{"shadow": {"bleedReduction": 1}}]})",
     "lights[0].shadow.bleedReduction: expected a number in [0, 1), got 1"},
    {"CascadesFive", R"({"lights": [{"shadow": {"cascades": 5}}]})",
     "lights[0].shadow.cascades: expected an integer in [1, 4], got 5"},
    {"CascadeSplitAboveOne", R"({"lights": [{"shadow": {"cascadeSplit": 1.5}}]})",
     "lights[0].shadow.cascadeSplit: expected a number in [0, 1], got 1.5"},
    {"DistanceNegative", R"({"lights": [{"shadow": {"distance": -3}}]})",
     "lights[0].shadow.distance: expected a finite number >= 0, got -3"},
};

INSTANTIATE_TEST_SUITE_P(LightsLoader, InvalidContentTest, testing::ValuesIn(kErrorCases),
                         [](const testing::TestParamInfo<ErrorCase>& param) {
                           return std::string(param.param.name);
                         });

TEST(LightsLoader, TruncatesLongValuesInMessages) {
  const std::string longType(100, 'x');
  const std::string message = errorOf(R"({"lights": [{"type": ")" + longType + R"("}]})");
  EXPECT_EQ(message, R"(lights.json: lights[0].type: expected "point", "spot" or "directional", )"
                     R"(got ")" +
                         std::string(39, 'x') + "...");
}

TEST(LightsLoader, UsesTheGivenLabel) {
  std::vector<std::string> warnings;
  try {
    omnishadow::parseLights(R"({"lights": [{"range": 0}]})", "scenes/studio.lights.json", warnings);
    FAIL() << "expected an InputError";
  } catch (const InputError& error) {
    EXPECT_STREQ(error.what(),
                 "scenes/studio.lights.json: lights[0].range: expected a finite number > 0, got 0");
  }
}

// ---------------------------------------------------------------------------------------------
// Malformed JSON

// Syntax errors are nlohmann's words after our position; the test pins the position and checks
// that nlohmann's own prefix is gone.
void expectSyntaxError(std::string_view text, std::string_view position) {
  const std::string message = errorOf(text);
  const std::string prefix = "lights.json:" + std::string(position) + ": JSON syntax error: ";
  EXPECT_EQ(message.substr(0, prefix.size()), prefix) << message;
  EXPECT_GT(message.size(), prefix.size()) << message;
  EXPECT_EQ(message.find("json.exception"), std::string::npos) << message;
  EXPECT_EQ(message.find("parse error at"), std::string::npos) << message;
  EXPECT_EQ(message.find('\n'), std::string::npos) << message;
}

TEST(LightsLoader, ReportsLineAndColumnOfSyntaxErrors) {
  // The missing comma is noticed at the next key, whose last byte is line 3, column 10.
  expectSyntaxError(
      "{\n"
      "  \"ambient\": [0.1, 0.1, 0.1]\n"
      "  \"lights\": []\n"
      "}\n",
      "3:10");
}

TEST(LightsLoader, ReportsTheOffendingCharacterOfABadLiteral) {
  // "4O": the letter O at line 3, column 37.
  expectSyntaxError(
      "{\n"
      "  \"lights\": [\n"
      "    { \"name\": \"lamp\", \"intensity\": 4O }\n"
      "  ]\n"
      "}\n",
      "3:37");
}

TEST(LightsLoader, ReportsAnErrorAtALineEndOnThatLine) {
  // nlohmann itself would say "line 3, column 0" here.
  expectSyntaxError("{\n  \"lights\": [\n    tru\n  ]\n}\n", "3:8");
}

TEST(LightsLoader, RejectsEmptyFile) {
  EXPECT_EQ(errorOf(""),
            "lights.json:1:1: JSON syntax error: unexpected end of input; expected '[', '{', or a "
            "literal");
}

TEST(LightsLoader, RejectsWhitespaceOnlyFile) {
  expectSyntaxError("  \n  ", "2:3");
}

TEST(LightsLoader, RejectsTruncatedFile) {
  expectSyntaxError("{\"lights\": [\n  {}", "2:5");
}

TEST(LightsLoader, RejectsTrailingComma) {
  expectSyntaxError(R"({"lights": [{},]})", "1:16");
}

TEST(LightsLoader, RejectsNaNAndInfinityAsSyntax) {
  expectSyntaxError(R"({"ambient": [NaN, 0, 0]})", "1:14");
  expectSyntaxError(R"({"ambient": [Infinity, 0, 0]})", "1:14");
  expectSyntaxError(R"({"ambient": [-Infinity, 0, 0]})", "1:15");
}

TEST(LightsLoader, RejectsNumbersTooLargeToBeFinite) {
  EXPECT_EQ(errorOf("{\n  \"lights\": [{\"intensity\": 1e999}]\n}"),
            "lights.json:2:28: expected a finite number, got 1e999");
  EXPECT_EQ(errorOf(R"({"ambient": [0, -1e999, 0]})"),
            "lights.json:1:17: expected a finite number, got -1e999");
}

// ---------------------------------------------------------------------------------------------
// Files

class LightsFileTest : public testing::Test {
 protected:
  void SetUp() override {
    const auto* test = testing::UnitTest::GetInstance()->current_test_info();
    directory_ = std::filesystem::path(testing::TempDir()) /
                 (std::string("lights_loader_test_") + test->name());
    std::filesystem::remove_all(directory_);
    std::filesystem::create_directories(directory_);
  }
  void TearDown() override { std::filesystem::remove_all(directory_); }

  std::filesystem::path write(const std::string& name, std::string_view content) {
    const std::filesystem::path path = directory_ / name;
    std::ofstream(path, std::ios::binary) << content;
    return path;
  }

  // The message of the InputError that loading `path` throws; "(no error)" when none.
  static std::string loadError(const std::filesystem::path& path) {
    std::vector<std::string> warnings;
    try {
      omnishadow::loadLightsFile(path, warnings);
    } catch (const InputError& error) {
      return error.what();
    }
    return "(no error)";
  }

  std::filesystem::path directory_;
};

TEST_F(LightsFileTest, LoadsFileAndUsesItsPathAsOrigin) {
  const auto path = write("studio.json", R"({"lights": [{"name": "key", "colour": 1}]})");
  std::vector<std::string> warnings;
  const LightSetup setup = omnishadow::loadLightsFile(path, warnings);
  ASSERT_EQ(setup.lights.size(), 1u);
  EXPECT_EQ(setup.lights[0].name, "key");
  EXPECT_EQ(setup.lights[0].origin, path.string());
  const std::vector<std::string> expected = {path.string() +
                                             ": lights[0].colour: unknown field, ignored"};
  EXPECT_EQ(warnings, expected);
}

TEST_F(LightsFileTest, EnvironmentImageIsFoundBesideTheFile) {
  std::filesystem::create_directories(directory_ / "rig");
  const auto path = write("rig/studio.json", R"({"environment": {"image": "maps/sky.exr"}})");
  std::vector<std::string> warnings;
  const LightSetup setup = omnishadow::loadLightsFile(path, warnings);
  EXPECT_EQ(setup.environment->image, directory_ / "rig" / "maps" / "sky.exr");
  EXPECT_EQ(setup.environment->origin, path.string());
  const auto absolute = write("absolute.json", R"({"environment": {"image": "/srv/sky.exr"}})");
  EXPECT_EQ(omnishadow::loadLightsFile(absolute, warnings).environment->image, "/srv/sky.exr");
}

TEST_F(LightsFileTest, LabelsContentErrorsWithThePath) {
  const auto path = write("bad.json", "{\n  \"ambient\": 1\n}\n");
  EXPECT_EQ(loadError(path),
            path.string() + ": ambient: expected an array of 3 finite numbers >= 0");
}

TEST_F(LightsFileTest, ReportsMissingFile) {
  const auto path = directory_ / "missing.json";
  EXPECT_EQ(loadError(path),
            path.string() + ": cannot read lights file: No such file or directory");
}

TEST_F(LightsFileTest, ReportsDirectory) {
  EXPECT_EQ(loadError(directory_),
            directory_.string() + ": cannot read lights file: Is a directory");
}

TEST_F(LightsFileTest, RejectsEmptyFile) {
  const auto path = write("empty.json", "");
  const std::string prefix = path.string() + ":1:1: JSON syntax error: ";
  EXPECT_EQ(loadError(path).substr(0, prefix.size()), prefix);
}

}  // namespace

TEST(LightsLoader, FarAloneNeedsOnlyToBePositiveWhenNearIsAutomatic) {
  const Light light = parse(R"({"lights": [{"shadow": {"far": 0.01}}]})").lights.at(0);
  EXPECT_FLOAT_EQ(light.shadow.far, 0.01f);
  EXPECT_FLOAT_EQ(light.shadow.near, 0.0f);  // derived at render time (effectiveShadowNear)
}

}  // namespace lights_loader_test
