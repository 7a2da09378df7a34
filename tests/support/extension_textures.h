#pragma once

// What the tests of the texture-image extensions (EXT_texture_webp, EXT_texture_avif) share:
// a picture that shows flips, swapped channels and premultiplied alpha, its comparison, and a
// scene whose textures are re-encoded to reach its materials only through the extension.

#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "renderer/scene/scene.h"

namespace omnishadow::test_support {

// RGBA8, first row = top: red grows to the right, green downwards, blue along the diagonal, and
// alpha falls from 255 at the top to 55 at the bottom.
std::vector<std::uint8_t> cornersPictureRgba(int width, int height);

// The largest difference of channels [firstChannel, firstChannel + channels) of two RGBA8
// pictures of the same size.
int largestChannelDifference(const std::vector<std::uint8_t>& a, const std::vector<std::uint8_t>& b,
                             int firstChannel, int channels);

// Writes folder/scene.gltf: `scene` (a .gltf with data: URI or external buffers) with each of
// its images encoded by `encode` into folder/texture<i>.<suffix>, every texture naming it only
// through `extension`, which the file lists as used and required. Returns the new scene's path.
std::filesystem::path withTexturesThrough(
    const std::filesystem::path& scene, const std::filesystem::path& folder,
    const std::string& extension, const std::string& suffix,
    const std::function<std::vector<unsigned char>(const Image&)>& encode);

}  // namespace omnishadow::test_support
