#include "renderer/view/sheen_brdf.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace omnishadow {
namespace {

constexpr double kPi = std::numbers::pi;

// The specification's l(x, alpha_g): the fit of Conty and Kulla's shadowing term.
double lambdaFit(double x, double alphaG) {
  const double t = (1.0 - alphaG) * (1.0 - alphaG);
  const auto mix = [t](double a, double b) { return a + (b - a) * t; };
  const double a = mix(21.5473, 25.3245), b = mix(3.82987, 3.32435), c = mix(0.19823, 0.16801),
               d = mix(-1.97760, -1.27393), e = mix(-4.32054, -4.85967);
  return a / (1.0 + b * std::pow(x, c)) + d * x + e;
}

double lambdaSheen(double cosTheta, double alphaG) {
  return std::abs(cosTheta) < 0.5
             ? std::exp(lambdaFit(cosTheta, alphaG))
             : std::exp(2.0 * lambdaFit(0.5, alphaG) - lambdaFit(1.0 - cosTheta, alphaG));
}

}  // namespace

double charlieDistribution(double NdotH, double alphaG) {
  const double inverse = 1.0 / alphaG;
  const double sin2h = std::max(1.0 - NdotH * NdotH, 0.0);
  return (2.0 + inverse) * std::pow(sin2h, 0.5 * inverse) / (2.0 * kPi);
}

double charlieVisibility(double NdotV, double NdotL, double alphaG) {
  return 1.0 /
         ((1.0 + lambdaSheen(NdotV, alphaG) + lambdaSheen(NdotL, alphaG)) * (4.0 * NdotV * NdotL));
}

double sheenDirectionalAlbedo(double mu, double roughness, int steps) {
  const double alphaG = std::max(roughness * roughness, static_cast<double>(kMinSheenAlpha));
  // The shader's floor for NdotV; E(0) is its limit, 0.
  const double muOut = std::clamp(mu, 1e-4, 1.0);
  const double sinOut = std::sqrt(1.0 - muOut * muOut);
  const double dTheta = 0.5 * kPi / steps, dPhi = kPi / steps;  // phi over [0, pi], doubled
  double sum = 0.0;
  for (int i = 0; i < steps; ++i) {
    const double theta = (i + 0.5) * dTheta;
    const double muIn = std::cos(theta), sinIn = std::sin(theta);
    for (int j = 0; j < steps; ++j) {
      const double phi = (j + 0.5) * dPhi;
      // Out = (sinOut, 0, muOut), in = (sinIn cos(phi), sinIn sin(phi), muIn).
      const double hx = sinOut + sinIn * std::cos(phi), hy = sinIn * std::sin(phi),
                   hz = muOut + muIn;
      const double NdotH = hz / std::sqrt(hx * hx + hy * hy + hz * hz);
      sum += charlieDistribution(NdotH, alphaG) * charlieVisibility(muOut, muIn, alphaG) * muIn *
             sinIn;
    }
  }
  return 2.0 * sum * dTheta * dPhi;
}

}  // namespace omnishadow
