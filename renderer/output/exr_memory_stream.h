#pragma once

#include <OpenEXR/ImfIO.h>

#include <cstdint>
#include <cstring>
#include <string>

namespace omnishadow {

// OpenEXR's own file stream reports failed writes while it encodes, but flushes its last
// buffered bytes in a destructor that swallows errors: on a full disk the file could come out
// short without a word. Encoding into memory and writing with writeFileBytes (image_writer.h)
// checks it all.
class ExrMemoryStream : public Imf::OStream {
 public:
  explicit ExrMemoryStream(const std::string& name) : Imf::OStream(name.c_str()) {}
  void write(const char c[], int n) override {
    const auto count = static_cast<std::size_t>(n);
    if (position_ + count > bytes_.size()) bytes_.resize(position_ + count);
    std::memcpy(bytes_.data() + position_, c, count);
    position_ += count;
  }
  std::uint64_t tellp() override { return position_; }
  void seekp(std::uint64_t position) override { position_ = static_cast<std::size_t>(position); }
  const std::string& bytes() const { return bytes_; }

 private:
  std::string bytes_;
  std::size_t position_ = 0;
};

}  // namespace omnishadow
