#pragma once

#include <GL/glcorearb.h>

#include "renderer/render/frame.h"
#include "renderer/view/texel_region.h"

namespace omnishadow {

// The 8-bit beauty of a frame drawn into a float target (blended or see-through surfaces), made
// on the CPU as the target is read back: what toSrgb8() makes of the float beauty with
// `exposureScale` (2^stops), byte for byte, first row = top unless `glRowOrder`.
//
// The rows come a band at a time into a few buffers that stay in cache, and a second thread
// encodes the bands this one has read while it reads the next. Reading the whole float target
// first took 14.7 MB of fresh memory for a 1280x720 frame, whose pages faulted in the first frame
// of a process (about 3,600 faults), and a second pass over it to encode. On llvmpipe, Sundial's
// first frame: readback 9.7 -> 2.7 ms, PNG encoding 11.6 -> 8.7 (medians of 10 renders); a later
// frame's readback 1.5 -> 2.9, now with the encoding in it.
//
// Only the pixels of `drawn` (GL's window coordinates: FrameTargets::drawn()) are read and
// encoded, each band's pieces of it one after another; every other pixel holds the clear value,
// zeros, whose bytes are written instead. Sundial's drawn rectangle is half its 1280x720 frame
// (steady readback 2.5 -> 1.5 ms), its drawn region 63% of that rectangle (1.5 -> 1.2 ms).
Srgb8Image readSrgb8InBands(GLuint texture, int width, int height, const TexelRegion& drawn,
                            float exposureScale, bool glRowOrder);

}  // namespace omnishadow
