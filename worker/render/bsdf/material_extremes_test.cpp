// Every BSDF at its extremes, rendered the way `tessera-worker render` renders a scene file
// (worker/extremes_test_support.h). Small images (16 x 16, 16 spp) so that the whole file takes
// seconds.
//
// What each test asks (docs/accuracy.md, "The extremes, each a test"): no NaN or Inf anywhere
// (none dropped, every pixel finite), every pixel positive where light must arrive.
#include "extremes_test_support.h"
#include "render/texture/texture_test_images.h"

namespace tessera {
namespace {

using namespace extremes_test;

// --- Materials ---------------------------------------------------------------------------------

/// The textures every material case may use, written beside the scene: a checkerboard; an
/// 8 x 8 normal map holding the extreme tangent-space directions (along the surface, straight
/// into it, the zero vector of mid-grey, along -u and -v) among ordinary ones; and an 8 x 8
/// height field with one-texel cliffs (a bump map with scale 100 tilts normals almost flat).
const char* kTextures = R"(
  "checker": {"type": "checkerboard", "color0": [0.9, 0.9, 0.9], "color1": [0.05, 0.05, 0.05],
              "to_uv": [[4, 0, 0], [0, 4, 0]]},
  "normals": {"type": "bitmap", "file": "normals.exr", "filter": "nearest"},
  "heights": {"type": "bitmap", "file": "heights.exr"},
  "opacity": {"type": "checkerboard", "color0": [1, 1, 1], "color1": [0, 0, 0],
              "to_uv": [[3, 0, 0], [0, 3, 0]]})";

void write_material_textures(const fs::path& dir) {
  // Texel = (m + 1) / 2 for a tangent-space direction m (need not be unit).
  const std::vector<glm::vec3> directions = {
      {0, 0, 1}, {1, 0, 0}, {0, 0, -1}, {0, 0, 0},   {-1, 0, 0}, {0, -1, 0.001f},
      {0, 1, 0}, {1, 1, 1}, {0.3f, -0.2f, 0.9f}, {-0.99f, 0.1f, 0.01f}};
  std::vector<float> normals;
  for (int i = 0; i < 64; ++i) {
    const glm::vec3 m = directions[size_t(i * 7 + i / 8) % directions.size()];
    for (int c = 0; c < 3; ++c) normals.push_back(0.5f * (m[c] + 1.0f));
  }
  test::write_exr(dir / "normals.exr", 8, 8, normals);
  std::vector<float> heights;
  for (int i = 0; i < 64; ++i) {
    const float h = ((i * 37) % 11 == 0) ? 1.0f : ((i % 3 == 0) ? 0.5f : 0.0f);
    heights.insert(heights.end(), {h, h, h});
  }
  test::write_exr(dir / "heights.exr", 8, 8, heights);
}

struct MaterialCase {
  const char* name;
  const char* material;  ///< the JSON object of material "test"
  const char* extra = "";  ///< more materials, each `"name": {...},` (a `back` names one)
  /// A perturbed normal can turn a specular reflection or refraction below the surface, which
  /// counts as black (Mitsuba's normalmap and bumpmap adapters do the same): a pixel on such
  /// texels may be black, so only the image mean must be > 0.
  bool black_allowed = false;
  /// Samples per pixel of the stage render. 16 leaves a pixel black by chance where few
  /// directions get light back (a normal-mapped anisotropic conductor: at 16 spp 10 or 11 of
  /// seeds 1-16 gave a black pixel, by the sampler, at 64 spp none), so such a case takes more, asserting the same.
  int stage_spp = 16;
};

/// The stage: the test material on a sphere and on a tilted quad with uvs (for textures, normal
/// and bump maps), over a grey floor, lit by a quad light and a dim uniform environment (so that
/// every pixel receives light, whatever the material does with it). `floor` is the floor's
/// material ("test" for the grazing views).
std::string material_scene(const MaterialCase& c, const std::string& camera, const char* floor) {
  return std::string(R"({"tessera": 1,
  "camera": )") + camera + R"(,
  "textures": {)" + kTextures + R"(},
  "materials": {)" + c.extra + R"(
    "grey": {"type": "diffuse", "reflectance": [0.5, 0.5, 0.5]},
    "test": )" + c.material + R"(},
  "shapes": [
    {"type": "quad", "material": ")" + floor + R"(",
     "vertices": [[-20, 0, 20], [20, 0, 20], [20, 0, -20], [-20, 0, -20]]},
    {"type": "sphere", "center": [-0.55, 0.5, 0], "radius": 0.5, "material": "test"},
    {"type": "triangles", "material": "test",
     "vertices": [[0.1, 0.05, 0.3], [1.1, 0.05, 0.1], [1.1, 1.05, -0.2], [0.1, 1.05, 0]],
     "indices": [[0, 1, 2], [0, 2, 3]], "uvs": [[0, 1], [1, 1], [1, 0], [0, 0]]},
    {"type": "quad", "emission": [6, 6, 6],
     "vertices": [[-0.5, 3, -0.5], [0.5, 3, -0.5], [0.5, 3, 0.5], [-0.5, 3, 0.5]]}
  ],
  "lights": [{"type": "constant", "radiance": [0.3, 0.3, 0.3]}]
})";
}

const MaterialCase kMaterials[] = {
    {"diffuse_white", R"({"type": "diffuse", "reflectance": [1, 1, 1]})"},
    {"diffuse_textured", R"({"type": "diffuse", "reflectance": {"texture": "checker"}})"},
    {"conductor_k0", R"({"type": "conductor", "eta": [1.5, 1.5, 1.5], "k": [0, 0, 0]})"},
    {"conductor_eta0_k0", R"({"type": "conductor", "eta": [0, 0, 0], "k": [0, 0, 0]})"},
    {"conductor_perfect", R"({"type": "conductor", "perfect": true})"},
    {"conductor_textured", R"({"type": "conductor", "eta": [0.2, 0.9, 1.1], "k": [3.9, 2.4, 2.1],
                                "specular_reflectance": {"texture": "checker"}})"},
    {"roughconductor_ggx_alpha_1e-4",
     R"({"type": "rough_conductor", "distribution": "ggx", "alpha": 1e-4, "eta": [0.2, 0.9, 1.1], "k": [3.9, 2.4, 2.1]})"},
    {"roughconductor_ggx_alpha_1",
     R"({"type": "rough_conductor", "distribution": "ggx", "alpha": 1, "eta": [0.2, 0.9, 1.1], "k": [3.9, 2.4, 2.1]})"},
    {"roughconductor_beckmann_alpha_1e-4",
     R"({"type": "rough_conductor", "distribution": "beckmann", "alpha": 1e-4, "perfect": true})"},
    {"roughconductor_beckmann_alpha_1",
     R"({"type": "rough_conductor", "distribution": "beckmann", "alpha": 1, "perfect": true})"},
    {"roughconductor_k0_alpha_1",
     R"({"type": "rough_conductor", "distribution": "ggx", "alpha": 1, "eta": [1.5, 1.5, 1.5], "k": [0, 0, 0]})"},
    {"roughconductor_anisotropic",
     R"({"type": "rough_conductor", "distribution": "ggx", "alpha_u": 1e-4, "alpha_v": 1, "perfect": true})"},
    {"roughconductor_anisotropic_beckmann_unsampled",
     R"({"type": "rough_conductor", "distribution": "beckmann", "alpha_u": 1, "alpha_v": 1e-4,
         "sample_visible": false, "perfect": true})"},
    {"roughconductor_textured_alpha",
     R"({"type": "rough_conductor", "distribution": "ggx", "alpha": {"texture": "checker"}, "perfect": true})"},
    {"dielectric_eta_1.0001", R"({"type": "glass", "ior": 1.0001})"},
    {"dielectric_eta_10", R"({"type": "glass", "ior": 10})"},
    {"dielectric_eta_0.5", R"({"type": "glass", "ior": 0.5})"},
    {"dielectric_tinted", R"({"type": "glass", "ior": 1.5, "specular_reflectance": [0.5, 0.5, 0.5],
                              "specular_transmittance": {"texture": "checker"}})"},
    {"roughdielectric_eta_1.0001_alpha_1e-4",
     R"({"type": "rough_glass", "distribution": "ggx", "ior": 1.0001, "alpha": 1e-4})"},
    {"roughdielectric_eta_1.0001_alpha_1",
     R"({"type": "rough_glass", "distribution": "ggx", "ior": 1.0001, "alpha": 1})"},
    {"roughdielectric_eta_10_alpha_1e-4",
     R"({"type": "rough_glass", "distribution": "beckmann", "ior": 10, "alpha": 1e-4})"},
    {"roughdielectric_eta_10_alpha_1",
     R"({"type": "rough_glass", "distribution": "beckmann", "ior": 10, "alpha": 1})"},
    {"roughdielectric_anisotropic",
     R"({"type": "rough_glass", "distribution": "ggx", "ior": 1.5, "alpha_u": 1e-4, "alpha_v": 1})"},
    {"thindielectric", R"({"type": "thin_glass", "ior": 1.5})"},
    {"thindielectric_eta_1.0001", R"({"type": "thin_glass", "ior": 1.0001})"},
    {"thindielectric_eta_10", R"({"type": "thin_glass", "ior": 10})"},
    {"plastic", R"({"type": "plastic", "diffuse_reflectance": [0.8, 0.2, 0.1]})"},
    {"plastic_nonlinear_eta_10",
     R"({"type": "plastic", "ior": 10, "nonlinear": true, "diffuse_reflectance": [1, 1, 1]})"},
    {"plastic_eta_1.0001", R"({"type": "plastic", "ior": 1.0001, "diffuse_reflectance": [0.5, 0.5, 0.5]})"},
    {"roughplastic_alpha_1e-4",
     R"({"type": "rough_plastic", "distribution": "ggx", "alpha": 1e-4, "diffuse_reflectance": [0.8, 0.2, 0.1]})"},
    {"roughplastic_alpha_1",
     R"({"type": "rough_plastic", "distribution": "beckmann", "alpha": 1, "nonlinear": true,
         "diffuse_reflectance": {"texture": "checker"}})"},
    {"roughplastic_eta_1.0001_alpha_1",
     R"({"type": "rough_plastic", "distribution": "ggx", "ior": 1.0001, "alpha": 1, "diffuse_reflectance": [1, 1, 1]})"},
    {"twosided_diffuse", R"({"type": "diffuse", "reflectance": [0.7, 0.7, 0.7], "two_sided": true})"},
    {"twosided_conductor_with_diffuse_back",
     R"({"type": "rough_conductor", "alpha": 0.2, "perfect": true, "two_sided": true, "back": "back"})",
     R"("back": {"type": "diffuse", "reflectance": [0.2, 0.6, 0.2], "two_sided": true},)"},
    {"mask_0", R"({"type": "diffuse", "reflectance": [0.7, 0.7, 0.7], "opacity": 0})"},
    {"mask_0.5", R"({"type": "rough_conductor", "alpha": 0.3, "perfect": true, "opacity": 0.5})"},
    {"mask_1", R"({"type": "plastic", "opacity": 1})"},
    {"mask_textured", R"({"type": "diffuse", "reflectance": [0.7, 0.7, 0.7], "two_sided": true,
                          "opacity": {"texture": "opacity"}})"},
    {"normalmap_diffuse", R"({"type": "diffuse", "reflectance": [0.7, 0.7, 0.7], "normal_map": "normals"})"},
    {"normalmap_conductor", R"({"type": "conductor", "perfect": true, "normal_map": "normals"})",
     "", true},
    {"normalmap_dielectric", R"({"type": "glass", "ior": 1.5, "normal_map": "normals"})", "", true},
    {"normalmap_anisotropic_roughconductor",
     R"({"type": "rough_conductor", "alpha_u": 0.05, "alpha_v": 0.8, "perfect": true, "normal_map": "normals"})",
     "", false, 64},
    {"bumpmap_diffuse",
     R"({"type": "diffuse", "reflectance": [0.7, 0.7, 0.7], "bump_map": "heights", "bump_scale": 100})"},
    {"bumpmap_roughdielectric",
     R"({"type": "rough_glass", "ior": 1.33, "alpha": 0.05, "bump_map": "heights", "bump_scale": 100})",
     "", true},
    {"bumpmap_roughplastic",
     R"({"type": "rough_plastic", "alpha": 1e-4, "bump_map": "heights", "bump_scale": 0.01})"},
};

class MaterialExtremes : public ::testing::TestWithParam<MaterialCase> {};

TEST_P(MaterialExtremes, RenderFiniteAndLit) {
  const MaterialCase& c = GetParam();
  const SceneFolder dir(std::string("material_") + c.name);
  write_material_textures(dir.path());
  // Seen from above: every pixel sees the floor, the objects or the environment, each lit.
  write_file(dir / "stage.json", material_scene(c, kStageCamera, "grey"));
  const Rendered stage = render_file(dir / "stage.json", 16, 16, c.stage_spp);
  expect_finite(stage, std::string(c.name) + " (stage)", !c.black_allowed);
  EXPECT_GT(stage.mean_luminance(), 0.0) << c.name;
  // The floor made of the material, seen at grazing angles. Light arrives at every point of it,
  // but a specular floor may reflect only the (black) ground-level horizon: no positivity.
  write_file(dir / "grazing.json", material_scene(c, kGrazingCamera, "test"));
  expect_finite(render_file(dir / "grazing.json", 16, 16, 16), std::string(c.name) + " (grazing)",
                false);
}

INSTANTIATE_TEST_SUITE_P(Extremes, MaterialExtremes, ::testing::ValuesIn(kMaterials),
                         [](const auto& info) {
                           std::string name = info.param.name;
                           for (char& ch : name) {
                             if (ch == '.' || ch == '-') ch = '_';
                           }
                           return name;
                         });

TEST(MaterialExtremes, EveryNamedMetalRendersFinite) {
  // Mitsuba's named conductors (some are dielectrics with k = 0 at some wavelengths, MgO, ThF4),
  // smooth and at alpha 1e-4 and 1, through the importer: one small sphere each.
  const char* metals[] = {"a-C",  "Ag",   "Al",   "AlAs", "AlAs_palik", "AlSb", "Au",   "Be",
                          "Cr",   "CsI",  "Cu",   "Cu2O", "CuO",        "d-C",  "Hg",   "HgTe",
                          "Ir",   "K",    "Li",   "MgO",  "Mo",         "Na_palik", "Nb", "Ni_palik",
                          "Rh",   "Se",   "Se-e", "SiC",  "SnTe",       "Ta",   "Te",   "Te-e",
                          "ThF4", "TiC",  "TiN",  "TiO2", "TiO2-e",     "VC",   "VN",   "W",
                          "none"};
  const SceneFolder dir("named_metals");
  std::string xml = R"(<scene version="3.0.0">
  <sensor type="perspective">
    <float name="fov" value="50"/>
    <transform name="to_world"><lookat origin="0, 0, 9" target="0, 0, 0" up="0, 1, 0"/></transform>
    <film type="hdrfilm"><integer name="width" value="16"/><integer name="height" value="16"/></film>
  </sensor>
  <emitter type="constant"><rgb name="radiance" value="0.5"/></emitter>
  <shape type="rectangle">
    <transform name="to_world"><scale value="0.5"/><rotate x="1" angle="90"/><translate y="6"/></transform>
    <emitter type="area"><rgb name="radiance" value="20"/></emitter>
  </shape>
)";
  int i = 0;
  for (const char* metal : metals) {
    const char* kinds[] = {R"(<bsdf type="conductor">)",
                           R"(<bsdf type="roughconductor"><float name="alpha" value="0.0001"/>)",
                           R"(<bsdf type="roughconductor"><float name="alpha" value="1"/><string name="distribution" value="ggx"/>)"};
    const int kind = i % 3;
    const double x = -3.6 + 0.8 * (i % 10), y = -3.2 + 0.8 * (i / 10);
    xml += "  <shape type=\"sphere\"><point name=\"center\" value=\"" + std::to_string(x) + ", " +
           std::to_string(y) + ", 0\"/><float name=\"radius\" value=\"0.38\"/>" + kinds[kind] +
           "<string name=\"material\" value=\"" + metal + "\"/></bsdf></shape>\n";
    ++i;
  }
  xml += "</scene>\n";
  write_file(dir / "metals.xml", xml);
  expect_finite(render_file(dir / "metals.xml", 32, 32, 16), "named metals", true);
}

}  // namespace
}  // namespace tessera
