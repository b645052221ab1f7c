// The directional albedo of the rough BSDFs (and the plastic) against Mitsuba 3's, from the
// table mitsuba_albedo.txt that mitsuba_albedo.py made: the same definitions of D, G, Fresnel
// and the plastics' internal scattering give the same fraction of scattered light within 1 %.
#include <cmath>
#include <fstream>
#include <iostream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "render/bsdf/albedo_estimate.h"
#include "render/bsdf/bsdf.h"
#include "render/bsdf/bsdf_test_cases.h"

namespace tessera::test {
namespace {

struct AlbedoRow {
  int line = 0;
  std::string type, distribution;
  float alpha_u = 0, alpha_v = 0, eta = 0, cos_theta_o = 0;
  bool nonlinear = false, sample_visible = true;
  glm::dvec3 albedo{0.0}, se{0.0};
};

std::vector<AlbedoRow> read_table(std::string* header) {
  const std::string path =
      std::string(TESSERA_SOURCE_DIR) + "/worker/render/bsdf/mitsuba_albedo.txt";
  std::ifstream in(path);
  EXPECT_TRUE(in) << "cannot read " << path;
  std::vector<AlbedoRow> rows;
  std::string text;
  for (int line = 1; std::getline(in, text); ++line) {
    if (text.empty()) continue;
    if (text[0] == '#') {
      *header += text + "\n";
      continue;
    }
    std::istringstream s(text);
    AlbedoRow r;
    r.line = line;
    int nonlinear = 0, visible = 1;
    s >> r.type >> r.distribution >> r.alpha_u >> r.alpha_v >> r.eta >> nonlinear >> visible >>
        r.cos_theta_o >> r.albedo.x >> r.albedo.y >> r.albedo.z >> r.se.x >> r.se.y >> r.se.z;
    EXPECT_TRUE(s) << path << ": line " << line << ": expected 14 columns";
    r.nonlinear = nonlinear != 0;
    r.sample_visible = visible != 0;
    rows.push_back(r);
  }
  return rows;
}

BsdfParams params_of(const AlbedoRow& r) {
  BsdfParams p;
  if (r.type == "rough_conductor") {
    p.type = MaterialType::rough_conductor;
  } else if (r.type == "rough_glass") {
    p.type = MaterialType::rough_glass;
  } else if (r.type == "rough_plastic") {
    p.type = MaterialType::rough_plastic;
  } else if (r.type == "plastic") {
    p.type = MaterialType::plastic;
  } else {
    ADD_FAILURE() << "line " << r.line << ": unknown type " << r.type;
  }
  p.distribution =
      r.distribution == "ggx" ? MicrofacetDistribution::ggx : MicrofacetDistribution::beckmann;
  p.alpha_u = r.alpha_u;
  p.alpha_v = r.alpha_v;
  p.eta = r.eta;
  p.nonlinear = r.nonlinear;
  p.sample_visible = r.sample_visible;
  // The constants mitsuba_albedo.py uses (checked against the table's header below).
  p.conductor_eta = {0.2f, 0.9f, 1.1f};
  p.conductor_k = {3.9f, 2.4f, 2.2f};
  p.reflectance = {0.8f, 0.5f, 0.2f};
  return p;
}

TEST(BsdfAlbedo, MatchesMitsuba3WithinOnePercent) {
  std::string header;
  const std::vector<AlbedoRow> rows = read_table(&header);
  ASSERT_GE(rows.size(), 150u);
  ASSERT_NE(header.find("conductor eta [0.2, 0.9, 1.1] k [3.9, 2.4, 2.2]"), std::string::npos);
  ASSERT_NE(header.find("diffuse_reflectance [0.8, 0.5, 0.2]"), std::string::npos);
  BsdfCases tables(/*rough_plastic=*/false);
  double worst = 0;
  int worst_line = 0;
  for (const AlbedoRow& r : rows) {
    BsdfParams p = params_of(r);
    if (p.type == MaterialType::rough_plastic) p = tables.with_table(p);
    const Bsdf bsdf(p);
    // Radiance transport, as the table: the 1 / eta^2 of a refraction stays in.
    const AlbedoEstimate ours = grid_albedo(bsdf, albedo_wo(r.cos_theta_o), r.line, false);
    for (int c = 0; c < 3; ++c) {
      const double rel = std::abs(ours.mean[c] - r.albedo[c]) / std::max(r.albedo[c], 1e-2);
      if (rel > worst) {
        worst = rel;
        worst_line = r.line;
      }
      EXPECT_NEAR(ours.mean[c], r.albedo[c], 0.01 * r.albedo[c] + 1e-4)
          << "mitsuba_albedo.txt line " << r.line << " (" << r.type << " " << r.distribution
          << " alpha " << r.alpha_u << "/" << r.alpha_v << " cos " << r.cos_theta_o << ") channel "
          << c << ": ours +- " << ours.se[c] << ", Mitsuba's +- " << r.se[c];
    }
  }
  std::cout << "largest relative difference " << worst << " (line " << worst_line << ")\n";
}

}  // namespace
}  // namespace tessera::test
