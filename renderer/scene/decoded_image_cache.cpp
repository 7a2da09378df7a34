#include "renderer/scene/decoded_image_cache.h"

#include <cstring>
#include <functional>
#include <string_view>
#include <utility>

namespace omnishadow {

struct DecodedImageCache::Pending {
  std::size_t digest = 0;
  std::promise<std::optional<Picture>> promise;
  std::shared_future<std::optional<Picture>> result = promise.get_future().share();
};

namespace {

std::size_t digestOf(const unsigned char* bytes, std::size_t size) {
  return std::hash<std::string_view>{}(
      std::string_view(reinterpret_cast<const char*>(bytes), size));
}

}  // namespace

DecodedImageCache::Lookup DecodedImageCache::find(const unsigned char* bytes, std::size_t size) {
  const std::size_t digest = digestOf(bytes, size);
  std::shared_future<std::optional<Picture>> decoding;
  {
    std::lock_guard lock(mutex_);
    const auto [first, last] = entries_.equal_range(digest);
    for (auto it = first; it != last; ++it) {
      Entry& entry = it->second;
      if (entry.encoded.size() != size || std::memcmp(entry.encoded.data(), bytes, size) != 0)
        continue;
      if (entry.pending) {
        decoding = entry.pending->result;
        break;
      }
      Picture picture = entry.picture;
      picture.rgba = PixelBytes::lock(entry.rgba);
      if (!picture.rgba.empty()) return {std::move(picture), nullptr};
      entries_.erase(it);  // no scene holds it any more
      break;
    }
    if (!decoding.valid()) {
      auto claim = std::make_shared<Pending>();
      claim->digest = digest;
      Entry entry;
      entry.encoded.assign(bytes, bytes + size);
      entry.pending = claim;
      entries_.emplace(digest, std::move(entry));
      return {std::nullopt, std::move(claim)};
    }
  }
  // Another load is decoding these bytes: its picture, or, if it could not, a decode of our
  // own (which meets the same error), without a claim.
  std::optional<Picture> picture = decoding.get();
  return {std::move(picture), nullptr};
}

void DecodedImageCache::fulfil(const std::shared_ptr<Pending>& claim, const Picture& picture) {
  settle(claim, &picture);
}

void DecodedImageCache::abandon(const std::shared_ptr<Pending>& claim) {
  settle(claim, nullptr);
}

void DecodedImageCache::settle(const std::shared_ptr<Pending>& claim, const Picture* picture) {
  if (!claim) return;
  PixelBytes::Watch watch;
  if (picture) {
    PixelBytes pixels = picture->rgba;
    watch = pixels.watch();
  }
  {
    std::lock_guard lock(mutex_);
    for (auto it = entries_.begin(); it != entries_.end();) {
      Entry& entry = it->second;
      if (entry.pending == claim) {
        if (!picture || picture->rgba.empty()) {
          it = entries_.erase(it);
          continue;
        }
        entry.pending.reset();
        entry.picture = *picture;
        entry.picture.rgba = {};
        entry.rgba = watch;
      } else if (!entry.pending && entry.rgba.expired()) {
        it = entries_.erase(it);  // no scene holds it any more
        continue;
      }
      ++it;
    }
  }
  claim->promise.set_value(picture && !picture->rgba.empty() ? std::optional<Picture>(*picture)
                                                             : std::nullopt);
}

std::size_t DecodedImageCache::size() const {
  std::lock_guard lock(mutex_);
  std::size_t held = 0;
  for (const auto& [digest, entry] : entries_)
    held += !entry.pending && !entry.rgba.expired() ? 1 : 0;
  return held;
}

}  // namespace omnishadow
