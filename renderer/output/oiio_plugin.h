#pragma once

#include <filesystem>
#include <string>

#include "renderer/output/image_writer.h"

namespace omnishadow {

// OpenImageIO links about 250 shared libraries (GDAL, Poppler, FFmpeg, OpenVDB...): loading
// them cost every omnishadow process 0.2-0.4 s before it did anything. PNG and EXR are read and
// written without it; every other format goes through libomnishadow_oiio.so, a plugin built
// with omnishadow that wraps OpenImageIO and is loaded (dlopen) the first time such a file is
// read, so that nothing else pays for it.

// The plugin's file name, and the function it exports (extern "C", kOiioPluginEntry):
//   bool omnishadow_oiio_read_image(const char* path, FloatImage* image, std::string* error,
//                                   int abi)
// which returns false with `error` set when OpenImageIO cannot read the file, and refuses an
// `abi` other than kOiioPluginAbi (a plugin from another build).
inline constexpr const char* kOiioPluginFile = "libomnishadow_oiio.so";
inline constexpr const char* kOiioPluginEntry = "omnishadow_oiio_read_image";
inline constexpr int kOiioPluginAbi = 1;
using OiioReadImage = bool (*)(const char*, FloatImage*, std::string*, int);

// Reads any image OpenImageIO understands through the plugin, which is looked for beside the
// executable, in ../lib/omnishadow from it, and in the build folder it was built in. Throws
// InputError "PATH: cannot read image: ..." when the plugin is missing or cannot read the file.
FloatImage readImageWithOiioPlugin(const std::filesystem::path& path);

}  // namespace omnishadow
