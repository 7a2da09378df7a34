#include "renderer/output/png_decoder.h"

#include <png.h>

#include <csetjmp>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <vector>

#include "renderer/core/errors.h"
#include "renderer/output/image_limits.h"

namespace omnishadow {
namespace {

// Everything the decoder touches lives here, outside the frame that calls setjmp, so that
// libpng's longjmp on an error leaves nothing half-destroyed.
struct PngRead {
  explicit PngRead(const std::string& file) : bytes(file) {}
  const std::string& bytes;
  std::size_t position = 8;  // after the signature, which the caller checked
  png_structp png = nullptr;
  png_infop info = nullptr;
  std::string error;
  png_uint_32 width = 0, height = 0;
  int channels = 0, bitDepth = 0;
  std::vector<std::uint8_t> data;
  std::vector<png_bytep> rows;

  ~PngRead() { png_destroy_read_struct(&png, info ? &info : nullptr, nullptr); }
};

void readBytes(png_structp png, png_bytep out, png_size_t count) {
  auto* read = static_cast<PngRead*>(png_get_io_ptr(png));
  if (read->bytes.size() - read->position < count) png_error(png, "file is truncated");
  std::memcpy(out, read->bytes.data() + read->position, count);
  read->position += count;
}

[[noreturn]] void onError(png_structp png, png_const_charp message) {
  static_cast<PngRead*>(png_get_error_ptr(png))->error = message;
  png_longjmp(png, 1);
}

void onWarning(png_structp, png_const_charp) {}

// False with read.error set when libpng gave up. No object with a destructor may live in the
// frames that call setjmp (longjmp would skip it), so the size check, which builds a message,
// runs between the two.
bool readInfo(PngRead& read) {
  if (setjmp(png_jmpbuf(read.png))) return false;
  png_set_read_fn(read.png, &read, readBytes);
  png_set_sig_bytes(read.png, 8);
  png_read_info(read.png, read.info);
  png_set_expand(read.png);  // palette -> RGB, grey < 8 bits -> 8, tRNS -> alpha
  if (png_get_bit_depth(read.png, read.info) == 16) png_set_swap(read.png);  // host order
  png_set_interlace_handling(read.png);
  png_read_update_info(read.png, read.info);
  read.width = png_get_image_width(read.png, read.info);
  read.height = png_get_image_height(read.png, read.info);
  read.channels = png_get_channels(read.png, read.info);
  read.bitDepth = png_get_bit_depth(read.png, read.info);
  return true;
}

bool readImage(PngRead& read) {
  if (setjmp(png_jmpbuf(read.png))) return false;
  const std::size_t rowBytes = png_get_rowbytes(read.png, read.info);
  read.data.resize(rowBytes * read.height);
  read.rows.resize(read.height);
  for (png_uint_32 y = 0; y < read.height; ++y) read.rows[y] = read.data.data() + y * rowBytes;
  png_read_image(read.png, read.rows.data());
  png_read_end(read.png, nullptr);
  return true;
}

}  // namespace

FloatImage decodePng(const std::string& bytes, const std::string& name) {
  auto fail = [&](const std::string& reason) {
    return InputError(name + ": cannot read image: " + reason);
  };
  if (bytes.size() < 8 || png_sig_cmp(reinterpret_cast<png_const_bytep>(bytes.data()), 0, 8))
    throw fail("not a PNG file");
  PngRead read(bytes);
  read.png = png_create_read_struct(PNG_LIBPNG_VER_STRING, &read, onError, onWarning);
  if (!read.png) throw fail("out of memory");
  read.info = png_create_info_struct(read.png);
  if (!read.info) throw fail("out of memory");
  if (!readInfo(read)) throw fail(read.error);
  const std::string sizeProblem = imageSizeProblem(read.width, read.height, read.channels);
  if (!sizeProblem.empty()) throw fail(sizeProblem);
  if (!readImage(read)) throw fail(read.error);

  FloatImage image;
  image.width = static_cast<int>(read.width);
  image.height = static_cast<int>(read.height);
  static const std::vector<std::string> kNames[] = {
      {}, {"Y"}, {"Y", "A"}, {"R", "G", "B"}, {"R", "G", "B", "A"}};
  image.channels = kNames[read.channels];
  // Times the reciprocal, not divided: OpenImageIO's conversion, to the last bit.
  const std::size_t count = static_cast<std::size_t>(read.width) * read.height * read.channels;
  image.pixels.resize(count);
  if (read.bitDepth == 16) {
    for (std::size_t i = 0; i < count; ++i) {
      std::uint16_t value;
      std::memcpy(&value, read.data.data() + 2 * i, 2);
      image.pixels[i] = static_cast<float>(value) * (1.0f / 65535.0f);
    }
  } else {
    for (std::size_t i = 0; i < count; ++i)
      image.pixels[i] = static_cast<float>(read.data[i]) * (1.0f / 255.0f);
  }
  return image;
}

}  // namespace omnishadow
