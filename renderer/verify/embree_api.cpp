#include "renderer/verify/embree_api.h"

#include <dlfcn.h>

#include <string>

#include "renderer/core/errors.h"
#include "renderer/core/library_symbol.h"

#ifndef OMNISHADOW_LIBEMBREE_SONAME
#error "OMNISHADOW_LIBEMBREE_SONAME: the CMake build defines it from the Embree it found"
#endif

namespace omnishadow {
namespace {

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
  const bool all = resolveSymbol(handle, "rtcNewDevice", api.newDevice) &&
                   resolveSymbol(handle, "rtcReleaseDevice", api.releaseDevice) &&
                   resolveSymbol(handle, "rtcGetDeviceError", api.getDeviceError) &&
                   resolveSymbol(handle, "rtcSetDeviceErrorFunction", api.setDeviceErrorFunction) &&
                   resolveSymbol(handle, "rtcNewScene", api.newScene) &&
                   resolveSymbol(handle, "rtcReleaseScene", api.releaseScene) &&
                   resolveSymbol(handle, "rtcSetSceneFlags", api.setSceneFlags) &&
                   resolveSymbol(handle, "rtcSetSceneBuildQuality", api.setSceneBuildQuality) &&
                   resolveSymbol(handle, "rtcCommitScene", api.commitScene) &&
                   resolveSymbol(handle, "rtcNewGeometry", api.newGeometry) &&
                   resolveSymbol(handle, "rtcReleaseGeometry", api.releaseGeometry) &&
                   resolveSymbol(handle, "rtcCommitGeometry", api.commitGeometry) &&
                   resolveSymbol(handle, "rtcAttachGeometry", api.attachGeometry) &&
                   resolveSymbol(handle, "rtcSetNewGeometryBuffer", api.setNewGeometryBuffer) &&
                   resolveSymbol(handle, "rtcSetGeometryMask", api.setGeometryMask) &&
                   resolveSymbol(handle, "rtcSetGeometryUserData", api.setGeometryUserData) &&
                   resolveSymbol(handle, "rtcGetGeometry", api.getGeometry) &&
                   resolveSymbol(handle, "rtcGetGeometryUserData", api.getGeometryUserData) &&
                   resolveSymbol(handle, "rtcSetGeometryOccludedFilterFunction",
                                 api.setGeometryOccludedFilterFunction) &&
                   resolveSymbol(handle, "rtcSetGeometryIntersectFilterFunction",
                                 api.setGeometryIntersectFilterFunction) &&
                   resolveSymbol(handle, "rtcIntersect1", api.intersect1) &&
                   resolveSymbol(handle, "rtcOccluded1", api.occluded1);
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
