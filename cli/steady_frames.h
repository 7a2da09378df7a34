#pragma once

#include "cli/render_job.h"
#include "renderer/render/renderer.h"

namespace omnishadow::cli {

// `render --repeat N`: after the frame that is written, renders the same job N more times on the
// same renderer (context, compiled shaders and shadow textures warm) and prints the median of
// each stage of those frames to stderr, as "steady <stage>" lines and "steady frame" (shadow
// maps + lighting + readback, the frame time peers/compare.py compares with three.js's steady
// frame). The lights move by 1 mm every other frame so that no shadow map is reused from the
// frame before: every frame renders its shadow maps, as three.js does. Nothing is written.
void printSteadyFrames(Renderer& renderer, const RenderJob& job, const LoadedJob& loaded,
                       int repeat);

}  // namespace omnishadow::cli
