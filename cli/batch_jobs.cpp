#include "cli/batch_jobs.h"

#include <glob.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iterator>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>

#include "cli/common_options.h"
#include "cli/frame_set.h"
#include "renderer/core/errors.h"
#include "renderer/core/input_file.h"
#include "renderer/core/json_depth.h"

namespace fs = std::filesystem;
using json = nlohmann::json;

namespace omnishadow::cli {
namespace {

bool isScene(const fs::path& path) {
  const std::string ext = lowerExtension(path);
  return ext == ".gltf" || ext == ".glb";
}

bool hasWildcard(const std::string& text) {
  return text.find_first_of("*?[") != std::string::npos;
}

// Lights for a scene without --lights: "<stem>.lights.json" beside it, else "lights.json" in
// its folder.
fs::path sceneLights(const fs::path& scene) {
  if (fs::path own = defaultLightsFile(scene); !own.empty()) return own;
  const fs::path folder = scene.parent_path() / "lights.json";
  return pathExists(folder) ? folder : fs::path();
}

// The outputs of folder, glob and scene inputs come from the flags alone; a manifest's jobs
// name their own, and are checked one by one (addManifest()).
void requireDefaultOutputs(const BatchDefaults& d) {
  if (!d.png && !d.exr && !d.aov && !d.masks)
    throw InputError("--no-png: nothing left to write; add --exr, --aov or --masks");
}

// A job for `scene` whose outputs are `stem` (no extension) plus the batch's formats.
RenderJob folderJob(const fs::path& scene, const fs::path& stem, const BatchDefaults& defaults) {
  RenderJob job = defaults.job;
  job.scene = scene;
  job.lights = defaults.lights.empty() ? sceneLights(scene) : defaults.lights;
  if (defaults.png) job.png.push_back(fs::path(stem.string() + ".png"));
  if (defaults.exr) job.exr.push_back(fs::path(stem.string() + ".exr"));
  if (defaults.aov) job.aov = fs::path(stem.string() + ".aov.exr");
  if (defaults.masks) job.masks = stem;
  return job;
}

void addScene(const fs::path& scene, const fs::path& base, const BatchDefaults& defaults,
              std::vector<BatchEntry>& jobs) {
  const fs::path relative = scene.lexically_relative(base);
  fs::path stem = relative;
  stem.replace_extension();
  jobs.push_back({relative.generic_string(), folderJob(scene, defaults.out / stem, defaults)});
}

void addFolder(const fs::path& folder, std::vector<BatchEntry>& jobs,
               const BatchDefaults& defaults) {
  std::vector<fs::path> scenes;
  // An entry that cannot be looked at (a symbolic link loop, a dangling link) is no scene; it
  // must not stop the scenes beside it from rendering.
  std::error_code ec;
  for (const auto& entry :
       fs::recursive_directory_iterator(folder, fs::directory_options::skip_permission_denied))
    if (isScene(entry.path()) && entry.is_regular_file(ec)) scenes.push_back(entry.path());
  std::sort(scenes.begin(), scenes.end());
  if (scenes.empty()) throw InputError(folder.string() + ": no .gltf or .glb files in this folder");
  for (const fs::path& scene : scenes) addScene(scene, folder, defaults, jobs);
}

void addGlob(const std::string& pattern, std::vector<BatchEntry>& jobs,
             const BatchDefaults& defaults) {
  glob_t matches{};
  const int status = ::glob(pattern.c_str(), 0, nullptr, &matches);
  std::vector<fs::path> scenes;
  if (status == 0)
    for (std::size_t i = 0; i < matches.gl_pathc; ++i)
      if (isScene(matches.gl_pathv[i]) && fs::is_regular_file(matches.gl_pathv[i]))
        scenes.emplace_back(matches.gl_pathv[i]);
  globfree(&matches);
  std::sort(scenes.begin(), scenes.end());
  if (scenes.empty()) throw InputError(pattern + ": matches no .gltf or .glb file");
  // Outputs mirror the paths below the pattern's leading folder without wildcards.
  fs::path base;
  for (const fs::path& part : fs::path(pattern).parent_path()) {
    if (hasWildcard(part.string())) break;
    base /= part;
  }
  for (const fs::path& scene : scenes) addScene(scene, base, defaults, jobs);
}

// Manifest fields: each reader throws InputError naming "<manifest>: jobs[i].<field>".
class ManifestJob {
 public:
  ManifestJob(const json& value, std::string where) : value_(value), where_(std::move(where)) {}

  std::optional<std::string> string(const char* field) const {
    const json* v = find(field);
    if (!v) return std::nullopt;
    if (!v->is_string() || v->get<std::string>().empty())
      fail(field, "expected a non-empty string");
    return v->get<std::string>();
  }
  std::optional<double> number(const char* field) const {
    const json* v = find(field);
    if (!v) return std::nullopt;
    if (!v->is_number() || !std::isfinite(v->get<double>()))
      fail(field, "expected a finite number");
    return v->get<double>();
  }
  // An integer in [min, max], checked before the conversion (1e12 is no int).
  std::optional<int> integer(const char* field, int min, int max) const {
    const auto n = number(field);
    if (!n) return std::nullopt;
    if (*n != std::floor(*n) || *n < min || *n > max)
      fail(field,
           "expected an integer in [" + std::to_string(min) + ", " + std::to_string(max) + "]");
    return static_cast<int>(*n);
  }
  std::optional<bool> boolean(const char* field) const {
    const json* v = find(field);
    if (!v) return std::nullopt;
    if (!v->is_boolean()) fail(field, "expected true or false");
    return v->get<bool>();
  }
  std::optional<glm::vec3> vec3(const char* field) const {
    const json* v = find(field);
    if (!v) return std::nullopt;
    if (!v->is_array() || v->size() != 3 || !std::all_of(v->begin(), v->end(), [](const json& x) {
          return x.is_number() && std::isfinite(x.get<double>());
        }))
      fail(field, "expected an array of 3 finite numbers");
    return glm::vec3((*v)[0].get<float>(), (*v)[1].get<float>(), (*v)[2].get<float>());
  }
  // An empty list is allowed: a job may write masks or AOVs without an image.
  std::optional<std::vector<std::string>> strings(const char* field) const {
    const json* v = find(field);
    if (!v) return std::nullopt;
    if (!v->is_array() ||
        !std::all_of(v->begin(), v->end(), [](const json& x) { return x.is_string(); }))
      fail(field, "expected an array of file names");
    return v->get<std::vector<std::string>>();
  }
  bool isString(const char* field) const {
    const json* v = find(field);
    return v && v->is_string();
  }
  [[noreturn]] void fail(const std::string& field, const std::string& what) const {
    throw InputError(where_ + "." + field + ": " + what);
  }
  const std::string& where() const { return where_; }

 private:
  const json* find(const char* field) const {
    const auto it = value_.find(field);
    return it == value_.end() ? nullptr : &*it;
  }
  const json& value_;
  std::string where_;
};

// A manifest's output name as a path below --out. Absolute names and ".." are refused, and so is
// a name that leaves --out through a symbolic link that already exists below it: links are
// resolved, and the result must still lie inside --out (itself resolved, so --out may be a
// link).
fs::path confinedOutput(const ManifestJob& m, const char* field, const fs::path& out,
                        const std::string& name) {
  const fs::path relative(name);
  const auto refuse = [&](const std::string& why) {
    m.fail(field, "\"" + name + "\": " + why + "; output names are relative to --out");
  };
  if (relative.is_absolute()) refuse("an absolute path");
  for (const fs::path& part : relative) {
    if (part == "..") refuse("\"..\" would leave the output folder");
  }
  std::error_code ec;
  const fs::path folder = fs::weakly_canonical(fs::absolute(out), ec);
  const fs::path resolved = fs::weakly_canonical(fs::absolute(out / relative), ec);
  if (ec) refuse(ec.message());  // e.g. a name longer than the file system allows
  const fs::path inside = resolved.lexically_relative(folder);
  if (inside.empty() || *inside.begin() == ".." || inside == ".") {
    refuse("a symbolic link below --out leads outside it");
  }
  return out / relative;
}

RenderJob manifestJob(const ManifestJob& m, const fs::path& folder, const BatchDefaults& d) {
  const auto scene = m.string("scene");
  if (!scene) m.fail("scene", "missing; expected the path of a .gltf or .glb file");
  const fs::path scenePath = folder / *scene;
  fs::path stem = fs::path(*scene).filename();
  stem.replace_extension();
  RenderJob job = folderJob(scenePath, d.out / stem, d);
  if (const auto lights = m.string("lights")) job.lights = folder / *lights;
  if (const auto outputs = m.strings("outputs")) {
    job.png.clear();
    job.exr.clear();
    for (const std::string& output : *outputs) {
      const std::string ext = lowerExtension(output);
      if (ext == ".png") {
        job.png.push_back(confinedOutput(m, "outputs", d.out, output));
      } else if (ext == ".exr") {
        job.exr.push_back(confinedOutput(m, "outputs", d.out, output));
      } else {
        m.fail("outputs", "\"" + output + "\": expected .png or .exr names");
      }
    }
  }
  if (const auto aov = m.string("aov")) job.aov = confinedOutput(m, "aov", d.out, *aov);
  if (const auto layers = m.string("aovLayers")) job.layers = parseLayers(*layers);
  if (const auto masks = m.string("masks")) job.masks = confinedOutput(m, "masks", d.out, *masks);
  if (const auto aa = m.integer("aa", 1, 16)) {
    if (*aa != 1 && *aa != 4 && *aa != 8 && *aa != 16) m.fail("aa", "expected 1, 4, 8 or 16");
    job.antialiasing = *aa;
  }
  if (const auto camera = m.string("camera")) job.camera.select = *camera;
  if (const auto eye = m.vec3("eye")) job.camera.eye = eye;
  if (const auto target = m.vec3("target")) job.camera.target = target;
  if (const auto up = m.vec3("up")) job.camera.up = up;
  if (const auto fov = m.number("fov")) job.camera.fovDegrees = static_cast<float>(*fov);
  if (const auto width = m.integer("width", 1, 16384)) job.camera.width = width;
  if (const auto height = m.integer("height", 1, 16384)) job.camera.height = height;
  if (const auto exposure = m.number("exposure")) job.exposure = static_cast<float>(*exposure);
  if (const auto shading = m.string("shading")) {
    if (*shading != "pbr" && *shading != "phong")
      m.fail("shading", "expected \"pbr\" or \"phong\"");
    job.shading = *shading == "phong" ? Shading::Phong : Shading::Pbr;
  }
  if (const auto index = m.integer("sceneIndex", 0, std::numeric_limits<int>::max()))
    job.sceneIndex = *index;
  if (const auto noGltfLights = m.boolean("noGltfLights")) job.noGltfLights = *noGltfLights;
  if (!m.isString("time"))  // a "START:END" range is expanded by addManifest()
    if (const auto time = m.number("time")) job.time = *time;
  if (const auto animation = m.string("animation")) job.animation = *animation;
  if (const auto variant = m.string("variant")) job.materialVariant = *variant;
  return job;
}

// A manifest job whose "time" is "START:END": one job per frame at "fps" (default 24), its
// outputs numbered like `render --time-range` (cli/frame_set.h).
void addTimeRange(const ManifestJob& m, const std::string& range, double fps,
                  const RenderJob& pattern, const std::string& name,
                  std::vector<BatchEntry>& jobs) {
  if (!(fps > 0.0)) m.fail("fps", "expected a positive number of frames per second");
  FrameSetOptions options;
  options.timeRange = range;
  options.fps = fps;
  std::vector<double> times;
  try {
    times = sequenceTimes(options);
  } catch (const InputError& e) {
    m.fail("time", e.what());
  }
  const auto numbered = [&](const fs::path& path, std::size_t frame) {
    if (path.filename().string().find('#') == std::string::npos)
      m.fail("outputs", path.filename().string() +
                            ": a time range writes one file per frame; put #### in the file name");
    return fs::path(numberedPath(path.string(), static_cast<int>(frame)));
  };
  for (std::size_t k = 0; k < times.size(); ++k) {
    RenderJob job = pattern;
    for (fs::path& path : job.png) path = numbered(path, k);
    for (fs::path& path : job.exr) path = numbered(path, k);
    if (!job.aov.empty()) job.aov = numbered(job.aov, k);
    if (!job.masks.empty()) job.masks = numbered(job.masks, k);
    job.time = times[k];
    jobs.push_back(
        {name + " @" + shortestDecimal(static_cast<float>(times[k])) + " s", std::move(job)});
  }
}

// Manifests list jobs, a few hundred bytes each; the bound keeps /dev/zero-like files out.
constexpr std::uint64_t kMaxManifestBytes = 64 << 20;

void addManifest(const fs::path& path, std::vector<BatchEntry>& jobs,
                 const BatchDefaults& defaults) {
  const std::string text = readInputFile(path, kMaxManifestBytes, "manifest");
  if (const std::size_t deep = findExcessiveNesting(text); deep != std::string::npos)
    throw InputError(path.string() + ":" + excessiveNestingMessage(text, deep));
  json manifest;
  try {
    manifest = json::parse(text);
  } catch (const json::parse_error& e) {
    // Same form as the lights file's syntax errors: file:line:column.
    const std::size_t end = std::min<std::size_t>(e.byte > 0 ? e.byte - 1 : 0, text.size());
    const auto line = 1 + std::count(text.begin(), text.begin() + end, '\n');
    const std::size_t lineStart = text.rfind('\n', end == 0 ? 0 : end - 1);
    const std::size_t column = lineStart == std::string::npos ? end + 1 : end - lineStart;
    throw InputError(path.string() + ":" + std::to_string(line) + ":" + std::to_string(column) +
                     ": JSON syntax error");
  } catch (const json::out_of_range&) {
    // 1e999 and the like: valid JSON syntax, but no double holds it (found by fuzz_manifest).
    throw InputError(path.string() + ": a number is too large to be read (more than 1.8e308)");
  }
  if (!manifest.is_object() || !manifest.contains("jobs") || !manifest["jobs"].is_array())
    throw InputError(path.string() + ": jobs: expected an array of job objects");
  const json& list = manifest["jobs"];
  for (std::size_t i = 0; i < list.size(); ++i) {
    const std::string where = path.string() + ": jobs[" + std::to_string(i) + "]";
    if (!list[i].is_object()) throw InputError(where + ": expected a job object");
    const ManifestJob m(list[i], where);
    RenderJob job = manifestJob(m, path.parent_path(), defaults);
    if (job.outputFiles().empty())
      throw InputError(where +
                       ": nothing to write; name images in \"outputs\", or give \"aov\" "
                       "or \"masks\"" +
                       (defaults.png ? "" : " (--no-png leaves out the images)"));
    const std::string name =
        "jobs[" + std::to_string(i) + "] " + list[i]["scene"].get<std::string>();
    if (m.isString("time")) {
      addTimeRange(m, *m.string("time"), m.number("fps").value_or(24.0), job, name, jobs);
      continue;
    }
    jobs.push_back({name, std::move(job)});
  }
}

}  // namespace

std::vector<BatchEntry> collectJobs(const std::vector<std::string>& inputs,
                                    const BatchDefaults& defaults) {
  std::vector<BatchEntry> jobs;
  for (const std::string& input : inputs) {
    const fs::path path(input);
    if (fs::is_directory(path)) {
      requireDefaultOutputs(defaults);
      addFolder(path, jobs, defaults);
    } else if (lowerExtension(path) == ".json") {
      addManifest(path, jobs, defaults);
    } else if (hasWildcard(input) && !fs::exists(path)) {
      requireDefaultOutputs(defaults);
      addGlob(input, jobs, defaults);
    } else if (!fs::exists(path)) {
      throw InputError(input + ": no such file or folder");
    } else if (isScene(path)) {
      requireDefaultOutputs(defaults);
      addScene(path, path.parent_path(), defaults, jobs);
    } else {
      throw InputError(input +
                       ": expected a folder, a .gltf/.glb file, a glob or a manifest .json");
    }
  }
  if (jobs.empty()) throw InputError("batch: no scenes to render");
  // Every job checked up front, and no two jobs may write one file.
  std::map<std::string, std::string> writers;
  for (const BatchEntry& entry : jobs) {
    validateJob(entry.job);
    for (const fs::path& output : entry.job.outputFiles()) {
      const std::string key = resolvedPath(output).string();
      const auto [it, fresh] = writers.emplace(key, entry.name);
      if (!fresh)
        throw InputError(output.string() + ": written by both " + it->second + " and " +
                         entry.name);
    }
  }
  return jobs;
}

Shard parseShard(const std::string& text) {
  Shard shard;
  char slash = 0;
  std::istringstream in(text);
  if (!(in >> shard.index >> slash >> shard.count) || slash != '/' || in.peek() != EOF ||
      shard.count < 1 || shard.index < 0 || shard.index >= shard.count)
    throw InputError("--shard " + text + ": expected K/N with 0 <= K < N, e.g. 0/4");
  return shard;
}

std::vector<BatchEntry> selectShard(std::vector<BatchEntry> jobs, const Shard& shard) {
  std::vector<BatchEntry> selected;
  for (std::size_t i = 0; i < jobs.size(); ++i)
    if (static_cast<int>(i % static_cast<std::size_t>(shard.count)) == shard.index)
      selected.push_back(std::move(jobs[i]));
  return selected;
}

}  // namespace omnishadow::cli
