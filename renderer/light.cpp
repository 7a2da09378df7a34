#include "renderer/light.h"

namespace omnishadow {

const char* toString(LightType type) {
  switch (type) {
    case LightType::Point: return "point";
    case LightType::Spot: return "spot";
    case LightType::Directional: return "directional";
  }
  return "?";
}

const char* toString(ShadowFilter filter) {
  switch (filter) {
    case ShadowFilter::Hard: return "hard";
    case ShadowFilter::Pcf: return "pcf";
    case ShadowFilter::PcfDisk: return "pcf-disk";
  }
  return "?";
}

}  // namespace omnishadow
