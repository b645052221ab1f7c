// Mitsuba's surface BSDFs as materials: diffuse, conductors, dielectrics and named IORs,
// plastics, the principled family and the polarizer.
#include <gtest/gtest.h>

#include <cmath>

#include "scene/mitsuba/mitsuba_bsdf_test_support.h"
#include "scene/mitsuba/mitsuba_ior.h"
#include "scene/mitsuba/mitsuba_test_support.h"

namespace tessera {
namespace {

using testing::bsdf_error;
using testing::material_of;
using testing::mitsuba_scene;
using testing::parse_xml;

TEST(MitsubaBsdf, Diffuse) {
  Material m = material_of(R"(<bsdf type="diffuse"><rgb name="reflectance" value="0.1, 0.2, 0.3"/>
      </bsdf>)");
  EXPECT_EQ(m.type, MaterialType::diffuse);
  EXPECT_EQ(m.reflectance.value, glm::dvec3(0.1, 0.2, 0.3));
  EXPECT_FALSE(m.two_sided);  // one-sided, as in Mitsuba
  EXPECT_EQ(material_of(R"(<bsdf type="diffuse"><float name="reflectance" value="0.25"/></bsdf>)")
                .reflectance.value,
            glm::dvec3(0.25));
  EXPECT_EQ(material_of(R"(<bsdf type="diffuse"><rgb name="reflectance" value="0.75"/></bsdf>)")
                .reflectance.value,
            glm::dvec3(0.75));
  EXPECT_EQ(material_of(R"(<bsdf type="diffuse"/>)").reflectance.value, glm::dvec3(0.5));
}

TEST(MitsubaBsdf, DiffuseReflectanceMustConserveEnergy) {
  EXPECT_NE(bsdf_error(R"(<bsdf type="diffuse"><rgb name="reflectance" value="0.5, 1.2, 0"/>
      </bsdf>)")
                .find("<rgb name=\"reflectance\">: each channel must be in [0, 1] (got 1.2)"),
            std::string::npos);
}

TEST(MitsubaBsdf, TexturesAndSpectraAreRead) {
  Scene s = parse_xml(mitsuba_scene(R"(<shape type="rectangle"><bsdf type="diffuse">
      <texture type="bitmap" name="reflectance"><string name="filename" value="wood.png"/>
      </texture></bsdf></shape>)"),
                      {{"wood.png", "(texels)"}});
  const Material& m = s.materials.at(0);
  ASSERT_EQ(m.reflectance.texture, 0);
  EXPECT_EQ(m.reflectance.value, glm::dvec3(1));  // the texture's scale
  ASSERT_EQ(s.textures.size(), 1u);
  EXPECT_EQ(s.textures[0].file, "wood.png");
  EXPECT_EQ(s.textures[0].color_space, TextureColorSpace::srgb);
  EXPECT_EQ(s.referenced_files, std::vector<std::string>{"wood.png"});
  EXPECT_EQ(material_of(R"(<bsdf type="diffuse"><spectrum name="reflectance" value="0.5"/></bsdf>)")
                .reflectance.value,
            glm::dvec3(0.5));
}

TEST(MitsubaBsdf, ConductorWithoutMaterialIsTheMirror) {
  EXPECT_EQ(
      material_of(R"(<bsdf type="conductor"><string name="material" value="none"/></bsdf>)").type,
      MaterialType::mirror);
  EXPECT_EQ(material_of(R"(<bsdf type="conductor"/>)").type, MaterialType::mirror);  // the default
  EXPECT_EQ(material_of(R"(<bsdf type="conductor"><rgb name="specular_reflectance" value="1"/>
      </bsdf>)")
                .type,
            MaterialType::mirror);
  // A tinted perfect conductor is a conductor with Mitsuba's eta 0, k 1.
  Material tinted = material_of(R"(<bsdf type="conductor">
      <rgb name="specular_reflectance" value="0.9"/></bsdf>)");
  EXPECT_EQ(tinted.type, MaterialType::conductor);
  EXPECT_TRUE(tinted.perfect);
  EXPECT_EQ(tinted.specular_reflectance.value, glm::dvec3(0.9));
}

TEST(MitsubaBsdf, ConductorsTakeEtaAndKOrANamedMetal) {
  Material gold = material_of(R"(<bsdf type="conductor"><string name="material" value="Au"/>
      </bsdf>)");
  EXPECT_EQ(gold.type, MaterialType::conductor);
  EXPECT_FALSE(gold.perfect);
  // Mitsuba 3.9.1 scalar_rgb: traverse(load_dict({'type': 'conductor', 'material': 'Au'})).
  testing::expect_near(gold.eta, glm::dvec3(0.143035978, 0.375307083, 1.44204533), 1e-8);
  testing::expect_near(gold.k, glm::dvec3(3.98299694, 2.38555646, 1.60335922), 1e-8);
  Material given = material_of(R"(<bsdf type="conductor"><rgb name="eta" value="0.2, 0.3, 0.4"/>
      </bsdf>)");
  EXPECT_EQ(given.type, MaterialType::conductor);
  EXPECT_FALSE(given.perfect);
  EXPECT_EQ(given.eta, glm::dvec3(0.2, 0.3, 0.4));
  EXPECT_EQ(given.k, glm::dvec3(1));  // Mitsuba's default k
  EXPECT_NE(bsdf_error(R"(<bsdf type="conductor"><string name="material" value="Unobtainium"/>
      </bsdf>)")
                .find("unknown conductor \"Unobtainium\" (Mitsuba's names: a-C, Ag, Al"),
            std::string::npos);
  EXPECT_NE(bsdf_error(R"(<bsdf type="conductor"><string name="material" value="Au"/>
      <rgb name="eta" value="0.2"/></bsdf>)")
                .find("give either eta and k or material, not both"),
            std::string::npos);
  EXPECT_NE(bsdf_error(R"(<bsdf type="conductor"><texture type="checkerboard" name="eta"/>
      </bsdf>)")
                .find("eta takes no texture in <bsdf type=\"conductor\">"),
            std::string::npos);
}

TEST(MitsubaBsdf, RoughKindsReadTheirMicrofacets) {
  Material rc = material_of(R"(<bsdf type="roughconductor"><string name="material" value="Al"/>
      <string name="distribution" value="ggx"/><float name="alpha_u" value="0.05"/>
      <float name="alpha_v" value="0.3"/></bsdf>)");
  EXPECT_EQ(rc.type, MaterialType::rough_conductor);
  EXPECT_EQ(rc.distribution, MicrofacetDistribution::ggx);
  EXPECT_EQ(rc.alpha_u.value, 0.05);
  EXPECT_EQ(rc.alpha_v.value, 0.3);
  Material rd = material_of(R"(<bsdf type="roughdielectric"><float name="alpha" value="0.2"/>
      <boolean name="sample_visible" value="false"/></bsdf>)");
  EXPECT_EQ(rd.type, MaterialType::rough_glass);
  EXPECT_EQ(rd.distribution, MicrofacetDistribution::beckmann);  // Mitsuba's default
  EXPECT_EQ(rd.alpha_u.value, 0.2);
  EXPECT_EQ(rd.alpha_v.value, 0.2);
  EXPECT_FALSE(rd.sample_visible);
  EXPECT_EQ(rd.ior, 1.5046 / 1.000277);
  Material defaults = material_of(R"(<bsdf type="roughconductor"/>)");
  EXPECT_EQ(defaults.alpha_u.value, 0.1);
  EXPECT_TRUE(defaults.perfect);
  EXPECT_NE(bsdf_error(R"(<bsdf type="roughconductor"><float name="alpha" value="0"/></bsdf>)")
                .find("<float name=\"alpha\">: must be > 0 (got 0; for a smooth surface use the "
                      "BSDF without \"rough\")"),
            std::string::npos);
  EXPECT_NE(bsdf_error(R"(<bsdf type="roughconductor"><float name="alpha_u" value="0.1"/></bsdf>)")
                .find("give both alpha_u and alpha_v"),
            std::string::npos);
  EXPECT_NE(bsdf_error(R"(<bsdf type="roughdielectric"><string name="distribution" value="phong"/>
      </bsdf>)")
                .find("\"phong\" is no distribution (beckmann or ggx)"),
            std::string::npos);
  // roughplastic is isotropic in Mitsuba: alpha_u is not one of its parameters.
  EXPECT_NE(bsdf_error(R"(<bsdf type="roughplastic"><float name="alpha_u" value="0.1"/></bsdf>)")
                .find("is not supported in <bsdf type=\"roughplastic\">"),
            std::string::npos);
}

TEST(MitsubaBsdf, PlasticsAndThinDielectric) {
  Material p = material_of(R"(<bsdf type="plastic"><rgb name="diffuse_reflectance" value="0.1, 0.2, 0.3"/>
      <boolean name="nonlinear" value="true"/></bsdf>)");
  EXPECT_EQ(p.type, MaterialType::plastic);
  EXPECT_EQ(p.reflectance.value, glm::dvec3(0.1, 0.2, 0.3));
  EXPECT_TRUE(p.nonlinear);
  EXPECT_EQ(p.ior, 1.49 / 1.000277);  // polypropylene / air
  Material rp = material_of(R"(<bsdf type="roughplastic"><float name="alpha" value="0.3"/>
      <string name="distribution" value="ggx"/></bsdf>)");
  EXPECT_EQ(rp.type, MaterialType::rough_plastic);
  EXPECT_EQ(rp.alpha_u.value, 0.3);
  EXPECT_EQ(rp.distribution, MicrofacetDistribution::ggx);
  Material thin = material_of(R"(<bsdf type="thindielectric">
      <rgb name="specular_transmittance" value="0.5"/></bsdf>)");
  EXPECT_EQ(thin.type, MaterialType::thin_glass);
  EXPECT_EQ(thin.specular_transmittance.value, glm::dvec3(0.5));
}

TEST(MitsubaBsdf, DielectricIorIsInteriorOverExterior) {
  Material m = material_of(R"(<bsdf type="dielectric"><float name="int_ior" value="1.5"/>
      <float name="ext_ior" value="1.25"/></bsdf>)");
  EXPECT_EQ(m.type, MaterialType::glass);
  EXPECT_EQ(m.ior, 1.5 / 1.25);
  EXPECT_EQ(material_of(R"(<bsdf type="dielectric"/>)").ior, 1.5046 / 1.000277);  // bk7 / air
  EXPECT_EQ(material_of(R"(<bsdf type="dielectric"><string name="int_ior" value="water"/>
      <string name="ext_ior" value="vacuum"/></bsdf>)")
                .ior,
            1.333);
  EXPECT_EQ(material_of(R"(<bsdf type="dielectric"><string name="int_ior" value="Diamond"/>
      <string name="ext_ior" value="water"/></bsdf>)")
                .ior,
            2.419 / 1.333);
}

TEST(MitsubaBsdf, BadIorsAreRefused) {
  EXPECT_NE(bsdf_error(R"(<bsdf type="dielectric"><string name="int_ior" value="unobtainium"/>
      </bsdf>)")
                .find("unknown IOR name \"unobtainium\" (Mitsuba's names: vacuum, helium"),
            std::string::npos);
  EXPECT_NE(bsdf_error(R"(<bsdf type="dielectric"><float name="int_ior" value="0"/></bsdf>)")
                .find("<float name=\"int_ior\">: must be > 0 (got 0)"),
            std::string::npos);
  EXPECT_EQ(material_of(R"(<bsdf type="dielectric"><rgb name="specular_transmittance"
      value="0.5"/></bsdf>)")
                .specular_transmittance.value,
            glm::dvec3(0.5));
}

TEST(MitsubaIor, MitsubasTable) {
  EXPECT_EQ(mitsuba_named_ior("vacuum"), 1.0);
  EXPECT_EQ(mitsuba_named_ior("air"), 1.000277);
  EXPECT_EQ(mitsuba_named_ior("water"), 1.333);
  EXPECT_EQ(mitsuba_named_ior("bk7"), 1.5046);
  EXPECT_EQ(mitsuba_named_ior("BK7"), 1.5046);
  EXPECT_EQ(mitsuba_named_ior("acrylic glass"), 1.49);
  EXPECT_EQ(mitsuba_named_ior("fused quartz"), 1.458);
  EXPECT_EQ(mitsuba_named_ior("diamond"), 2.419);
  EXPECT_EQ(mitsuba_named_ior("water ice"), 1.31);
  EXPECT_EQ(mitsuba_named_ior("glass"), std::nullopt);  // not in Mitsuba's table either
  EXPECT_EQ(mitsuba_named_ior(""), std::nullopt);
  EXPECT_NE(mitsuba_ior_names().find("bk7, sodium chloride"), std::string::npos);
}

TEST(MitsubaBsdf, PrincipledDefaultsAreMitsubas) {
  Material m = material_of(R"(<bsdf type="principled"/>)");
  EXPECT_EQ(m.type, MaterialType::principled);
  EXPECT_EQ(m.reflectance.value, glm::dvec3(0.5));
  EXPECT_EQ(m.principled.roughness.value, 0.5);
  EXPECT_EQ(m.principled.metallic.value, 0.0);
  EXPECT_EQ(m.principled.clearcoat_gloss.value, 0.0);
  EXPECT_FALSE(m.principled.transmits());
  EXPECT_FALSE(m.two_sided);
  // specular 0.5 is eta = 2 / (1 - sqrt(0.04)) - 1 = 1.5.
  EXPECT_NEAR(m.ior, 1.5, 1e-6);
  EXPECT_EQ(m.principled.main_specular_sampling_rate, 1.0);
}

TEST(MitsubaBsdf, PrincipledReadsEveryParameterAndTextures) {
  Material m = material_of(R"(<bsdf type="principled">
      <rgb name="base_color" value="0.2, 0.8, 0.1"/>
      <float name="roughness" value="0.15"/>
      <texture name="anisotropic" type="checkerboard"><float name="color0" value="0.05"/>
        <float name="color1" value="0.8"/></texture>
      <float name="metallic" value="0.3"/> <float name="spec_trans" value="0.4"/>
      <float name="spec_tint" value="0.5"/> <float name="sheen" value="0.6"/>
      <float name="sheen_tint" value="0.7"/> <float name="flatness" value="0.8"/>
      <float name="clearcoat" value="0.9"/> <float name="clearcoat_gloss" value="0.25"/>
      <float name="eta" value="1.33"/>
      <float name="main_specular_sampling_rate" value="2"/>
      <float name="clearcoat_sampling_rate" value="0.5"/>
      <float name="diffuse_reflectance_sampling_rate" value="3"/></bsdf>)");
  const PrincipledParameters& p = m.principled;
  EXPECT_EQ(m.reflectance.value, glm::dvec3(0.2, 0.8, 0.1));
  EXPECT_EQ(p.roughness.value, 0.15);
  EXPECT_GE(p.anisotropic.texture, 0);
  EXPECT_EQ(p.metallic.value, 0.3);
  EXPECT_EQ(p.spec_trans.value, 0.4);
  EXPECT_EQ(p.spec_tint.value, 0.5);
  EXPECT_EQ(p.sheen.value, 0.6);
  EXPECT_EQ(p.sheen_tint.value, 0.7);
  EXPECT_EQ(p.flatness.value, 0.8);
  EXPECT_EQ(p.clearcoat.value, 0.9);
  EXPECT_EQ(p.clearcoat_gloss.value, 0.25);
  EXPECT_EQ(m.ior, 1.33);
  EXPECT_EQ(p.main_specular_sampling_rate, 2.0);
  EXPECT_EQ(p.clearcoat_sampling_rate, 0.5);
  EXPECT_EQ(p.diffuse_reflectance_sampling_rate, 3.0);
  EXPECT_TRUE(p.transmits());
  EXPECT_TRUE(p.textured());
}

TEST(MitsubaBsdf, PrincipledEtaAsMitsubaAdjustsIt) {
  // eta = 1 (or specular = 0) cannot transmit: Mitsuba moves it when spec_trans is given.
  EXPECT_EQ(material_of(R"(<bsdf type="principled"><float name="spec_trans" value="0.5"/>
      <float name="eta" value="1"/></bsdf>)").ior, 1.001);
  EXPECT_EQ(material_of(R"(<bsdf type="principled"><float name="eta" value="1"/></bsdf>)").ior, 1.0);
  EXPECT_EQ(material_of(R"(<bsdf type="principled"><float name="spec_trans" value="0"/>
      <float name="specular" value="0"/></bsdf>)").ior, 1.0);
  const double eta = material_of(R"(<bsdf type="principled"><float name="spec_trans" value="1"/>
      <float name="specular" value="0"/></bsdf>)").ior;
  EXPECT_NEAR(eta, 2 / (1 - std::sqrt(0.08 * 1e-3)) - 1, 1e-6);
  EXPECT_NEAR(material_of(R"(<bsdf type="principled"><float name="specular" value="0.7"/></bsdf>)").ior,
              2 / (1 - std::sqrt(0.08 * 0.7)) - 1, 1e-6);
}

TEST(MitsubaBsdf, PrincipledRefusalsNameTheParameter) {
  EXPECT_NE(bsdf_error(R"(<bsdf type="principled"><float name="eta" value="1.5"/>
      <float name="specular" value="0.5"/></bsdf>)").find("give eta or specular, not both"),
            std::string::npos);
  EXPECT_NE(bsdf_error(R"(<bsdf type="principled"><float name="metallic" value="1.5"/></bsdf>)")
                .find("<float name=\"metallic\">: must be in [0, 1] (got 1.5)"),
            std::string::npos);
  EXPECT_NE(bsdf_error(R"(<bsdf type="principled"><float name="eta" value="-2"/></bsdf>)")
                .find("must be > 0"),
            std::string::npos);
  EXPECT_NE(bsdf_error(R"(<bsdf type="principled"><float name="clearcoat_sampling_rate"
      value="-1"/></bsdf>)").find("must be >= 0"),
            std::string::npos);
  EXPECT_NE(bsdf_error(R"(<bsdf type="principled"><float name="subsurface" value="0.5"/></bsdf>)")
                .find("subsurface"),
            std::string::npos);
  // With transmission it is two-sided by nature; Mitsuba's twosided refuses it too.
  EXPECT_NE(bsdf_error(R"(<bsdf type="twosided"><bsdf type="principled">
      <float name="spec_trans" value="0.5"/></bsdf></bsdf>)")
                .find("twosided takes only BSDFs that do not transmit light"),
            std::string::npos);
  EXPECT_TRUE(material_of(R"(<bsdf type="twosided"><bsdf type="principled"/></bsdf>)").two_sided);
}

TEST(MitsubaBsdf, PrincipledThinReadsEveryParameterAndTextures) {
  Material d = material_of(R"(<bsdf type="principledthin"/>)");
  EXPECT_EQ(d.type, MaterialType::principled_thin);
  EXPECT_EQ(d.reflectance.value, glm::dvec3(0.5));
  EXPECT_EQ(d.principled.roughness.value, 0.5);
  EXPECT_EQ(d.principled.diff_trans.value, 0.0);
  EXPECT_EQ(d.ior, 1.5);
  EXPECT_EQ(d.ior_texture, -1);
  EXPECT_TRUE(d.transmits());  // two-sided by nature

  Material m = material_of(R"(<bsdf type="principledthin">
      <rgb name="base_color" value="0.7, 0.1, 0.1"/>
      <float name="roughness" value="0.15"/>
      <texture name="anisotropic" type="checkerboard"><float name="color0" value="0.05"/>
        <float name="color1" value="0.8"/></texture>
      <float name="spec_trans" value="0.8"/> <float name="spec_tint" value="0.1"/>
      <float name="sheen" value="0.6"/> <float name="sheen_tint" value="0.7"/>
      <float name="flatness" value="0.4"/>
      <texture name="diff_trans" type="checkerboard"><float name="color0" value="0.4"/>
        <float name="color1" value="1.4"/></texture>
      <texture name="eta" type="checkerboard"><float name="color0" value="1.2"/>
        <float name="color1" value="1.5"/></texture>
      <float name="diffuse_reflectance_sampling_rate" value="0.5"/>
      <float name="specular_reflectance_sampling_rate" value="2"/>
      <float name="specular_transmittance_sampling_rate" value="3"/>
      <float name="diffuse_transmittance_sampling_rate" value="4"/></bsdf>)");
  const PrincipledParameters& p = m.principled;
  EXPECT_EQ(m.reflectance.value, glm::dvec3(0.7, 0.1, 0.1));
  EXPECT_EQ(p.roughness.value, 0.15);
  EXPECT_GE(p.anisotropic.texture, 0);
  EXPECT_EQ(p.spec_trans.value, 0.8);
  EXPECT_EQ(p.spec_tint.value, 0.1);
  EXPECT_EQ(p.sheen.value, 0.6);
  EXPECT_EQ(p.sheen_tint.value, 0.7);
  EXPECT_EQ(p.flatness.value, 0.4);
  EXPECT_GE(p.diff_trans.texture, 0);
  EXPECT_GE(m.ior_texture, 0);
  EXPECT_EQ(m.ior, 1.0);  // the texture's scale
  EXPECT_EQ(p.diffuse_reflectance_sampling_rate, 0.5);
  EXPECT_EQ(p.specular_reflectance_sampling_rate, 2.0);
  EXPECT_EQ(p.specular_transmittance_sampling_rate, 3.0);
  EXPECT_EQ(p.diffuse_transmittance_sampling_rate, 4.0);

  EXPECT_NE(bsdf_error(R"(<bsdf type="principledthin"><float name="diff_trans" value="2.5"/>
      </bsdf>)").find("<float name=\"diff_trans\">: must be in [0, 2] (got 2.5)"),
            std::string::npos);
  EXPECT_NE(bsdf_error(R"(<bsdf type="principledthin"><float name="eta" value="0"/></bsdf>)")
                .find("must be > 0"),
            std::string::npos);
  EXPECT_NE(bsdf_error(R"(<bsdf type="principledthin"><float name="metallic" value="0.5"/>
      </bsdf>)").find("metallic"),
            std::string::npos);  // principled's, not the thin one's
  EXPECT_NE(bsdf_error(R"(<bsdf type="twosided"><bsdf type="principledthin"/></bsdf>)")
                .find("twosided takes only BSDFs that do not transmit light"),
            std::string::npos);
}

TEST(MitsubaBsdf, PplasticReadsItsParameters) {
  Material d = material_of(R"(<bsdf type="pplastic"/>)");
  EXPECT_EQ(d.type, MaterialType::pplastic);
  EXPECT_EQ(d.reflectance.value, glm::dvec3(0.5));
  EXPECT_EQ(d.specular_reflectance.value, glm::dvec3(1.0));
  EXPECT_NEAR(d.ior, 1.49 / 1.000277, 1e-12);  // polypropylene over air
  EXPECT_EQ(d.distribution, MicrofacetDistribution::beckmann);
  EXPECT_EQ(d.alpha_u.value, 0.1);
  EXPECT_FALSE(d.transmits());

  Material m = material_of(R"(<bsdf type="pplastic">
      <rgb name="diffuse_reflectance" value="0.05, 0.03, 0.1"/>
      <rgb name="specular_reflectance" value="0.5"/>
      <float name="eta" value="1.33"/> <string name="distribution" value="ggx"/>
      <float name="alpha_u" value="0.06"/> <float name="alpha_v" value="0.2"/>
      <boolean name="sample_visible" value="false"/></bsdf>)");
  EXPECT_EQ(m.reflectance.value, glm::dvec3(0.05, 0.03, 0.1));
  EXPECT_EQ(m.specular_reflectance.value, glm::dvec3(0.5));
  EXPECT_EQ(m.ior, 1.33);
  EXPECT_EQ(m.distribution, MicrofacetDistribution::ggx);
  EXPECT_EQ(m.alpha_u.value, 0.06);
  EXPECT_EQ(m.alpha_v.value, 0.2);
  EXPECT_FALSE(m.sample_visible);
  EXPECT_NEAR(material_of(R"(<bsdf type="pplastic"><float name="int_ior" value="1.6"/>
      <float name="ext_ior" value="1.2"/></bsdf>)").ior, 1.6 / 1.2, 1e-12);

  EXPECT_NE(bsdf_error(R"(<bsdf type="pplastic"><float name="eta" value="1.5"/>
      <float name="int_ior" value="1.5"/></bsdf>)").find("give eta or int_ior and ext_ior"),
            std::string::npos);
  EXPECT_NE(bsdf_error(R"(<bsdf type="pplastic"><float name="int_ior" value="1.2"/>
      <float name="ext_ior" value="1.2"/></bsdf>)").find("must differ"),
            std::string::npos);
  EXPECT_NE(bsdf_error(R"(<bsdf type="pplastic"><boolean name="nonlinear" value="true"/>
      </bsdf>)").find("nonlinear"),
            std::string::npos);
}

TEST(MitsubaBsdf, PolarizerReadsTransmittanceAndAcceptsThetaAndPolarizing) {
  Material d = material_of(R"(<bsdf type="polarizer"/>)");
  EXPECT_EQ(d.type, MaterialType::polarizer);
  EXPECT_EQ(d.specular_transmittance.value, glm::dvec3(1.0));
  EXPECT_TRUE(d.transmits());  // two-sided by nature, as in Mitsuba (FrontSide | BackSide)

  // theta acts on polarization only: any angle, a spectrum or a texture, changes no RGB value.
  Material m = material_of(R"(<bsdf type="polarizer">
      <spectrum name="theta" value="-45"/> <boolean name="polarizing" value="false"/>
      <rgb name="transmittance" value="0.8, 0.5, 0.2"/></bsdf>)");
  EXPECT_EQ(m.specular_transmittance.value, glm::dvec3(0.8, 0.5, 0.2));
  Material t = material_of(R"(<bsdf type="polarizer">
      <texture name="theta" type="checkerboard"/>
      <texture name="transmittance" type="checkerboard"/></bsdf>)");
  EXPECT_GE(t.specular_transmittance.texture, 0);

  EXPECT_NE(bsdf_error(R"(<bsdf type="polarizer"><string name="polarizing" value="yes"/>
      </bsdf>)").find("polarizing"),
            std::string::npos);
  EXPECT_NE(bsdf_error(R"(<bsdf type="polarizer"><rgb name="transmittance" value="1.5"/>
      </bsdf>)").find("transmittance"),
            std::string::npos);
  EXPECT_NE(bsdf_error(R"(<bsdf type="polarizer"><float name="eta" value="1.5"/></bsdf>)")
                .find("eta"),
            std::string::npos);
  // Mitsuba's twosided takes no BSDF that transmits light.
  EXPECT_NE(bsdf_error(R"(<bsdf type="twosided"><bsdf type="polarizer"/></bsdf>)")
                .find("twosided takes only BSDFs that do not transmit"),
            std::string::npos);
}

}  // namespace
}  // namespace tessera
