#include "renderer/scene/pixel_bytes.h"

#include <atomic>
#include <cstring>
#include <utility>

namespace omnishadow {

namespace pixel_detail {

struct PixelBuffer {
  std::vector<std::uint8_t> bytes;
  // Set once a Watch was made: a holder alone (use_count 1) may still not change the bytes in
  // place, since a Watch may lock them on another thread at any time.
  std::atomic<bool> watched{false};
};

}  // namespace pixel_detail

using pixel_detail::PixelBuffer;

namespace {

std::shared_ptr<PixelBuffer> bufferOf(std::vector<std::uint8_t> bytes) {
  if (bytes.empty()) return nullptr;
  auto buffer = std::make_shared<PixelBuffer>();
  buffer->bytes = std::move(bytes);
  return buffer;
}

}  // namespace

PixelBytes::PixelBytes(std::vector<std::uint8_t> bytes) : buffer_(bufferOf(std::move(bytes))) {}

PixelBytes::PixelBytes(std::initializer_list<std::uint8_t> bytes)
    : buffer_(bufferOf(std::vector<std::uint8_t>(bytes))) {}

std::size_t PixelBytes::size() const {
  return buffer_ ? buffer_->bytes.size() : 0;
}

const std::uint8_t* PixelBytes::data() const {
  return buffer_ ? buffer_->bytes.data() : nullptr;
}

std::uint8_t* PixelBytes::data() {
  return buffer_ ? own().data() : nullptr;
}

void PixelBytes::assign(std::size_t count, std::uint8_t value) {
  own().assign(count, value);
}

void PixelBytes::resize(std::size_t count) {
  own().resize(count);
}

void PixelBytes::insert(const_iterator at, std::initializer_list<std::uint8_t> bytes) {
  const auto offset = static_cast<std::ptrdiff_t>(at - data());
  std::vector<std::uint8_t>& mine = own();
  mine.insert(mine.begin() + offset, bytes);
}

PixelBytes::Watch PixelBytes::watch() {
  Watch watch;
  if (!buffer_) return watch;
  buffer_->watched = true;
  watch.buffer_ = buffer_;
  return watch;
}

PixelBytes PixelBytes::lock(const Watch& watch) {
  PixelBytes bytes;
  bytes.buffer_ = watch.buffer_.lock();
  return bytes;
}

PixelBytes::operator const std::vector<std::uint8_t>&() const {
  static const std::vector<std::uint8_t> none;
  return buffer_ ? buffer_->bytes : none;
}

bool operator==(const PixelBytes& a, const std::vector<std::uint8_t>& b) {
  return static_cast<const std::vector<std::uint8_t>&>(a) == b;
}

bool operator==(const PixelBytes& a, const PixelBytes& b) {
  return a.size() == b.size() &&
         (a.sharesWith(b) || a.size() == 0 || std::memcmp(a.data(), b.data(), a.size()) == 0);
}

std::vector<std::uint8_t>& PixelBytes::own() {
  if (!buffer_) {
    buffer_ = std::make_shared<PixelBuffer>();
  } else if (buffer_.use_count() > 1 || buffer_->watched) {
    auto copy = std::make_shared<PixelBuffer>();
    copy->bytes = buffer_->bytes;
    buffer_ = std::move(copy);
  }
  return buffer_->bytes;
}

}  // namespace omnishadow
