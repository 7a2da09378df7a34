#include "cli/verify_command.h"

#include <CLI/CLI.hpp>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <sstream>

#include "cli/common_options.h"
#include "cli/malloc_heap.h"
#include "cli/render_job.h"
#include "renderer/core/errors.h"
#include "renderer/output/image_writer.h"
#include "renderer/output/output_transaction.h"
#include "renderer/render/renderer.h"
#include "renderer/verify/shadow_reference.h"
#include "renderer/verify/shadow_verification.h"
#include "renderer/view/shadow_plan.h"

namespace fs = std::filesystem;

namespace omnishadow::cli {
namespace {

using Json = nlohmann::ordered_json;

// The scene, lights and view options as a render job that only draws the AOVs.
RenderJob jobFromOptions(const VerifyOptions& o) {
  RenderJob job = sceneJob(o.input);
  job.aovs = true;
  validateJob(job);
  job.camera = cameraRequest(o.view);
  return job;
}

std::optional<double> parseMaxError(const std::string& text) {
  if (text.empty()) return std::nullopt;
  std::istringstream in(text);
  double value = 0.0;
  in >> value;
  if (!in || in.peek() != EOF || !std::isfinite(value) || value < 0.0 || value > 1.0)
    throw InputError("--max-error " + text +
                     ": expected a fraction of evaluated points between 0 and 1, e.g. 0.0005");
  return value;
}

void checkErrorImageName(const fs::path& path, const RenderJob& job, const LoadedJob& loaded) {
  if (fs::is_directory(path))
    throw InputError("--error-image " + path.string() + ": is a folder, expected a file name");
  std::vector<std::string> inputs = loaded.scene().inputFiles;
  inputs.push_back(job.lights.string());
  const fs::path target = fs::weakly_canonical(fs::absolute(path));
  for (const std::string& input : inputs)
    if (!input.empty() && target == fs::weakly_canonical(fs::absolute(input)))
      throw InputError(path.string() + ": refusing to overwrite an input file");
}

// The lights to check: all, or the one --light names.
std::vector<LightToVerify> selectLights(const VerifyOptions& o, const LoadedJob& loaded) {
  std::vector<LightToVerify> selected;
  for (const Light& light : loaded.lights)
    if (o.light.empty() || light.name == o.light)
      selected.push_back({light, effectiveShadowFar(light, loaded.scene().bounds)});
  if (selected.empty()) {
    std::string names;
    for (const Light& light : loaded.lights)
      names += (names.empty() ? "\"" : ", \"") + light.name + "\"";
    throw InputError("--light " + o.light + ": no such light (the scene's lights: " + names + ")");
  }
  return selected;
}

std::string fourDecimalPercent(double fraction) {
  char text[32];
  std::snprintf(text, sizeof text, "%.4f%%", 100.0 * fraction);
  return text;
}

std::string countAndPercent(std::int64_t n, double fraction) {
  return std::to_string(n) + " (" + fourDecimalPercent(fraction) + ")";
}

void printGroup(const char* label, const ClassCounts& c) {
  if (c.evaluated == 0) {
    std::printf("  %-9s %10d  %-10s %-22s %s\n", label, 0, "-", "-", "-");
    return;
  }
  std::printf("  %-9s %10lld  %-10s %-22s %s\n", label, static_cast<long long>(c.evaluated),
              fourDecimalPercent(c.agreementRate()).c_str(),
              countAndPercent(c.falseShadow, c.falseShadowRate()).c_str(),
              countAndPercent(c.falseLight, c.falseLightRate()).c_str());
}

void printOcclusion(const AmbientOcclusionCounts& c, const VerifySettings& settings) {
  using C = AmbientOcclusionCounts;
  std::printf("\nambient occlusion  radius %g, %d rays per point meeting a surface within %g\n",
              settings.occlusionRadius, settings.occlusionSamples, 0.9 * settings.occlusionRadius);
  std::printf("  evaluated  %lld points (%lld with an occlusion texture left out)\n",
              static_cast<long long>(c.evaluated), static_cast<long long>(c.textured));
  if (c.evaluated == 0) return;
  std::printf(
      "  error      mean %+.4f, mean absolute %.4f; darker by more than %g %s, lighter "
      "%s\n",
      C::mean(c.sumError, c.evaluated), C::mean(c.sumAbsoluteError, c.evaluated),
      static_cast<double>(kOcclusionErrorBound),
      fourDecimalPercent(C::mean(static_cast<double>(c.darker), c.evaluated)).c_str(),
      fourDecimalPercent(C::mean(static_cast<double>(c.lighter), c.evaluated)).c_str());
  std::printf(
      "  occluded   %lld points below %g by the rays: mean absolute error %.4f (%.4f "
      "without ambient occlusion)\n",
      static_cast<long long>(c.occluded), static_cast<double>(kOccludedShare),
      C::mean(c.occludedAbsoluteError, c.occluded), C::mean(c.occludedHidden, c.occluded));
}

Json occlusionJson(const std::optional<AmbientOcclusionCounts>& counts,
                   const VerifySettings& settings) {
  if (!counts) return Json(nullptr);
  using C = AmbientOcclusionCounts;
  const C& c = *counts;
  const auto mean = [&](double sum, std::int64_t n) {
    return n > 0 ? Json(C::mean(sum, n)) : Json(nullptr);
  };
  return Json{{"radius", jsonNumber(settings.occlusionRadius)},
              {"rays", settings.occlusionSamples},
              {"evaluated", c.evaluated},
              {"textured", c.textured},
              {"meanError", mean(c.sumError, c.evaluated)},
              {"meanAbsoluteError", mean(c.sumAbsoluteError, c.evaluated)},
              {"darker", c.darker},
              {"lighter", c.lighter},
              {"errorBound", jsonNumber(kOcclusionErrorBound)},
              {"occluded", c.occluded},
              {"occludedMeanAbsoluteError", mean(c.occludedAbsoluteError, c.occluded)},
              {"occludedMeanHidden", mean(c.occludedHidden, c.occluded)}};
}

const Light& lightNamed(const std::vector<LightToVerify>& lights, const std::string& name) {
  for (const LightToVerify& l : lights)
    if (l.light.name == name) return l.light;
  throw std::logic_error("no light " + name);
}

// First line naming what exceeds the bound, or empty.
std::string firstFailure(const ShadowVerification& v, double maxError) {
  for (const LightVerification& light : v.lights) {
    if (!light.shadowed) continue;
    const std::pair<const char*, double> rates[] = {
        {"false shadow", light.interior.falseShadowRate()},
        {"false light", light.interior.falseLightRate()}};
    for (const auto& [what, rate] : rates)
      if (rate > maxError)
        return "light \"" + light.name + "\": interior " + what + " " + fourDecimalPercent(rate) +
               " > " + fourDecimalPercent(maxError);
  }
  return {};
}

void printText(const RenderJob& job, const LoadedJob& loaded,
               const std::vector<LightToVerify>& lights, const ShadowVerification& v,
               const VerifySettings& settings, const std::optional<double>& maxError,
               const fs::path& errorImagePath) {
  const long long pixels = static_cast<long long>(v.width) * v.height;
  std::printf("scene      %s\n", job.scene.c_str());
  std::printf("view       %dx%d, %s\n", v.width, v.height, loaded.camera.description.c_str());
  std::printf(
      "rules      skip N.L < %g; edge band %g texels + filter; %d rays per point to a "
      "light with a radius\n",
      settings.grazing, settings.edgeTexels, settings.sourceSamples);
  for (const LightVerification& result : v.lights) {
    const Light& light = lightNamed(lights, result.name);
    std::printf("\nlight \"%s\"  %s", result.name.c_str(), toString(light.type));
    if (!result.shadowed) {
      std::printf("  not shadowed (shadow.enabled is false): skipped\n");
      continue;
    }
    std::printf("  %s  %d texels", toString(light.shadow.filter), light.shadow.resolution);
    if (light.shadow.radius > 0.0f)
      std::printf("  radius %g%s", light.shadow.radius,
                  light.type == LightType::Directional ? " rad" : "");
    std::printf("\n");
    const SkipCounts& s = result.skipped;
    std::printf("  evaluated  %lld of %lld pixels: %lld interior, %lld edge\n",
                static_cast<long long>(result.interior.evaluated + result.edge.evaluated), pixels,
                static_cast<long long>(result.interior.evaluated),
                static_cast<long long>(result.edge.evaluated));
    std::printf(
        "  skipped    background %lld, out of range %lld, outside cone %lld, facing away "
        "%lld, grazing %lld, beyond shadow far %lld, unlit %lld\n",
        static_cast<long long>(s.background), static_cast<long long>(s.outOfRange),
        static_cast<long long>(s.outsideCone), static_cast<long long>(s.facingAway),
        static_cast<long long>(s.grazing), static_cast<long long>(s.beyondShadowFar),
        static_cast<long long>(s.unlit));
    std::printf("  %-9s %10s  %-10s %-22s %s\n", "", "points", "agreement", "false shadow",
                "false light");
    printGroup("interior", result.interior);
    printGroup("edge", result.edge);
    if (result.transmittance.evaluated > 0)
      std::printf("  transmittance  %lld interior points, %s within %g per channel\n",
                  static_cast<long long>(result.transmittance.evaluated),
                  fourDecimalPercent(result.transmittance.agreementRate()).c_str(),
                  static_cast<double>(kTransmittanceTolerance));
  }
  if (v.occlusion) printOcclusion(*v.occlusion, settings);
  std::printf("\n");
  if (!errorImagePath.empty()) std::printf("error image  %s\n", errorImagePath.c_str());
  if (maxError) {
    const std::string failure = firstFailure(v, *maxError);
    if (failure.empty())
      std::printf("result     PASS: every interior error rate <= %s\n",
                  fourDecimalPercent(*maxError).c_str());
    else
      std::printf("result     FAIL: %s\n", failure.c_str());
  }
}

Json groupJson(const ClassCounts& c) {
  auto rate = [&](double r) { return c.evaluated > 0 ? Json(r) : Json(nullptr); };
  return Json{{"evaluated", c.evaluated},
              {"agree", c.agree},
              {"falseShadow", c.falseShadow},
              {"falseLight", c.falseLight},
              {"agreementRate", rate(c.agreementRate())},
              {"falseShadowRate", rate(c.falseShadowRate())},
              {"falseLightRate", rate(c.falseLightRate())}};
}

void printJson(const RenderJob& job, const LoadedJob& loaded,
               const std::vector<LightToVerify>& lights, const ShadowVerification& v,
               const VerifySettings& settings, const std::optional<double>& maxError,
               const fs::path& errorImagePath) {
  Json out;
  out["scene"] = job.scene.string();
  out["width"] = v.width;
  out["height"] = v.height;
  out["camera"] = loaded.camera.description;
  out["settings"] = Json{{"grazing", jsonNumber(settings.grazing)},
                         {"edgeTexels", jsonNumber(settings.edgeTexels)},
                         {"sourceSamples", settings.sourceSamples},
                         {"maxError", maxError ? Json(*maxError) : Json(nullptr)}};
  out["lights"] = Json::array();
  for (const LightVerification& result : v.lights) {
    const Light& light = lightNamed(lights, result.name);
    Json entry{
        {"name", result.name}, {"type", toString(light.type)}, {"shadowed", result.shadowed}};
    if (!result.shadowed) {
      for (const char* key : {"filter", "resolution", "radius", "skipped", "interior", "edge",
                              "transmittance", "pass"})
        entry[key] = nullptr;
      out["lights"].push_back(entry);
      continue;
    }
    const SkipCounts& s = result.skipped;
    entry["filter"] = toString(light.shadow.filter);
    entry["resolution"] = light.shadow.resolution;
    entry["radius"] = jsonNumber(light.shadow.radius);
    entry["skipped"] = Json{{"background", s.background},
                            {"outOfRange", s.outOfRange},
                            {"outsideCone", s.outsideCone},
                            {"facingAway", s.facingAway},
                            {"grazing", s.grazing},
                            {"beyondShadowFar", s.beyondShadowFar},
                            {"unlit", s.unlit}};
    entry["interior"] = groupJson(result.interior);
    entry["edge"] = groupJson(result.edge);
    entry["transmittance"] = result.transmittance.evaluated > 0
                                 ? Json{{"evaluated", result.transmittance.evaluated},
                                        {"agree", result.transmittance.agree},
                                        {"agreementRate", result.transmittance.agreementRate()},
                                        {"tolerance", jsonNumber(kTransmittanceTolerance)}}
                                 : Json(nullptr);
    entry["pass"] = !maxError || worstInteriorErrorRate(result) <= *maxError;
    out["lights"].push_back(entry);
  }
  out["ambientOcclusion"] = occlusionJson(v.occlusion, settings);
  out["errorImage"] = errorImagePath.empty() ? Json(nullptr) : Json(errorImagePath.string());
  out["pass"] = !maxError || firstFailure(v, *maxError).empty();
  // File names need not be UTF-8; JSON must be (invalid bytes become U+FFFD).
  std::printf("%s\n", out.dump(2, ' ', false, Json::error_handler_t::replace).c_str());
}

int verify(const VerifyOptions& o, std::vector<std::string>& warnings) {
  // A process that renders once and casts a ray per pixel and light: the heap set up as for a
  // batch (cli/malloc_heap.h). Sundial at 640x360 took 0.73-0.77 s with malloc as the system
  // has it and 0.23-0.39 s set up so: most of the difference was fresh 4 KiB pages.
  setUpMallocHeap();
  StageTimes times;
  ScopedStage loadStage(times, "load");
  const RenderJob job = jobFromOptions(o);
  const std::optional<double> maxError = parseMaxError(o.maxError);
  VerifySettings settings;
  settings.grazing = o.grazing;
  settings.edgeTexels = o.edgeTexels;
  settings.sourceSamples = o.sourceSamples;
  const int side = static_cast<int>(std::lround(std::sqrt(o.sourceSamples)));
  if (side * side != o.sourceSamples)
    throw InputError("--source-samples " + std::to_string(o.sourceSamples) +
                     ": expected a square number (a stratified n x n pattern), e.g. 16, 64, 256");
  settings.threads = o.threads;
  const fs::path errorImagePath = o.errorImage;
  if (!errorImagePath.empty() && lowerExtension(errorImagePath) != ".png")
    throw InputError("--error-image " + errorImagePath.string() + ": expected a .png name");
  LoadedJob loaded = loadJob(job);
  warnings = loaded.warnings;
  // A lights file with ambient occlusion: its layer is compared with rays too.
  RenderJob drawn = job;
  if (const std::optional<AmbientOcclusion>& occlusion = loaded.setup.ambientOcclusion) {
    drawn.layers.occlusion = drawn.layers.materialId = true;
    settings.occlusionRadius = effectiveRadius(*occlusion, loaded.scene().bounds);
    for (const Material& material : loaded.scene().materials)
      settings.texturedMaterials.push_back(material.occlusionTexture.texture >= 0);
  }
  const std::vector<LightToVerify> lights = selectLights(o, loaded);
  // Staging creates the file, so an unwritable --error-image fails here, before the render.
  OutputTransaction transaction;
  fs::path staged;
  if (!errorImagePath.empty()) {
    checkErrorImageName(errorImagePath, job, loaded);
    try {
      staged = transaction.stage(errorImagePath);
    } catch (const RenderError& e) {
      throw InputError(std::string("--error-image: ") + e.what());
    }
  }
  loadStage.stop();

  ScopedStage contextStage(times, "context");
  const std::unique_ptr<Renderer> renderer = openRenderer(o.device);
  contextStage.stop();
  const Frame frame = renderJob(*renderer, drawn, loaded, times);
  warnings.insert(warnings.end(), frame.warnings.begin(), frame.warnings.end());
  if (!frame.aovs) throw RenderError("the renderer returned no AOVs");

  ScopedStage referenceStage(times, "reference");
  const ShadowReference reference(loaded.scene());
  referenceStage.stop();
  ScopedStage raysStage(times, "rays");
  const ShadowVerification result =
      verifyShadows(reference, loaded.scene().bounds, lights, *frame.aovs, loaded.camera, settings);
  raysStage.stop();

  if (!errorImagePath.empty()) {
    ScopedStage encodeStage(times, "encode");
    writePng(staged, result.width, result.height, 3,
             errorImage(result, *frame.aovs, loaded.camera));
    transaction.commit();
  }
  printWarnings(warnings);
  if (o.json)
    printJson(job, loaded, lights, result, settings, maxError, errorImagePath);
  else
    printText(job, loaded, lights, result, settings, maxError, errorImagePath);
  if (o.device.stats) printStats(times);
  return maxError && !firstFailure(result, *maxError).empty() ? 1 : 0;
}

}  // namespace

void addVerifyCommand(CLI::App& app, VerifyOptions& o) {
  CLI::App* verify = app.add_subcommand(
      "verify",
      "Check the renderer's shadows against exact ray casting (Embree): agreement, false shadow "
      "and false light rates per light");
  addSceneInputOptions(*verify, o.input, SceneInputCommand::Verify);
  addViewOptions(*verify, o.view);
  verify->add_option("--light", o.light, "Check only this light (default: every light)");
  verify->add_option("--max-error", o.maxError,
                     "Exit with status 1 when a light's interior false-shadow or false-light "
                     "rate exceeds this fraction (e.g. 0.0005)");
  verify->add_option("--error-image", o.errorImage,
                     "Write a PNG: the scene in grey, false shadow red, false light blue, "
                     "edge points dimmer");
  verify
      ->add_option("--grazing", o.grazing,
                   "Skip points where N.L is below this (default 0.05, about 87 degrees)")
      ->check(CLI::Range(0.0f, 1.0f));
  verify
      ->add_option("--edge-texels", o.edgeTexels,
                   "Half-width of the shadow-edge band in shadow-map texels (default 3)")
      ->check(CLI::Range(0.0f, 1000.0f));
  verify
      ->add_option("--source-samples", o.sourceSamples,
                   "Rays per point to a light with a radius, a square number (default 64)")
      ->check(CLI::Range(1, 4096));
  verify
      ->add_option("--threads", o.threads,
                   "Threads casting rays (default: one per core); results do not depend on it")
      ->check(CLI::NonNegativeNumber);
  verify->add_flag("--json", o.json, "Print one JSON object (schema in the README)");
  addDeviceOptions(*verify, o.device, true);
}

int runVerify(const VerifyOptions& o) {
  return runPrintingWarnings(
      [&](std::vector<std::string>& warnings) { return verify(o, warnings); });
}

}  // namespace omnishadow::cli
