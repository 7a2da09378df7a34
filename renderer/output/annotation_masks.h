#pragma once

#include <cstdint>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "renderer/output/image_writer.h"
#include "renderer/output/output_transaction.h"
#include "renderer/scene/scene.h"
#include "renderer/view/camera.h"

namespace omnishadow {

// Annotation masks of one frame (--masks), made from its objectId AOV: exact, one surface per
// pixel (the one at the pixel's center). Rows top first.
struct AnnotationMasks {
  int width = 0;
  int height = 0;
  std::vector<std::uint16_t> instances;  // mesh instance (objectId) + 1; 0 = background
  std::vector<std::uint16_t> classes;    // class id (index["classes"]); 0 = background
  // {"instances": [{id, objectId, node, nodeName, mesh, material, materialId, class, classId,
  //   pixels, bbox, visibleFraction}], "classes": [{id, name}], "background": 0}.
  // bbox = [xmin, ymin, xmax, ymax] in pixels, max exclusive, null when no pixel is visible.
  // visibleFraction = pixels / the pixel centers the instance covers when drawn alone
  // (coveredPixelCount()), at most 1; null when it covers none (outside the view).
  nlohmann::ordered_json index;
};

// An instance's class: its node's extras "class" string, else the node's name, else the glTF
// mesh's name, else "node <index>".
std::string instanceClass(const Scene& scene, const MeshInstance& instance);

// A 16-bit mask holds the ids of at most this many mesh instances (0 is the background).
inline constexpr std::size_t kMaxMaskInstances = 65535;
// Throws InputError, naming `source` (the scene's file) when given, for a scene with more.
void checkMaskInstances(const Scene& scene, const std::string& source = {});

// From a frame's AOVs with the objectId layer. Throws InputError when the scene has more mesh
// instances than a 16-bit mask holds.
AnnotationMasks annotationMasks(const Scene& scene, const ViewCamera& camera,
                                const FloatImage& aovs);

// "<stem>.instances.png", "<stem>.semantic.png" (16-bit grey PNG) and "<stem>.masks.json".
std::vector<std::filesystem::path> annotationMaskFiles(const std::filesystem::path& stem);
// The bytes of those three files. Encoding the PNGs is most of the work of writing them, so it
// may run on another thread than the one that writes (the CLI's, while the beauty encodes).
struct EncodedAnnotationMasks {
  std::string instances, semantic, index;
};
EncodedAnnotationMasks encodeAnnotationMasks(const AnnotationMasks& masks);
void writeAnnotationMasks(const EncodedAnnotationMasks& files, const std::filesystem::path& stem,
                          OutputTransaction& transaction);

}  // namespace omnishadow
