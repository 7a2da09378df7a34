#pragma once

#include <string>

#include "renderer/render/render_settings.h"

namespace omnishadow {

// Turns on the layer with this --aov-layers name ("albedo", "roughness", "metallic", "diffuse",
// "specular", "objectId", "materialId", "occlusion"), or every layer for "all". False for any other
// name: each front end words the error its own way.
bool enableAovLayer(AovLayers& layers, const std::string& name);

}  // namespace omnishadow
