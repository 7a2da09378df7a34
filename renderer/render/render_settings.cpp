#include "renderer/render/render_settings.h"

namespace omnishadow {

const char* toString(ShadowPassStrategy strategy) {
  switch (strategy) {
    case ShadowPassStrategy::Auto:
      return "auto";
    case ShadowPassStrategy::Six:
      return "six";
    case ShadowPassStrategy::Geometry:
      return "geometry";
    case ShadowPassStrategy::Instanced:
      return "instanced";
    case ShadowPassStrategy::Batched:
      return "batched";
  }
  return "?";
}

ShadowPassStrategy parseShadowPassStrategy(const std::string& name) {
  for (const ShadowPassStrategy s : {ShadowPassStrategy::Six, ShadowPassStrategy::Geometry,
                                     ShadowPassStrategy::Instanced, ShadowPassStrategy::Batched})
    if (name == toString(s)) return s;
  return ShadowPassStrategy::Auto;
}

bool isShadowPassStrategyName(const std::string& name) {
  return name == "auto" || parseShadowPassStrategy(name) != ShadowPassStrategy::Auto;
}

const char* toString(DepthPrepass prepass) {
  switch (prepass) {
    case DepthPrepass::Auto:
      return "auto";
    case DepthPrepass::On:
      return "on";
    case DepthPrepass::Off:
      return "off";
  }
  return "?";
}

DepthPrepass parseDepthPrepass(const std::string& name) {
  for (const DepthPrepass p : {DepthPrepass::On, DepthPrepass::Off})
    if (name == toString(p)) return p;
  return DepthPrepass::Auto;
}

bool isDepthPrepassName(const std::string& name) {
  return name == "auto" || parseDepthPrepass(name) != DepthPrepass::Auto;
}

std::optional<bool> parseFinishEachStage(const std::string& name) {
  if (name == "on") return true;
  if (name == "off") return false;
  return std::nullopt;
}

bool isFinishEachStageName(const std::string& name) {
  return name == "auto" || parseFinishEachStage(name).has_value();
}

void requestObjectIds(RenderSettings& settings) {
  (settings.aovs ? settings.layers.objectId : settings.objectIds) = true;
}

bool drawsLitFrame(const RenderSettings& settings) {
  return settings.beauty || !settings.objectIds || settings.aovs || settings.readShadowMaps ||
         settings.lightViewSize > 0 || settings.debugView != DebugView::None;
}

}  // namespace omnishadow
