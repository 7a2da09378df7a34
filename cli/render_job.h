#pragma once

#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "renderer/core/stage_timer.h"
#include "renderer/render/renderer.h"
#include "renderer/scene/light.h"
#include "renderer/scene/scene.h"
#include "renderer/view/camera.h"

namespace omnishadow {
class DecodedImageCache;
}  // namespace omnishadow

namespace omnishadow::cli {

// One render, as `render` or one entry of `batch` describes it: inputs, view, outputs.
struct RenderJob {
  std::filesystem::path scene;
  std::filesystem::path lights;  // empty = no lights file
  bool noGltfLights = false;
  bool allowExternalUris = false;
  int sceneIndex = -1;
  std::string materialVariant;  // KHR_materials_variants: name or index; empty = defaults
  CameraRequest camera;
  std::vector<std::filesystem::path> png, exr;
  std::filesystem::path aov;
  bool aovs = false;  // fill Frame::aovs even without an AOV file (`verify` reads them)
  AovLayers layers;
  // --masks stem: instance and semantic masks and their index (renderer/output/annotation_masks.h)
  std::filesystem::path masks;
  // --aa: beauty samples per pixel
  int antialiasing = 1;
  float exposure = 0.0f;
  Shading shading = Shading::Pbr;
  DebugView debugView = DebugView::None;
  std::string debugLight;
  std::filesystem::path dumpDepth, lightViews;
  int lightViewSize = 512;
  double maxMemoryMiB = 4096.0;  // for shadow maps
  ShadowPassStrategy shadowPass = ShadowPassStrategy::Auto;
  DepthPrepass depthPrepass = DepthPrepass::Auto;
  std::optional<bool> finishEachStage;  // RenderSettings::finishEachStage; unset = auto
  std::optional<double> time;           // pose at this time; nullopt = rest pose
  std::string animation;                // clips that play: name, index or "all"; empty = all
  bool cameraJson = false;              // write the camera sidecar next to the first image

  // Every file the job writes besides the per-light ones: images, AOVs, the id sidecar.
  std::vector<std::filesystem::path> outputFiles() const;
  // The shadow map dumps and light views the job writes for these lights.
  std::vector<std::filesystem::path> perLightFiles(const std::vector<Light>& rendered) const;
};

// The job's inputs, loaded: CPU only, so it may run on any thread.
struct LoadedJob {
  // The job's scene: its own, or one at rest that a batch's jobs of one file share (no copy of
  // its images and meshes per job). A shared scene is never changed: a job that poses it at a
  // time poses a copy of its own.
  std::optional<Scene> own;
  std::shared_ptr<const Scene> shared;  // used while `own` is empty
  bool atRest = true;  // the scene is at rest as the loader left it (a shared one always is)
  const Scene& scene() const { return own ? *own : *shared; }
  LightSetup setup;
  std::vector<Light> lights;  // merged; a headlight when there is none and no environment
  ViewCamera camera;
  std::vector<std::string> warnings;
};

// Checks what needs no file reading: output names and formats, option combinations.
// Throws InputError.
void validateJob(const RenderJob& job);

// Reads the scene file as the job's options say, at rest; with `decodedImages`, pictures other
// loads decoded from the same image bytes are taken from there (GltfLoadOptions). Throws
// InputError.
Scene loadJobScene(const RenderJob& job, DecodedImageCache* decodedImages = nullptr);

// Reads the scene and lights file, poses the scene at job.time and resolves the camera.
// Throws InputError.
LoadedJob loadJob(const RenderJob& job, DecodedImageCache* decodedImages = nullptr);
// The same with the job's scene as loadJobScene() read it, shared with other jobs.
LoadedJob loadJob(const RenderJob& job, std::shared_ptr<const Scene> scene);

class SharedSceneLoads;

// loadJob() and how long it took (the `load` stage), for loads run beside other work; with
// `shared`, the scene comes from there (a batch's jobs of one file), and a job that loads its
// own takes the pictures of other loads from its DecodedImageCache.
struct TimedLoad {
  LoadedJob job;
  double milliseconds = 0.0;
};
TimedLoad loadJobTimed(const RenderJob& job, SharedSceneLoads* shared = nullptr);

// Poses the loaded scene at `time` (job.animation's clips; a shared scene is copied first, and a
// scene at rest is drawn as it is without a time), then merges its lights with the lights file's
// again and resolves the camera: what a frame of a sequence changes. Returns the posing warnings.
std::vector<std::string> poseJob(const RenderJob& job, std::optional<double> time,
                                 LoadedJob& loaded);

// What a render of `job` can do while its scene loads (Renderer::prepare): when a lights file
// is given, prepares for its lights (as if the scene had none of its own) at the job's size, up
// to 256 MiB, and nothing where that would be less than `minimumMiB`. Reports nothing: what
// fails here fails again, and is reported, when the job is loaded.
void prepareJob(Renderer& renderer, const RenderJob& job, double minimumMiB = 0.0);

// About the bytes a render of the loaded job allocates: Renderer::frameBytes, and the scene's
// images with their mipmaps and its geometry as the GL copies them. For the memory warm-up
// (memory_warmup.h).
std::size_t frameMemoryEstimate(const Renderer& renderer, const RenderJob& job,
                                const LoadedJob& loaded);

// Renders on the renderer's (GL) thread. Throws InputError for limits of this GL. The frame's
// warnings are the renderer's; the job's own are in `loaded`.
Frame renderJob(Renderer& renderer, const RenderJob& job, const LoadedJob& loaded,
                StageTimes& times);

// Encodes and writes every output of the job, all or nothing. CPU only; any thread.
// Returns the files written.
std::vector<std::filesystem::path> writeJobOutputs(const RenderJob& job, const LoadedJob& loaded,
                                                   const Frame& frame);

// "<file>: refusing to overwrite an input file" when an output is one of `inputs`.
void checkNotAnInput(const RenderJob& job, const std::vector<std::string>& inputs);

// The camera sidecar's path (renderer/output/camera_sidecar.h): beside the first PNG, EXR or AOV
// file.
std::filesystem::path cameraJsonPath(const RenderJob& job);

// "<aov stem>.ids.json": what objectId and materialId values stand for.
std::filesystem::path idSidecarPath(const RenderJob& job);

// Helpers shared by the commands that build jobs from options.
std::string lowerExtension(const std::filesystem::path& path);
AovLayers parseLayers(const std::string& list);
DebugView parseDebugView(const std::string& name);
// "x,y,z" -> vector; empty -> nullopt; anything else -> InputError naming the option.
std::optional<glm::vec3> parseVec3(const std::string& option, const std::string& text);
// The lights file used when none is given: "<scene stem>.lights.json" beside the scene.
std::filesystem::path defaultLightsFile(const std::filesystem::path& scene);
// `path` with `.`/`..` and the symlinks of its existing part resolved, so that two spellings of
// one file compare equal even when the file does not exist yet; lexically normal where the file
// system cannot resolve it (too long, a symlink loop). Never throws for the name.
std::filesystem::path resolvedPath(const std::filesystem::path& path);
// Whether `path` names an existing file or folder (a folder): false, not an exception, for a
// name the file system cannot look at (too long, a symlink loop); its read or write names that.
bool pathExists(const std::filesystem::path& path);
bool isFolder(const std::filesystem::path& path);

}  // namespace omnishadow::cli
