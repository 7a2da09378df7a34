#include "renderer/verify/embree_api.h"

#include <dlfcn.h>

#include <string>

#include "renderer/core/errors.h"

#ifndef OMNISHADOW_LIBEMBREE_SONAME
#error "OMNISHADOW_LIBEMBREE_SONAME: the CMake build defines it from the Embree it found"
#endif

namespace omnishadow {
namespace {

template <class F>
bool resolve(void* handle, const char* name, F& function) {
  function = reinterpret_cast<F>(::dlsym(handle, name));
  return function != nullptr;
}

const EmbreeLoad& processEmbree() {
  static const EmbreeLoad loaded = loadEmbree(OMNISHADOW_LIBEMBREE_SONAME);  // thread-safe
  return loaded;
}

}  // namespace

EmbreeLoad loadEmbree(const std::string& soname) {
  EmbreeLoad loaded;
  // Never closed: Embree's and TBB's threads live as long as the process.
  void* handle = ::dlopen(soname.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (!handle) {
    const char* why = ::dlerror();
    loaded.error = "Embree (" + soname + ") cannot be loaded: " + (why ? why : "unknown error") +
                   "; on Debian: apt install libembree3-3";
    return loaded;
  }
  EmbreeApi& api = loaded.api;
  const bool all = resolve(handle, "rtcNewDevice", api.newDevice) &&
                   resolve(handle, "rtcReleaseDevice", api.releaseDevice) &&
                   resolve(handle, "rtcGetDeviceError", api.getDeviceError) &&
                   resolve(handle, "rtcSetDeviceErrorFunction", api.setDeviceErrorFunction) &&
                   resolve(handle, "rtcNewScene", api.newScene) &&
                   resolve(handle, "rtcReleaseScene", api.releaseScene) &&
                   resolve(handle, "rtcSetSceneFlags", api.setSceneFlags) &&
                   resolve(handle, "rtcSetSceneBuildQuality", api.setSceneBuildQuality) &&
                   resolve(handle, "rtcCommitScene", api.commitScene) &&
                   resolve(handle, "rtcNewGeometry", api.newGeometry) &&
                   resolve(handle, "rtcReleaseGeometry", api.releaseGeometry) &&
                   resolve(handle, "rtcCommitGeometry", api.commitGeometry) &&
                   resolve(handle, "rtcAttachGeometry", api.attachGeometry) &&
                   resolve(handle, "rtcSetNewGeometryBuffer", api.setNewGeometryBuffer) &&
                   resolve(handle, "rtcSetGeometryMask", api.setGeometryMask) &&
                   resolve(handle, "rtcSetGeometryUserData", api.setGeometryUserData) &&
                   resolve(handle, "rtcGetGeometry", api.getGeometry) &&
                   resolve(handle, "rtcGetGeometryUserData", api.getGeometryUserData) &&
                   resolve(handle, "rtcSetGeometryOccludedFilterFunction",
                           api.setGeometryOccludedFilterFunction) &&
                   resolve(handle, "rtcSetGeometryIntersectFilterFunction",
                           api.setGeometryIntersectFilterFunction) &&
                   resolve(handle, "rtcIntersect1", api.intersect1) &&
                   resolve(handle, "rtcOccluded1", api.occluded1);
  if (!all) loaded.error = "Embree (" + soname + ") lacks a function omnishadow calls";
  return loaded;
}

const EmbreeApi& embreeApi() {
  const EmbreeLoad& loaded = processEmbree();
  if (!loaded.error.empty()) throw RenderError(loaded.error);
  return loaded.api;
}

bool embreeLoaded() {
  void* handle = ::dlopen(OMNISHADOW_LIBEMBREE_SONAME, RTLD_LAZY | RTLD_NOLOAD);
  if (handle) ::dlclose(handle);  // the reference RTLD_NOLOAD took
  return handle != nullptr;
}

}  // namespace omnishadow
