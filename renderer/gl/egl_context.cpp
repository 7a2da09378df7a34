#include "renderer/gl/egl_context.h"

#include <EGL/egl.h>
#include <EGL/eglext.h>
#include <GL/glcorearb.h>

#include <map>
#include <mutex>
#include <optional>
#include <vector>

#include "renderer/core/errors.h"
#include "renderer/gl/egl_extensions.h"
#include "renderer/gl/enum_names.h"
#include "renderer/gl/loaded_libraries.h"
#include "renderer/gl/relocation_prefault.h"

namespace omnishadow {
namespace {

const char* eglErrorName(EGLint error) {
  static constexpr gl::EnumName<EGLint> kNames[] = {
      OMNISHADOW_ENUM_NAME(EGL_SUCCESS),           OMNISHADOW_ENUM_NAME(EGL_NOT_INITIALIZED),
      OMNISHADOW_ENUM_NAME(EGL_BAD_ACCESS),        OMNISHADOW_ENUM_NAME(EGL_BAD_ALLOC),
      OMNISHADOW_ENUM_NAME(EGL_BAD_ATTRIBUTE),     OMNISHADOW_ENUM_NAME(EGL_BAD_CONTEXT),
      OMNISHADOW_ENUM_NAME(EGL_BAD_CONFIG),        OMNISHADOW_ENUM_NAME(EGL_BAD_CURRENT_SURFACE),
      OMNISHADOW_ENUM_NAME(EGL_BAD_DISPLAY),       OMNISHADOW_ENUM_NAME(EGL_BAD_SURFACE),
      OMNISHADOW_ENUM_NAME(EGL_BAD_MATCH),         OMNISHADOW_ENUM_NAME(EGL_BAD_PARAMETER),
      OMNISHADOW_ENUM_NAME(EGL_BAD_NATIVE_PIXMAP), OMNISHADOW_ENUM_NAME(EGL_BAD_NATIVE_WINDOW),
      OMNISHADOW_ENUM_NAME(EGL_CONTEXT_LOST),
  };
  return gl::nameOf(error, kNames, "unknown EGL error");
}

struct Candidate {
  std::string description;
  EGLenum platform;
  void* nativeDisplay;
};

// EGL initializes a display once per process, and eglTerminate() ends it for every renderer
// on it: the contexts current elsewhere live on, but none can be made there any more (another
// renderer's second shadow context failed with EGL_NOT_INITIALIZED). So the renderers of a
// process count their uses of each display, and the last to end terminates it. Process-wide
// state because EGL's displays are; never destroyed, so that a renderer that ends during exit
// still finds it.
class DisplayUses {
 public:
  static DisplayUses& instance() {
    static auto* uses = new DisplayUses;
    return *uses;
  }

  bool initialize(EGLDisplay display, EGLint* major, EGLint* minor) {
    const std::lock_guard<std::mutex> lock(mutex_);
    const std::vector<std::string> before = loadedLibraries();
    if (!eglInitialize(display, major, minor)) return false;
    // What initializing loaded (the driver, LLVM) stays loaded after the last eglTerminate().
    keepLibrariesLoadedSince(before);
    ++uses_[display];
    return true;
  }

  void terminate(EGLDisplay display) {
    const std::lock_guard<std::mutex> lock(mutex_);
    const auto found = uses_.find(display);
    if (found == uses_.end() || --found->second > 0) return;
    uses_.erase(found);
    eglTerminate(display);
  }

 private:
  std::mutex mutex_;
  std::map<EGLDisplay, int> uses_;
};

}  // namespace

struct EglContext::Impl {
  EGLDisplay display = EGL_NO_DISPLAY;
  EGLConfig config = EGL_NO_CONFIG_KHR;
  EGLContext context = EGL_NO_CONTEXT;
  bool ownsDisplay = true;  // false for a shared context: the first one terminates the display
  std::string description;

  // Returns an empty string on success, else why it failed.
  std::string tryCreate(const Candidate& candidate, bool debug) {
    auto getPlatformDisplay =
        gl::loadEglProc<PFNEGLGETPLATFORMDISPLAYEXTPROC>("eglGetPlatformDisplayEXT");
    if (!getPlatformDisplay) return "eglGetPlatformDisplayEXT is missing";
    display = getPlatformDisplay(candidate.platform, candidate.nativeDisplay, nullptr);
    if (display == EGL_NO_DISPLAY)
      return std::string("eglGetPlatformDisplayEXT failed: ") + eglErrorName(eglGetError());
    EGLint major = 0, minor = 0;
    if (!DisplayUses::instance().initialize(display, &major, &minor)) {
      display = EGL_NO_DISPLAY;
      return std::string("eglInitialize failed: ") + eglErrorName(eglGetError());
    }
    if (!eglBindAPI(EGL_OPENGL_API)) return fail("eglBindAPI(EGL_OPENGL_API)");

    const char* extensions = eglQueryString(display, EGL_EXTENSIONS);
    if (!gl::hasEglExtension(extensions, "EGL_KHR_no_config_context")) {
      const EGLint attributes[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_NONE};
      EGLint count = 0;
      if (!eglChooseConfig(display, attributes, &config, 1, &count) || count == 0)
        return fail("eglChooseConfig (no EGL_KHR_no_config_context)");
    }
    description = candidate.description;
    return createContext(EGL_NO_CONTEXT, debug);
  }

  // Creates the context on `display` and makes it current; an empty string on success.
  std::string createContext(EGLContext shareWith, bool debug) {
    const EGLint contextAttributes[] = {EGL_CONTEXT_MAJOR_VERSION,
                                        4,
                                        EGL_CONTEXT_MINOR_VERSION,
                                        5,
                                        EGL_CONTEXT_OPENGL_PROFILE_MASK,
                                        EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                                        EGL_CONTEXT_OPENGL_DEBUG,
                                        debug ? EGL_TRUE : EGL_FALSE,
                                        EGL_NONE};
    context = eglCreateContext(display, config, shareWith, contextAttributes);
    if (context == EGL_NO_CONTEXT) return fail("eglCreateContext (OpenGL 4.5 core)");
    if (!eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, context))
      return fail("eglMakeCurrent without a surface");
    return {};
  }

  std::string fail(const std::string& what) {
    std::string message = what + " failed: " + eglErrorName(eglGetError());
    release();
    return message;
  }

  void release() {
    if (display == EGL_NO_DISPLAY) return;
    eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    if (context != EGL_NO_CONTEXT) eglDestroyContext(display, context);
    if (ownsDisplay)
      DisplayUses::instance().terminate(display);
    else
      eglReleaseThread();  // a shared context's thread (ShadowWorker's) ends after it
    context = EGL_NO_CONTEXT;
    display = EGL_NO_DISPLAY;
  }
};

namespace {

// EGL devices in the order they are tried: hardware first (or the one --gpu names).
std::vector<Candidate> deviceCandidates(int gpuIndex, std::vector<std::string>& notes) {
  const char* clientExtensions = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
  if (!gl::hasEglExtension(clientExtensions, "EGL_EXT_platform_device")) {
    notes.push_back("EGL device platform: not supported by this EGL (no EGL_EXT_platform_device)");
    return {};
  }
  auto queryDevices = gl::loadEglProc<PFNEGLQUERYDEVICESEXTPROC>("eglQueryDevicesEXT");
  auto queryDeviceString =
      gl::loadEglProc<PFNEGLQUERYDEVICESTRINGEXTPROC>("eglQueryDeviceStringEXT");
  EGLDeviceEXT devices[32];
  EGLint count = 0;
  if (!queryDevices || !queryDevices(32, devices, &count) || count == 0) {
    notes.push_back("EGL device platform: no devices");
    return {};
  }
  if (gpuIndex >= count)
    throw InputError("--gpu " + std::to_string(gpuIndex) + ": there are only " +
                     std::to_string(count) + " EGL devices (0.." + std::to_string(count - 1) + ")");
  std::vector<Candidate> hardware, software;
  for (EGLint i = 0; i < count; ++i) {
    if (gpuIndex >= 0 && i != gpuIndex) continue;
    const char* extensions = queryDeviceString ? queryDeviceString(devices[i], EGL_EXTENSIONS) : "";
    const bool isSoftware = gl::hasEglExtension(extensions, "EGL_MESA_device_software");
    std::string name = "EGL device " + std::to_string(i);
    if (isSoftware) {
      name += " (software)";
    } else if (const char* drm = queryDeviceString
                                     ? queryDeviceString(devices[i], EGL_DRM_DEVICE_FILE_EXT)
                                     : nullptr) {
      name += std::string(" (") + drm + ")";
    } else {
      eglGetError();  // the DRM query may fail on drivers without DRM; not an error
    }
    (isSoftware ? software : hardware).push_back({name, EGL_PLATFORM_DEVICE_EXT, devices[i]});
  }
  hardware.insert(hardware.end(), software.begin(), software.end());
  return hardware;
}

}  // namespace

EglContext::EglContext(const ContextOptions& options) : impl_(std::make_unique<Impl>()) {
  // Listing the devices and initializing a display load the EGL vendor libraries and the
  // driver (relocation_prefault.h); a process's later contexts load nothing new.
  const RelocationPrefault prefault;
  std::vector<std::string> attempts;
  std::vector<Candidate> candidates = deviceCandidates(options.gpuIndex, attempts);
  // Asking for a device that is not there is a usage error, also where EGL lists none at all.
  if (options.gpuIndex >= 0 && candidates.empty())
    throw InputError("--gpu " + std::to_string(options.gpuIndex) + ": there are no EGL devices (" +
                     (attempts.empty() ? std::string("none listed") : attempts.front()) +
                     "); leave --gpu out to use the surfaceless platform");
  const char* clientExtensions = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
  if (options.gpuIndex < 0) {
    if (gl::hasEglExtension(clientExtensions, "EGL_MESA_platform_surfaceless"))
      candidates.push_back(
          {"EGL surfaceless platform", EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY});
    else
      attempts.push_back(
          "EGL surfaceless platform: not supported (no EGL_MESA_platform_surfaceless)");
  }
  for (const Candidate& candidate : candidates) {
    const std::string why = impl_->tryCreate(candidate, options.debug);
    if (why.empty()) return;
    attempts.push_back(candidate.description + ": " + why);
  }
  std::string message = "cannot create a headless OpenGL 4.5 core context through EGL; tried: ";
  for (std::size_t i = 0; i < attempts.size(); ++i) message += (i ? "; " : "") + attempts[i];
  if (attempts.empty()) message += "nothing (no EGL platform available)";
  throw RenderError(message);
}

EglContext::EglContext(const EglContext& shareWith, bool debug) : impl_(std::make_unique<Impl>()) {
  impl_->display = shareWith.impl_->display;
  impl_->config = shareWith.impl_->config;
  impl_->ownsDisplay = false;
  impl_->description = shareWith.impl_->description;
  if (!eglBindAPI(EGL_OPENGL_API))  // per thread
    throw RenderError("cannot create a shared GL context: eglBindAPI(EGL_OPENGL_API) failed: " +
                      std::string(eglErrorName(eglGetError())));
  const std::string why = impl_->createContext(shareWith.impl_->context, debug);
  if (!why.empty()) throw RenderError("cannot create a shared GL context: " + why);
}

EglContext::~EglContext() {
  impl_->release();
}

void EglContext::makeCurrent() const {
  if (eglGetCurrentContext() == impl_->context) return;
  if (!eglMakeCurrent(impl_->display, EGL_NO_SURFACE, EGL_NO_SURFACE, impl_->context))
    throw RenderError(std::string("cannot make the GL context current again: eglMakeCurrent "
                                  "failed: ") +
                      eglErrorName(eglGetError()));
}

const std::string& EglContext::platformDescription() const {
  return impl_->description;
}

std::string EglContext::glDescription() const {
  auto text = [](GLenum name) {
    const auto* s = reinterpret_cast<const char*>(glGetString(name));
    return std::string(s ? s : "?");
  };
  return text(GL_VENDOR) + " | " + text(GL_RENDERER) + " | " + text(GL_VERSION);
}

}  // namespace omnishadow
