// Chi-square tests of every BSDF's sample() against its pdf() over the grid of
// bsdf_test_cases.h (pbrt-v4 and Mitsuba style; fixed seeds).
#include <gtest/gtest.h>

#include "render/bsdf/bsdf_test_cases.h"
#include "render/bsdf/chi_square.h"

namespace tessera::test {
namespace {

void run_chi_square(MaterialType type) {
  const BsdfCases cases(type == MaterialType::rough_plastic);
  const std::vector<BsdfCase> selected = cases.of(type);
  ASSERT_FALSE(selected.empty());
  int tests = 0;
  for (const BsdfCase& c : selected) tests += int(test_wos(c.two_sided_wo).size());
  // Bonferroni: the whole test fails by chance with probability below 1 %.
  const double alpha = 0.01 / tests;
  uint64_t seed = 1;
  for (const BsdfCase& c : selected) {
    const Bsdf bsdf(c.params);
    for (glm::vec3 wo : test_wos(c.two_sided_wo)) {
      const ChiSquareResult r = chi_square_test(bsdf, wo, seed++, 100000, alpha);
      EXPECT_TRUE(r.passed) << c.name << ", wo (" << wo.x << ", " << wo.y << ", " << wo.z
                            << "): " << r.message;
    }
  }
}

TEST(BsdfChiSquare, Diffuse) { run_chi_square(MaterialType::diffuse); }
TEST(BsdfChiSquare, RoughConductor) { run_chi_square(MaterialType::rough_conductor); }
TEST(BsdfChiSquare, RoughDielectric) { run_chi_square(MaterialType::rough_glass); }
TEST(BsdfChiSquare, Plastic) { run_chi_square(MaterialType::plastic); }
TEST(BsdfChiSquare, RoughPlastic) { run_chi_square(MaterialType::rough_plastic); }
TEST(BsdfChiSquare, Principled) { run_chi_square(MaterialType::principled); }
TEST(BsdfChiSquare, PrincipledThin) { run_chi_square(MaterialType::principled_thin); }
TEST(BsdfChiSquare, PPlastic) { run_chi_square(MaterialType::pplastic); }
TEST(BsdfChiSquare, Blend) { run_chi_square(MaterialType::blend); }

}  // namespace
}  // namespace tessera::test
