#pragma once

// Embree's functions, looked up in its library the first time `verify` (or the exact reference
// behind it) needs them. Linked instead, Embree and the TBB it brings were loaded and
// initialized by every omnishadow process: about 3.5 ms of each, on the 2-core machine of
// docs/performance.md, where `omnishadow --version` takes about 20. Only the header is compiled
// in; the library is found by the soname of the one the build found.

#include <embree3/rtcore.h>

#include <string>

namespace omnishadow {

struct EmbreeApi {
  decltype(&::rtcNewDevice) newDevice = nullptr;
  decltype(&::rtcReleaseDevice) releaseDevice = nullptr;
  decltype(&::rtcGetDeviceError) getDeviceError = nullptr;
  decltype(&::rtcSetDeviceErrorFunction) setDeviceErrorFunction = nullptr;
  decltype(&::rtcNewScene) newScene = nullptr;
  decltype(&::rtcReleaseScene) releaseScene = nullptr;
  decltype(&::rtcSetSceneFlags) setSceneFlags = nullptr;
  decltype(&::rtcSetSceneBuildQuality) setSceneBuildQuality = nullptr;
  decltype(&::rtcCommitScene) commitScene = nullptr;
  decltype(&::rtcNewGeometry) newGeometry = nullptr;
  decltype(&::rtcReleaseGeometry) releaseGeometry = nullptr;
  decltype(&::rtcCommitGeometry) commitGeometry = nullptr;
  decltype(&::rtcAttachGeometry) attachGeometry = nullptr;
  decltype(&::rtcSetNewGeometryBuffer) setNewGeometryBuffer = nullptr;
  decltype(&::rtcSetGeometryMask) setGeometryMask = nullptr;
  decltype(&::rtcSetGeometryUserData) setGeometryUserData = nullptr;
  decltype(&::rtcGetGeometry) getGeometry = nullptr;
  decltype(&::rtcGetGeometryUserData) getGeometryUserData = nullptr;
  decltype(&::rtcSetGeometryOccludedFilterFunction) setGeometryOccludedFilterFunction = nullptr;
  decltype(&::rtcSetGeometryIntersectFilterFunction) setGeometryIntersectFilterFunction = nullptr;
  decltype(&::rtcIntersect1) intersect1 = nullptr;
  decltype(&::rtcOccluded1) occluded1 = nullptr;
};

// Loads the library on the first call (thread-safe) and keeps it for the process. Throws
// RenderError, at every call, where it cannot be loaded or lacks one of the functions.
const EmbreeApi& embreeApi();

// What loading the library `soname` gives: its functions, or why not (a message naming it). The
// library is never closed. embreeApi() loads Embree's own soname this way.
struct EmbreeLoad {
  EmbreeApi api;
  std::string error;  // empty when every function was found
};
EmbreeLoad loadEmbree(const std::string& soname);

// Whether this process has loaded Embree's library (for tests).
bool embreeLoaded();

}  // namespace omnishadow
