// Internal to the scene library: what the glTF loader lets a file make it read and decode.
#pragma once

#include <tiny_gltf.h>

#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

#include "renderer/scene/gltf_data_uris.h"

namespace omnishadow::gltf_detail {

// glTF images are PNG or JPEG (WebP and AVIF through their extensions), and only those reach a
// decoder: stb_image's others would take almost any bytes for a TGA (a format without a
// signature).
bool isDecodableImage(const unsigned char* b, std::size_t size);

// KTX2 or DDS: formats that only texture extensions (KHR_texture_basisu, MSFT_texture_dds)
// bring, which the loader never decodes.
bool isExtensionImageFormat(const unsigned char* b, std::size_t size);

// "image/png", "image/jpeg", "image/webp" or "image/avif" as the bytes' signature says; empty
// for anything else.
std::string imageMimeType(const unsigned char* bytes, std::size_t size);

// Empty string when a PNG, JPEG, WebP or AVIF may be decoded, else why not.
std::string imageTooLarge(const unsigned char* bytes, std::size_t size);

// Decodes a PNG, JPEG, WebP or AVIF that passed the checks above into `image`, as
// tinygltf::LoadImageData would (width, height, component, bits, pixel_type, image): JPEG with
// libjpeg-turbo, and with stb_image (tinygltf's decoder) the CMYK JPEGs libjpeg-turbo does not
// turn into RGB; PNG with libdeflate or stb_image; WebP with libwebp; AVIF with libavif.
// Sets `image`'s mimeType to what the bytes are (imageMimeType). Damaged
// JPEG data that still gives a picture adds a line to `warning`; a JPEG libjpeg-turbo refuses is an
// error, not tried again with stb_image.
bool decodeImage(tinygltf::Image* image, int index, std::string* error, std::string* warning,
                 const unsigned char* bytes, int size);

// tinygltf's image loader (TinyGLTF::SetImageLoader): checks images read from URIs as above and
// decodes those in the data: URIs tinygltf decoded; it leaves those in bufferViews to the
// loader, which checks their bounds first, and keeps the bytes of those in files of their own
// and of those in the data: URIs the reader took (Image::as_is) for the loader to decode with
// the other images. Its user data is the reader's DataUris (or nullptr), which tells the latter.
bool decodeUriImage(tinygltf::Image* image, int index, std::string* error, std::string* warning,
                    int width, int height, const unsigned char* bytes, int size, void*);

// Where external files may come from: the scene's folder (and below), unless the user allows
// any path. Files a .gltf names are read only through this check, so a downloaded scene cannot
// make the renderer read /etc/passwd or ../../secrets into a texture.
struct UriPolicy {
  std::filesystem::path folder;  // canonical
  bool allowExternal = false;
  std::string violation;  // the first refused path, for the error message
  // The data: URIs the reader took out of the JSON: their placeholder names are served from
  // memory, before any lookup (gltf_data_uris.h).
  DataUris* dataUris = nullptr;
};

// tinygltf's file callbacks (FsCallbacks::FileExists and ReadWholeFile), with a UriPolicy as
// their user data: external files are looked up and read only where the policy permits.
bool existsWithinFolder(const std::string& filepath, void* user);
bool readWithinFolder(std::vector<unsigned char>* out, std::string* error,
                      const std::string& filepath, void* user);

}  // namespace omnishadow::gltf_detail
