// KHR_materials_sheen's BRDF on the CPU (renderer/view/sheen_brdf.h) and the directional albedo
// table the build computes from it: the distribution is a normalized one, the table holds the
// integral it says it holds, and its lookup interpolates it. No GL.
#include "renderer/view/sheen_brdf.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "renderer/view/sheen_albedo_table.h"

namespace omnishadow::sheen_brdf_test {
namespace {

constexpr double kPi = std::numbers::pi;

// Any microfacet distribution projects to the unit disc: the integral of D(h) (N.h) over the
// hemisphere of h is 1. Checked for the Charlie distribution as the specification writes it,
// with its roughness mapping alpha_g = r^2, by a midpoint rule in the polar angle (D does not
// depend on the azimuth).
TEST(SheenBrdf, CharlieDistributionIsNormalized) {
  for (const double roughness : {0.1, 0.3, 0.5, 0.8, 1.0}) {
    const double alphaG = roughness * roughness;
    const int steps = 200000;
    const double dTheta = 0.5 * kPi / steps;
    double sum = 0.0;
    for (int i = 0; i < steps; ++i) {
      const double theta = (i + 0.5) * dTheta;
      sum += charlieDistribution(std::cos(theta), alphaG) * std::cos(theta) * std::sin(theta);
    }
    EXPECT_NEAR(2.0 * kPi * sum * dTheta, 1.0, 1e-4) << "roughness " << roughness;
  }
}

// The specification's visibility is symmetric in V and L, and the lambda fit's two branches
// meet at a cosine of 0.5 (they are one function there).
TEST(SheenBrdf, CharlieVisibilityIsSymmetricAndContinuous) {
  for (const double alphaG : {0.01, 0.16, 0.49, 1.0}) {
    EXPECT_DOUBLE_EQ(charlieVisibility(0.3, 0.8, alphaG), charlieVisibility(0.8, 0.3, alphaG));
    const double below = charlieVisibility(0.5 - 1e-9, 0.7, alphaG);
    const double above = charlieVisibility(0.5 + 1e-9, 0.7, alphaG);
    EXPECT_NEAR(below, above, 1e-6 * above) << "alpha_g " << alphaG;
  }
}

// Each entry of the table is E at its grid point: the integral at four times the table's
// steps per angle agrees within 2e-3 where E <= 1, and entries are 1 where it exceeds 1 (the
// visibility fit's grazing excess, clamped). Every fourth cosine and roughness, and the ends.
TEST(SheenAlbedoTable, HoldsTheDirectionalAlbedoAtItsGrid) {
  const auto& table = sheenAlbedoTable();
  int clamped = 0, checked = 0;
  for (int j = 0; j < kSheenAlbedoRoughnesses; j += (j + 4 < kSheenAlbedoRoughnesses ? 4 : 3)) {
    for (int i = 0; i < kSheenAlbedoCosines; i += (i + 4 < kSheenAlbedoCosines ? 4 : 3)) {
      const double mu = static_cast<double>(i) / (kSheenAlbedoCosines - 1);
      const double roughness = static_cast<double>(j) / (kSheenAlbedoRoughnesses - 1);
      const double fine = sheenDirectionalAlbedo(mu, roughness, 4 * kSheenAlbedoSteps);
      const float entry = table[j * kSheenAlbedoCosines + i];
      if (fine > 1.0 + 2e-3) {
        EXPECT_EQ(entry, 1.0f) << "mu " << mu << " roughness " << roughness;
        ++clamped;
      } else {
        EXPECT_NEAR(entry, std::min(fine, 1.0), 2e-3) << "mu " << mu << " roughness " << roughness;
      }
      ++checked;
    }
  }
  EXPECT_EQ(checked, 9 * 5);
  EXPECT_GE(clamped, 1);  // the grazing entries of roughness 0
  for (const float e : table) {
    EXPECT_GE(e, 0.0f);
    EXPECT_LE(e, 1.0f);
  }
}

// E falls from grazing to normal incidence for every roughness from 0.2 on (a sheen is a
// grazing-angle effect), and at normal incidence grows with roughness (from 0.4 on: below, it
// is 0 to the table's seven digits).
TEST(SheenAlbedoTable, SheenIsAGrazingAngleEffect) {
  for (int j = 3; j < kSheenAlbedoRoughnesses; ++j) {
    const float roughness = static_cast<float>(j) / (kSheenAlbedoRoughnesses - 1);
    EXPECT_GT(sheenAlbedo(0.1f, roughness), sheenAlbedo(0.5f, roughness)) << roughness;
    EXPECT_GT(sheenAlbedo(0.5f, roughness), sheenAlbedo(1.0f, roughness)) << roughness;
    if (j >= 6) {
      EXPECT_GT(sheenAlbedo(1.0f, roughness), sheenAlbedo(1.0f, roughness - 0.2f)) << roughness;
    }
  }
}

// The lookup returns the entries at grid points, interpolates linearly in each axis between
// them, and clamps both arguments to [0, 1].
TEST(SheenAlbedoTable, LookupInterpolatesBilinearlyAndClamps) {
  const auto& table = sheenAlbedoTable();
  const auto entry = [&](int i, int j) { return table[j * kSheenAlbedoCosines + i]; };
  const float du = 1.0f / (kSheenAlbedoCosines - 1), dr = 1.0f / (kSheenAlbedoRoughnesses - 1);
  EXPECT_FLOAT_EQ(sheenAlbedo(5 * du, 7 * dr), entry(5, 7));
  EXPECT_FLOAT_EQ(sheenAlbedo(1.0f, 1.0f),
                  entry(kSheenAlbedoCosines - 1, kSheenAlbedoRoughnesses - 1));
  EXPECT_NEAR(sheenAlbedo(5.25f * du, 7 * dr), 0.75f * entry(5, 7) + 0.25f * entry(6, 7), 1e-6f);
  EXPECT_NEAR(sheenAlbedo(5 * du, 7.5f * dr), 0.5f * entry(5, 7) + 0.5f * entry(5, 8), 1e-6f);
  EXPECT_EQ(sheenAlbedo(-0.5f, 2.0f), sheenAlbedo(0.0f, 1.0f));
  EXPECT_EQ(sheenAlbedo(1.5f, -1.0f), sheenAlbedo(1.0f, 0.0f));
}

}  // namespace
}  // namespace omnishadow::sheen_brdf_test
