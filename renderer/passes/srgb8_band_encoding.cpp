#include "renderer/passes/srgb8_band_encoding.h"

#include <algorithm>
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <mutex>
#include <optional>
#include <system_error>
#include <thread>
#include <vector>

#include "renderer/output/image_writer.h"
#include "renderer/scene/srgb_transfer.h"

namespace omnishadow {

namespace {

// 8 rows of a 1280-pixel frame are 160 KB of floats, so the buffers stay in cache between their
// read and their encoding. Bands of 8 to 64 rows took the same time in later frames (Sundial,
// 1280x720); in a process's first frame, whose buffers are fresh pages, 8 rows took 2.7 ms
// against 3.2 for 32 (medians of 10 renders).
constexpr int kBandRows = 8;
// A band's buffer is read into again once the band four before it has been encoded.
constexpr int kBuffers = 4;
// From this many pixels on a second thread encodes: for a small frame its start costs more
// than it saves (the same bound as the CPU encoder's, display_transform.cpp).
constexpr std::size_t kTwoThreadPixels = std::size_t{1} << 18;

// Which bands have been read, taken for encoding and encoded, shared by the reading thread and
// the encoding one. Bands are taken in order, each once, when read.
class BandProgress {
 public:
  explicit BandProgress(int bands) : bands_(bands), encoded_(static_cast<std::size_t>(bands)) {}

  void markRead() {
    {
      std::lock_guard lock(mutex_);
      ++read_;
    }
    changed_.notify_all();
  }
  // The next band read and not taken yet, or nothing for now.
  std::optional<int> tryTake() {
    std::lock_guard lock(mutex_);
    return takeLocked();
  }
  // The next band read and not taken yet, once there is one; nothing when every band is taken.
  std::optional<int> waitTake() {
    std::unique_lock lock(mutex_);
    changed_.wait(lock, [&] { return taken_ < read_ || taken_ == bands_; });
    return takeLocked();
  }
  void markEncoded(int band) {
    {
      std::lock_guard lock(mutex_);
      encoded_[static_cast<std::size_t>(band)] = 1;
    }
    changed_.notify_all();
  }
  bool isEncoded(int band) {
    std::lock_guard lock(mutex_);
    return encoded_[static_cast<std::size_t>(band)] != 0;
  }
  void waitEncoded(int band) {
    std::unique_lock lock(mutex_);
    changed_.wait(lock, [&] { return encoded_[static_cast<std::size_t>(band)] != 0; });
  }

 private:
  std::optional<int> takeLocked() {
    if (taken_ == read_) return std::nullopt;
    return taken_++;
  }

  std::mutex mutex_;
  std::condition_variable changed_;
  const int bands_;
  int read_ = 0, taken_ = 0;
  std::vector<char> encoded_;
};

}  // namespace

Srgb8Image readSrgb8InBands(GLuint texture, int width, int height, const TexelRegion& drawn,
                            float exposureScale, bool glRowOrder) {
  const int w = width, h = height;
  Srgb8Image image{w, h, std::vector<std::uint8_t>(static_cast<std::size_t>(w) * h * 3)};
  // Outside `drawn` every pixel holds the clear value, zeros, whose bytes at any exposure are
  // the zeros the picture starts with: they are not read back.
  const TexelRegion read = drawn.clipped(TexelRect::whole(w, h));
  const TexelRect bounds = read.bounds();
  if (bounds.empty()) return image;
  // A band's pieces of the region lie side by side within the bounds' columns, so that a band's
  // buffer holds them all.
  const std::size_t boundsRow = static_cast<std::size_t>(bounds.x1 - bounds.x0) * 4;
  const int bands = (bounds.y1 - bounds.y0 + kBandRows - 1) / kBandRows;
  const int bufferCount = std::min(bands, kBuffers);
  std::vector<FloatPixels> buffers(static_cast<std::size_t>(bufferCount),
                                   FloatPixels(boundsRow * kBandRows));
  // Each band's pieces of the region, in the order its buffer holds them: found once, for the
  // reading thread and the encoding one alike.
  std::vector<TexelRegion> pieces;
  pieces.reserve(static_cast<std::size_t>(bands));
  for (int band = 0; band < bands; ++band) {
    const int y0 = bounds.y0 + band * kBandRows;
    pieces.push_back(read.clipped({bounds.x0, y0, bounds.x1, std::min(y0 + kBandRows, bounds.y1)}));
  }
  const auto piecesOf = [&](int band) -> const std::vector<TexelRect>& {
    return pieces[static_cast<std::size_t>(band)].rects();
  };
  // Bands in GL's order (bottom first); each row is encoded into its place in the picture, as
  // readChannels() places them, so the rows need no turning around.
  const auto encode = [&](int band) {
    const float* pixels = buffers[static_cast<std::size_t>(band % bufferCount)].data();
    for (const TexelRect& piece : piecesOf(band)) {
      const auto pieceWidth = static_cast<std::size_t>(piece.x1 - piece.x0);
      for (int glRow = piece.y0; glRow < piece.y1; ++glRow, pixels += pieceWidth * 4) {
        const int y = glRowOrder ? glRow : h - 1 - glRow;
        rgbaToSrgb8Rgb(pixels, pieceWidth, exposureScale,
                       image.rgb.data() + (static_cast<std::size_t>(y) * w + piece.x0) * 3);
      }
    }
  };

  BandProgress progress(bands);
  std::thread encoder;
  if (static_cast<std::size_t>(read.texels()) >= kTwoThreadPixels &&
      std::thread::hardware_concurrency() >= 2) {
    try {
      encoder = std::thread([&] {
        while (const std::optional<int> band = progress.waitTake()) {
          encode(*band);
          progress.markEncoded(*band);
        }
      });
    } catch (const std::system_error&) {
      // No second thread: this one encodes each band after reading it.
    }
  }
  // This thread encodes what is ready while it waits for a buffer, and whatever is left at the
  // end.
  const auto encodeOne = [&] {
    const std::optional<int> band = progress.tryTake();
    if (!band) return false;
    encode(*band);
    progress.markEncoded(*band);
    return true;
  };
  for (int band = 0; band < bands; ++band) {
    const int previous = band - bufferCount;
    if (previous >= 0)
      while (!progress.isEncoded(previous))
        if (!encodeOne()) progress.waitEncoded(previous);
    FloatPixels& buffer = buffers[static_cast<std::size_t>(band % bufferCount)];
    std::size_t at = 0;
    for (const TexelRect& piece : piecesOf(band)) {
      const std::size_t floats = static_cast<std::size_t>(piece.texels()) * 4;
      glGetTextureSubImage(texture, 0, piece.x0, piece.y0, 0, piece.x1 - piece.x0,
                           piece.y1 - piece.y0, 1, GL_RGBA, GL_FLOAT,
                           static_cast<GLsizei>(floats * sizeof(float)), buffer.data() + at);
      at += floats;
    }
    progress.markRead();
    if (!encoder.joinable()) encodeOne();
  }
  while (encodeOne()) {
  }
  for (int band = 0; band < bands; ++band) progress.waitEncoded(band);
  if (encoder.joinable()) encoder.join();
  return image;
}

}  // namespace omnishadow
