#pragma once

#include <cstddef>
#include <cstdint>
#include <initializer_list>
#include <memory>
#include <vector>

namespace omnishadow {

namespace pixel_detail {
struct PixelBuffer;  // the bytes, and whether a Watch may see them
}  // namespace pixel_detail

// The bytes of a decoded picture (Image::rgba). Copies share them until one of them is changed
// (copy on write): a scene copied to be posed keeps one copy of its pixels, and so do the scenes
// of a batch whose files hold the same image bytes (DecodedImageCache). Reading through a const
// object never copies; the changing members (non-const data(), operator[], begin(), end(),
// assign, resize, insert) make the bytes this object's own first, so write through a
// PixelBytes that is not const only where it is meant to change.
class PixelBytes {
 public:
  using value_type = std::uint8_t;
  using iterator = std::uint8_t*;
  using const_iterator = const std::uint8_t*;

  // A reference that does not keep the bytes alive, for a cache of what others hold.
  class Watch {
   public:
    bool expired() const { return buffer_.expired(); }

   private:
    friend class PixelBytes;
    std::weak_ptr<pixel_detail::PixelBuffer> buffer_;
  };

  PixelBytes() = default;
  // Implicit, as the std::vector it stands for: `image.rgba = decoded` and `= {1, 2, 3, 4}`.
  PixelBytes(std::vector<std::uint8_t> bytes);  // NOLINT(google-explicit-constructor)
  PixelBytes(std::initializer_list<std::uint8_t> bytes);

  std::size_t size() const;
  bool empty() const { return size() == 0; }
  const std::uint8_t* data() const;
  const std::uint8_t& operator[](std::size_t i) const { return data()[i]; }
  const_iterator begin() const { return data(); }
  const_iterator end() const { return data() + size(); }

  std::uint8_t* data();
  std::uint8_t& operator[](std::size_t i) { return data()[i]; }
  iterator begin() { return data(); }
  iterator end() { return data() + size(); }
  void assign(std::size_t count, std::uint8_t value);
  void resize(std::size_t count);
  void insert(const_iterator at, std::initializer_list<std::uint8_t> bytes);

  // A Watch of these bytes. From now on a change through any PixelBytes that holds them copies
  // them first, since whoever locks the Watch may be reading them on another thread.
  Watch watch();
  // The bytes a Watch still sees, or empty bytes when every holder has let them go.
  static PixelBytes lock(const Watch& watch);
  // Whether the two hold the very same bytes (not a copy).
  bool sharesWith(const PixelBytes& other) const { return buffer_ && buffer_ == other.buffer_; }

  // The bytes as the vector that keeps them, for code that reads a std::vector.
  operator const std::vector<std::uint8_t>&() const;  // NOLINT(google-explicit-constructor)

  friend bool operator==(const PixelBytes& a, const PixelBytes& b);
  friend bool operator==(const PixelBytes& a, const std::vector<std::uint8_t>& b);

 private:
  std::vector<std::uint8_t>& own();

  std::shared_ptr<pixel_detail::PixelBuffer> buffer_;  // null: no bytes
};

}  // namespace omnishadow
