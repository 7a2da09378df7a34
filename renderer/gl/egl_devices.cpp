#include "renderer/gl/egl_devices.h"

#include <EGL/egl.h>
#include <EGL/eglext.h>
#include <GL/glcorearb.h>

#include <exception>

#include "renderer/gl/egl_context.h"
#include "renderer/gl/egl_extensions.h"

namespace omnishadow {
namespace {

// GL's own names for the device, from a context made on it: "vendor | renderer | version".
void probeWithContext(GpuDevice& device) {
  try {
    const EglContext context(ContextOptions{device.index, false});
    auto text = [](GLenum name) {
      const auto* s = reinterpret_cast<const char*>(glGetString(name));
      return std::string(s ? s : "");
    };
    if (device.vendor.empty()) device.vendor = text(GL_VENDOR);
    if (device.renderer.empty()) device.renderer = text(GL_RENDERER);
    if (device.driver.empty()) device.driver = text(GL_VERSION);
  } catch (const std::exception&) {
    // A device that cannot make an OpenGL 4.5 context is still listed, without names.
  }
}

}  // namespace

std::vector<GpuDevice> listEglDevices(bool probe) {
  if (!gl::hasEglExtension(eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS),
                           "EGL_EXT_platform_device"))
    return {};
  auto queryDevices = gl::loadEglProc<PFNEGLQUERYDEVICESEXTPROC>("eglQueryDevicesEXT");
  auto queryString = gl::loadEglProc<PFNEGLQUERYDEVICESTRINGEXTPROC>("eglQueryDeviceStringEXT");
  auto queryAttrib = gl::loadEglProc<PFNEGLQUERYDEVICEATTRIBEXTPROC>("eglQueryDeviceAttribEXT");
  EGLDeviceEXT handles[32];
  EGLint count = 0;
  if (!queryDevices || !queryString || !queryDevices(32, handles, &count)) return {};
  std::vector<GpuDevice> devices;
  for (EGLint i = 0; i < count; ++i) {
    GpuDevice device;
    device.index = i;
    const char* extensions = queryString(handles[i], EGL_EXTENSIONS);
    // Each query below may fail on a driver without it: that leaves the field empty and an EGL
    // error behind, which is no error of ours.
    auto string = [&](EGLint name) {
      const char* value = queryString(handles[i], name);
      if (!value) eglGetError();
      return std::string(value ? value : "");
    };
    device.software = gl::hasEglExtension(extensions, "EGL_MESA_device_software");
    if (gl::hasEglExtension(extensions, "EGL_EXT_device_drm"))
      device.drmNode = string(EGL_DRM_DEVICE_FILE_EXT);
    if (gl::hasEglExtension(extensions, "EGL_EXT_device_drm_render_node"))
      device.renderNode = string(EGL_DRM_RENDER_NODE_FILE_EXT);
    if (gl::hasEglExtension(extensions, "EGL_EXT_device_query_name")) {
      device.vendor = string(EGL_VENDOR);
      device.renderer = string(EGL_RENDERER_EXT);
    }
    if (gl::hasEglExtension(extensions, "EGL_EXT_device_persistent_id"))
      device.driver = string(EGL_DRIVER_NAME_EXT);
    EGLAttrib cuda = -1;
    if (gl::hasEglExtension(extensions, "EGL_NV_device_cuda") && queryAttrib) {
      if (queryAttrib(handles[i], EGL_CUDA_DEVICE_NV, &cuda) && cuda >= 0)
        device.cuda = static_cast<int>(cuda);
      else
        eglGetError();
    }
    devices.push_back(device);
  }
  if (probe)
    for (GpuDevice& device : devices)
      if (device.vendor.empty() || device.renderer.empty() || device.driver.empty())
        probeWithContext(device);
  return devices;
}

}  // namespace omnishadow
