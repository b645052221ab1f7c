// The editable scene description: what a scene file says, resolved to world space.
//
// This is the description, not the render-ready scene: the worker turns it
// into an immutable Embree scene (worker/render/scene/traceable_scene.h). Everything here is plain data
// so that the server and the client can parse and validate scenes without linking the renderer.
//
// core/scene/ in layers, each including only those below it: this folder, the model (this
// Scene, SceneError, transforms, bundle paths and file readers, image and grid checks); mesh/,
// the mesh files; native/, scene format v1 (and its writer); mitsuba/, the Mitsuba 3 importer,
// which builds on native/'s parsers; loader/, scene files on disk of either format, on top.
#pragma once

#include <cmath>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <glm/mat3x3.hpp>
#include <glm/mat4x4.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "scene/mesh_attribute.h"

namespace tessera {

struct VolumeGridFile;  // scene/volume_grid_file.h

/// Which image axis the camera's field of view spans (diagonal: the image's diagonal, Mitsuba's
/// fov_axis "diagonal" and its focal_length).
enum class FovAxis { x, y, smaller, larger, diagonal };

/// tan of the half angles the view spans along image x and y, at distance 1 from a pinhole:
/// fov_deg along fov_axis for an image of width / height `aspect` (the other axis by the aspect;
/// for the diagonal, x is the diagonal's tangent over sqrt(1 + 1 / aspect^2), as Mitsuba's
/// parse_fov turns a diagonal angle into the horizontal one).
inline glm::dvec2 fov_half_tangents(double fov_deg, FovAxis fov_axis, double aspect) {
  const double tan_half = std::tan(fov_deg * 0.5 * 3.14159265358979323846 / 180.0);
  FovAxis axis = fov_axis;  // smaller and larger: the image axis they name at this aspect
  if (axis == FovAxis::smaller) axis = aspect <= 1 ? FovAxis::x : FovAxis::y;
  if (axis == FovAxis::larger) axis = aspect >= 1 ? FovAxis::x : FovAxis::y;
  if (axis == FovAxis::y) return glm::dvec2(tan_half * aspect, tan_half);
  const double x = axis == FovAxis::diagonal ? tan_half / std::sqrt(1 + 1 / (aspect * aspect)) : tan_half;
  return glm::dvec2(x, x / aspect);
}

/// How the camera maps the scene onto the image.
enum class Projection {
  perspective,   ///< a pinhole (or thin lens) at `position`: fov, fov_axis, aperture_radius
  orthographic,  ///< parallel rays from a rectangle centred on `position`: view_size
};

struct Camera {
  Projection projection = Projection::perspective;
  glm::dvec3 position{0, 0, 1};
  glm::dvec3 look_at{0, 0, 0};
  glm::dvec3 up{0, 1, 0};
  double fov_deg = 39.3;        ///< full angle along fov_axis, degrees, in (0, 180)
  FovAxis fov_axis = FovAxis::x;
  double aperture_radius = 0;   ///< thin lens radius in scene units; 0 = pinhole
  double focus_distance = 1;    ///< distance to the plane in focus, scene units, > 0
  /// orthographic only: full width and height (scene units, each > 0) of the rectangle centred
  /// on `position`, perpendicular to the view direction, from which the camera rays start,
  /// all along the view direction. Image x runs along cross(view, up), image y against up.
  /// Nothing behind the rectangle is seen (it is Mitsuba's near clip plane). The image's
  /// pixels need not be square: view_size may have another aspect than the film.
  glm::dvec2 view_size{2, 2};
  /// orthographic only: when > 0, view_size was made for an image of this width / height and
  /// its height follows the image's aspect, as Mitsuba's orthographic sensor frames it (the view
  /// keeps its width): rendered at width / height a, the view is view_size.y * view_aspect / a
  /// high. 0: view_size as given, whatever the image's size (the native format's).
  double view_aspect = 0;
  /// The medium the camera sits in (index into Scene::media), -1 = vacuum: camera rays start
  /// in it (Mitsuba's <medium> inside a <sensor>).
  int32_t medium = -1;
};

/// The pixel reconstruction filter. Tessera samples it by filter importance sampling: each
/// camera sample's film offset is drawn from the filter's footprint around the pixel centre and
/// counts in that pixel only, so tiles stay independent (docs/renderer.md): with weight 1 for
/// the filters that are never negative (box, tent, gaussian), with a signed weight for those
/// with negative lobes (mitchell, which also stands for Mitsuba's catmullrom, and lanczos).
enum class FilterKind { box, tent, gaussian, mitchell, lanczos };

/// The most lobes a lanczos filter may have (its radius in pixels): camera rays of the image's
/// border pixels reach up to radius - 1/2 pixels beyond it, and real scenes use 2 to 4.
inline constexpr int kMaxLanczosLobes = 64;

struct PixelFilter {
  FilterKind kind = FilterKind::box;
  /// Half-width of the footprint in pixels: box 0.5, tent 1 (Mitsuba's defaults), gaussian
  /// 4 * stddev (Mitsuba truncates there), mitchell 2, lanczos its number of lobes. > 0.
  double radius = 0.5;
  double stddev = 0.5;  ///< gaussian only, pixels, > 0
  /// mitchell only: Mitchell and Netravali's B and C (Mitsuba's defaults 1/3, 1/3; its
  /// catmullrom is B = 0, C = 0.5), each finite.
  double b = 1.0 / 3.0, c = 1.0 / 3.0;
};

struct Film {
  int width = 256;
  int height = 256;
  PixelFilter filter;  ///< native default box; the Mitsuba importer's default gaussian 0.5
};

/// Where Tessera's Russian roulette starts unless the scene says (RenderSettings::rr_depth).
inline constexpr int kDefaultRrDepth = 3;

/// Render settings the scene file carries; a job may override spp, max_depth and seed
/// (JobOverrides).
struct RenderSettings {
  int64_t spp = 64;      ///< samples per pixel, >= 1
  int max_depth = -1;    ///< Mitsuba convention: path segments incl. the camera ray; -1 = unbounded
  uint64_t seed = 0;
  /// Mitsuba's `hide_emitters`: camera rays pass through area emitters and see no environment;
  /// the emitters' light still reaches every surface (and is seen in mirrors).
  bool hide_emitters = false;
  /// Russian roulette may end a path from its rr_depth-th scattering event on (1 = the first
  /// surface the camera ray hits), as Mitsuba's path integrator counts its rr_depth; >= 1.
  /// Where it starts changes the noise, not the image.
  int rr_depth = kDefaultRrDepth;
};

// ---------------------------------------------------------------------------------------------
// Textures. A texture is looked up by a surface point's (u, v); every colour (and roughness,
// opacity) parameter of a material or emitter is a constant or a texture.

enum class TextureKind {
  bitmap,
  checkerboard,
  /// Mitsuba's `rawconstant`: `value` everywhere, with no colour conversion or range check.
  rawconstant,
  /// Mitsuba's `mesh_attribute`: the shape's attribute `attribute` (Shape::attributes) times
  /// `scale`, interpolated at the hit as Mitsuba does (docs/scenes.md, "Mesh attributes").
  mesh_attribute,
  /// Mitsuba's `volume`: a 3D grid (its gridvolume) or a constant (its constvolume) looked up
  /// at the hit's world position (docs/scenes.md, "Volume textures").
  volume,
};

/// How a bitmap's texel values map to the renderer's linear RGB.
enum class TextureColorSpace {
  srgb,    ///< 8/16-bit images used as colours (Mitsuba's default for them): sRGB-decoded
  linear,  ///< float images (EXR, HDR) or `raw="true"`: used as stored
};
enum class TextureFilter { bilinear, nearest };  ///< Mitsuba's filter_type; bilinear = trilinear mip
enum class TextureWrap { repeat, mirror, clamp };

struct Texture {
  std::string name;    ///< id or a generated name, unique in the scene
  std::string origin;  ///< for messages: "textures[2]" or "<file>: line <L>: <texture ...>"
  TextureKind kind = TextureKind::bitmap;

  // TextureKind::bitmap
  std::string file;  ///< bundle path (see Scene::referenced_files)
  TextureColorSpace color_space = TextureColorSpace::srgb;
  TextureFilter filter = TextureFilter::bilinear;
  TextureWrap wrap = TextureWrap::repeat;

  // TextureKind::checkerboard (Mitsuba: color0 where floor(2u) + floor(2v) is even)
  glm::dvec3 color0{0.4, 0.4, 0.4};
  glm::dvec3 color1{0.2, 0.2, 0.2};

  // TextureKind::rawconstant: `value` (any finite numbers); `channels` 1 when Mitsuba's value
  // was a <float> (then value holds it three times; scalar lookups read it), 3 for a <vector>
  // (which Mitsuba's scalar lookups refuse: a scalar parameter cannot use it).
  glm::dvec3 value{0, 0, 0};
  int channels = 3;

  // TextureKind::mesh_attribute: the attribute's name ("vertex_..." or "face_...") and a factor.
  // A shape whose material uses it must have the attribute; a colour parameter reads 1 channel
  // as grey, 3 as RGB; a scalar parameter reads a 1-channel attribute, and 0 from a 3-channel
  // one (Mitsuba's eval_1).
  std::string attribute;
  double scale = 1;

  /// Applied to (u, v, 1) before the lookup (Mitsuba's `to_uv`): row-major 2x3 affine map.
  glm::dmat3 to_uv{1.0};

  // TextureKind::volume. A grid (`file`, its values in `grid`: 1 or 3 channels) is looked up at
  // q = inverse(volume_to_world) * p, p the hit's world position, the grid spanning [0, 1]^3 of
  // q; `filter` (bilinear = Mitsuba's trilinear, or nearest) and `wrap` (Mitsuba's default for
  // volumes: clamp) act per axis. Without a grid it is a constant: `value` and `channels` as for
  // rawconstant (a colour reads value; a scalar reads value.x for 1 channel, the mean of 3).
  std::shared_ptr<const VolumeGridFile> grid;
  glm::dmat4 volume_to_world{1.0};  ///< affine and invertible
};

/// A parameter that is a constant or a texture: value * texture(uv) when texture >= 0 (value
/// then is a scale, 1 unless the scene says otherwise), value alone otherwise.
struct TexturedColor {
  glm::dvec3 value{0.5, 0.5, 0.5};
  int32_t texture = -1;  ///< index into Scene::textures, -1 = constant
  bool is_constant() const { return texture < 0; }
};
/// A scalar parameter: the texture's first channel (its mean for RGB textures, as Mitsuba's
/// scalar lookups) times value.
struct TexturedFloat {
  double value = 1;
  int32_t texture = -1;
  bool is_constant() const { return texture < 0; }
};

// ---------------------------------------------------------------------------------------------
// Materials (BSDFs), with Mitsuba's parameters and their meaning (docs/scenes.md).

enum class MaterialType {
  diffuse,          ///< Lambertian: reflectance
  mirror,           ///< perfect mirror (a smooth conductor of reflectance 1)
  glass,            ///< smooth dielectric: ior, specular_reflectance / _transmittance
  conductor,        ///< smooth conductor: eta, k (complex IOR relative to the outside), specular_reflectance
  rough_conductor,  ///< microfacet conductor: + distribution, alpha_u/v
  rough_glass,      ///< microfacet dielectric (Mitsuba's roughdielectric)
  thin_glass,       ///< thin dielectric sheet: reflection and straight transmission
  plastic,          ///< smooth dielectric coating over a diffuse base: reflectance = diffuse_reflectance
  rough_plastic,    ///< microfacet coating over a diffuse base
  /// Mitsuba's `principled` (Disney's BSDF as Mitsuba 3 writes it): reflectance = base_color,
  /// ior = eta, the other parameters in Material::principled.
  principled,
  /// Mitsuba's `blendbsdf`: (1 - blend_weight) * blend[0] + blend_weight * blend[1].
  blend,
  /// Mitsuba's `principledthin`: a thin sheet with Burley's lobes, reflecting and transmitting
  /// alike from both sides. reflectance = base_color, ior (or ior_texture) = the sheet's eta,
  /// the other parameters in Material::principled (those principled_thin reads, and diff_trans).
  principled_thin,
  /// Mitsuba's `pplastic` as its RGB variants render it (without polarization): a microfacet
  /// reflection of Fresnel F over a diffuse base attenuated by (1 - F) on the way in and out.
  /// reflectance = diffuse_reflectance, ior (or ior_texture), the microfacet keys (anisotropic).
  pplastic,
  /// Mitsuba's `polarizer` as its RGB variants render it (without polarization): light passes
  /// straight through, scaled by specular_transmittance / 2 (Mitsuba's `transmittance`), from
  /// either side; nothing is reflected. Its theta and polarizing change no RGB image.
  polarizer,
  /// Mitsuba's `hair` (Chiang et al. 2016): a fibre's reflection and transmission, meant for
  /// curves; ior = interior / exterior index (!= 1), the rest in Material::hair. Two-sided by
  /// nature: light crosses the fibre.
  hair,
};

enum class MicrofacetDistribution { ggx, beckmann };

/// The parameters of a `principled` material besides base_color (Material::reflectance) and eta
/// (Material::ior), with Mitsuba's names, defaults and meaning: each a weight in [0, 1] (constant
/// or textured), except the three sampling rates (>= 0, constants), which steer which lobe
/// sample() draws without changing the BSDF's value.
struct PrincipledParameters {
  TexturedFloat roughness{0.5, -1};    ///< GGX alpha = roughness^2 (at least 0.001)
  TexturedFloat anisotropic{0, -1};    ///< alpha_u / alpha_v = 1 / (1 - 0.9 anisotropic)
  TexturedFloat metallic{0, -1};       ///< blend towards a Schlick conductor of base_color
  TexturedFloat spec_trans{0, -1};     ///< weight of the rough dielectric transmission
  TexturedFloat spec_tint{0, -1};      ///< tints the dielectric reflection towards base_color
  TexturedFloat sheen{0, -1};          ///< grazing retro-reflection for cloth
  TexturedFloat sheen_tint{0, -1};     ///< tints the sheen towards base_color
  TexturedFloat flatness{0, -1};       ///< blends the diffuse lobe towards a fake subsurface one
  TexturedFloat clearcoat{0, -1};      ///< weight of the GTR1 clear coat lobe
  TexturedFloat clearcoat_gloss{0, -1};  ///< coat alpha = lerp(0.1, 0.001, clearcoat_gloss)
  double main_specular_sampling_rate = 1;
  double clearcoat_sampling_rate = 1;
  double diffuse_reflectance_sampling_rate = 1;
  /// principled_thin only: the share of the diffuse light that goes through the sheet, in
  /// [0, 2] (Mitsuba's range: 0 reflects all of it, 1 half, 2 transmits all).
  TexturedFloat diff_trans{0, -1};
  /// principled_thin only: sampling rates of its specular reflection and transmission and of
  /// its diffuse transmission (>= 0, constants; diffuse_reflectance_sampling_rate as above).
  double specular_reflectance_sampling_rate = 1;
  double specular_transmittance_sampling_rate = 1;
  double diffuse_transmittance_sampling_rate = 1;
  /// Whether the material transmits light: spec_trans textured or non-zero (Mitsuba's
  /// m_has_spec_trans). It then is two-sided by nature, as a dielectric.
  bool transmits() const { return !spec_trans.is_constant() || spec_trans.value != 0; }
  /// Any parameter textured.
  bool textured() const {
    for (const TexturedFloat* f : {&roughness, &anisotropic, &metallic, &spec_trans, &spec_tint,
                                   &sheen, &sheen_tint, &flatness, &clearcoat, &clearcoat_gloss,
                                   &diff_trans}) {
      if (!f->is_constant()) return true;
    }
    return false;
  }
};

/// Mitsuba's absorption of melanin concentrations (d'Eon et al. 2011, as its RGB variants take
/// it): eumelanin (0.419, 0.697, 1.37) + pheomelanin (0.187, 0.4, 1.05), per unit radius.
inline glm::dvec3 melanin_sigma_a(double eumelanin, double pheomelanin) {
  return eumelanin * glm::dvec3(0.419, 0.697, 1.37) + pheomelanin * glm::dvec3(0.187, 0.4, 1.05);
}

/// A `hair` material's parameters besides its index (Material::ior), with Mitsuba's names,
/// defaults and meaning (docs/scenes.md, "`materials`").
struct HairParameters {
  /// Absorption inside the fibre per unit fibre radius, >= 0 per channel: Mitsuba's
  /// scale * sigma_a, or its melanin mix (melanin_sigma_a). The default is Mitsuba's: 1.3
  /// eumelanin and 0.2 pheomelanin.
  TexturedColor sigma_a{melanin_sigma_a(1.3, 0.2), -1};
  double longitudinal_roughness = 0.3;  ///< beta_m, in [0, 1]
  double azimuthal_roughness = 0.3;     ///< beta_n, in [0, 1]
  double scale_tilt_deg = 2;            ///< alpha: the cuticle scales' tilt, degrees
};

struct Material {
  std::string name;
  MaterialType type = MaterialType::diffuse;
  /// diffuse: albedo; plastic / rough_plastic / pplastic: diffuse_reflectance; principled and
  /// principled_thin: base_color.
  /// Linear RGB; constants in [0, 1] (textures are clamped there at lookup).
  TexturedColor reflectance{{0.5, 0.5, 0.5}, -1};
  /// conductors, glass, plastics: Mitsuba's specular_reflectance (default 1).
  TexturedColor specular_reflectance{{1, 1, 1}, -1};
  /// glass kinds: Mitsuba's specular_transmittance (default 1); polarizer: its transmittance.
  TexturedColor specular_transmittance{{1, 1, 1}, -1};
  /// glass kinds, plastics, principled (Mitsuba's eta, or its `specular` converted): interior
  /// over exterior index, > 0.
  double ior = 1.5;
  /// principled_thin and pplastic, whose index Mitsuba lets a texture give: the index is then
  /// ior * texture(uv) (ior the scale). -1 = the constant ior.
  int32_t ior_texture = -1;
  /// conductors: complex index of refraction relative to the exterior, per RGB channel.
  /// `perfect` = true is Mitsuba's material="none": Fresnel reflectance 1 whatever eta and k.
  glm::dvec3 eta{0, 0, 0};
  glm::dvec3 k{1, 1, 1};
  bool perfect = false;
  /// rough kinds: Mitsuba's alpha (alpha_u = alpha_v when isotropic), each > 0.
  MicrofacetDistribution distribution = MicrofacetDistribution::beckmann;
  TexturedFloat alpha_u{0.1, -1};
  TexturedFloat alpha_v{0.1, -1};
  bool sample_visible = true;  ///< rough kinds: visible-normal sampling (Mitsuba's default)
  bool nonlinear = false;      ///< plastics: Mitsuba's `nonlinear`
  /// diffuse, conductors, plastics: both sides reflect alike (glass kinds always are two-sided).
  bool two_sided = false;
  /// Mitsuba's twosided with two different BSDFs: the material index seen from the back, whose
  /// `two_sided` is true (it is shaded with its own front). -1 = none.
  int32_t back = -1;
  /// Mitsuba's mask: the probability that a hit is opaque, in [0, 1]. A hit is transparent with
  /// probability 1 - opacity, decided by a hash of (seed, pixel, sample index, bounce, geometry,
  /// primitive), never by the order of Embree's callbacks.
  TexturedFloat opacity{1, -1};
  /// Mitsuba's normalmap: texture index of a tangent-space normal map (linear RGB in [0, 1]
  /// mapped to [-1, 1]), -1 = none.
  int32_t normal_map = -1;
  /// Mitsuba's bumpmap: texture index of a height field and its scale, -1 = none.
  int32_t bump_map = -1;
  double bump_scale = 1;
  /// principled only: its parameters besides base_color and eta.
  PrincipledParameters principled;
  /// blend only: Mitsuba's `weight` of the second BSDF, in [0, 1] (textures clamped there).
  TexturedFloat blend_weight{0.5, -1};
  /// blend only: the two nested BSDFs (Mitsuba's first and second), any kind but without
  /// sidedness, mask, bump or normal map of their own (the blend carries those).
  std::vector<Material> blend;
  /// hair only: its parameters besides ior.
  HairParameters hair;
  /// Whether the material transmits light (glass kinds, principled with spec_trans,
  /// principled_thin, polarizer, hair, a blend of one): then two-sided by nature.
  bool transmits() const {
    if (type == MaterialType::glass || type == MaterialType::rough_glass ||
        type == MaterialType::thin_glass) {
      return true;
    }
    if (type == MaterialType::principled) return principled.transmits();
    // Mitsuba's principledthin always has a transmission lobe and treats both sides alike.
    if (type == MaterialType::principled_thin) return true;
    if (type == MaterialType::polarizer || type == MaterialType::hair) return true;
    if (type == MaterialType::blend) {
      for (const Material& m : blend) {
        if (m.transmits()) return true;
      }
    }
    return false;
  }
};

// ---------------------------------------------------------------------------------------------
// Emitters that are not shapes (area emitters are Shape::emission).

enum class LightKind {
  point,        ///< position, intensity (W/sr)
  spot,         ///< position and direction from to_world; intensity, cutoff_angle, beam_width
  directional,  ///< direction (to_world's +z), irradiance (W/m^2)
  constant,     ///< uniform environment: radiance
  envmap,       ///< lat-long environment map (Mitsuba's layout): file, scale, to_world
  projector,    ///< a pinhole projecting an image along to_world's +z: value, texture, fov_x_deg, aspect
};

struct Light {
  LightKind kind = LightKind::point;
  std::string origin;  ///< for messages
  /// point / spot: the light's frame (spot shines along +z); directional: +z is the direction
  /// light travels; envmap: the map's orientation. Rigid (rotation + translation).
  glm::dmat4 to_world{1.0};
  /// point / spot: intensity; directional: irradiance; constant: radiance; envmap: scale per
  /// channel (Mitsuba's `scale`, the same on all three); projector: irradiance times Mitsuba's
  /// `scale` (with a texture: the scale alone).
  glm::dvec3 value{1, 1, 1};
  double cutoff_angle_deg = 20;  ///< spot: no light beyond it
  double beam_width_deg = 15;    ///< spot: full intensity inside it (Mitsuba's smooth falloff between)
  std::string file;              ///< envmap: bundle path of the EXR/HDR lat-long map
  /// spot: Mitsuba's `texture`, projected over the cone and multiplying `value`: the direction
  /// (x, y, z) in the light's frame looks up (u, v) = (0.5 + 0.5 x / (z tan cutoff),
  /// 0.5 + 0.5 y / (z tan cutoff)), so the cutoff cone touches the edges of [0, 1]^2.
  /// projector: the irradiance image (Mitsuba's `irradiance` texture) over the image plane.
  /// Index into Scene::textures; -1 = none (value alone).
  int32_t texture = -1;
  /// projector: Mitsuba's perspective frustum. The horizontal field of view (degrees, in
  /// (0, 180)) and the image's width / height (> 0; Mitsuba takes it from the irradiance
  /// texture's resolution, 1 for a constant). A point (x, y, z) of the light's frame (z > 0)
  /// falls on uv = (0.5 - 0.5 x / (z t), 0.5 - 0.5 aspect y / (z t)), t = tan(fov_x / 2), and
  /// is lit when uv is in [0, 1]^2; it receives pi * value * texture(uv) / (z^2 cos theta).
  double fov_x_deg = 0;
  double aspect = 1;
};

// ---------------------------------------------------------------------------------------------
// Shapes.

/// How a curve's control points make its centre line (Mitsuba's linearcurve, bsplinecurve).
enum class CurveBasis {
  linear,   ///< straight segments between consecutive points, spheres at the joints and ends
  bspline,  ///< uniform cubic B-spline: each 4 consecutive points make a segment; open ends
};

/// Shading normals of an SDF grid (Mitsuba's sdfgrid `normals`).
enum class SdfNormals {
  smooth,    ///< blend of the gradients of the 8 voxels around the nearest grid vertex
  analytic,  ///< gradient of the trilinear interpolant (the geometric normal)
};

/// One shape of the scene in world space. Quads, boxes, tetrahedra, triangle lists and meshes
/// are all triangle meshes here; spheres stay exact; an instance places a shape group; curves
/// are round tubes along control points (Embree's round curves, as Mitsuba traces them); an
/// SDF grid is the zero set of a trilinearly interpolated grid of values.
struct Shape {
  enum class Kind { triangles, sphere, instance, curves, sdfgrid };
  Kind kind = Kind::triangles;

  // Kind::triangles
  std::vector<glm::dvec3> positions;   ///< world space (a group's shapes: the group's space)
  std::vector<glm::dvec3> normals;     ///< per-vertex shading normals, empty = use face normals
  std::vector<glm::u32vec3> indices;   ///< counter-clockwise seen from the front
  /// Per-vertex texture coordinates (OBJ `vt`, PLY u/v, serialized UVs, Mitsuba's
  /// parametrisation of rectangle, disk and cube); empty = none (lookups then use (0, 0)).
  std::vector<glm::dvec2> uvs;
  /// Mitsuba's mesh attributes (from PLY files), read by `mesh_attribute` textures: "vertex_*"
  /// one row per position, "face_*" one row per triangle of `indices`.
  std::vector<MeshAttribute> attributes;

  // Kind::sphere
  glm::dvec3 center{0, 0, 0};
  double radius = 1;  ///< > 0
  /// Rotation of the sphere's own frame (its to_world without scale and translation): Mitsuba's
  /// sphere (u, v) = (phi / 2 pi, theta / pi) are measured in that frame.
  glm::dmat3 frame{1.0};

  // Kind::instance: the group's shapes placed by to_world (Embree instancing)
  uint32_t group = 0;  ///< index into Scene::groups
  /// instance: places the group; sdfgrid: maps the grid's [0, 1]^3 to the world (a group's
  /// grid: to the group's space). Affine, invertible.
  glm::dmat4 to_world{1.0};

  // Kind::sdfgrid (Mitsuba's sdfgrid): value (x, y, z) sits at object-space point
  // (x / (nx - 1), y / (ny - 1), z / (nz - 1)); the surface is where the trilinear interpolant
  // of the values is 0, its front facing growing values. No uv (always (0, 0)), never emits.
  glm::u32vec3 sdf_resolution{0, 0, 0};  ///< samples along x, y, z; each >= 2
  /// nx * ny * nz finite values, x fastest: value(x, y, z) = sdf_values[(z * ny + y) * nx + x].
  /// At least one voxel has corners of both signs (or a zero corner).
  std::vector<float> sdf_values;
  SdfNormals sdf_normals = SdfNormals::smooth;
  /// Bundle path of the .vol file the values came from; empty = written inline.
  std::string sdf_file;

  // Kind::curves: tubes of varying radius around each curve's centre line. Only their outside
  // is ever hit (a ray from inside a tube passes out of it), as in Mitsuba.
  CurveBasis curve_basis = CurveBasis::linear;
  /// (x, y, z, radius) per control point: position in world space (a group's curves: the
  /// group's space), radius >= 0 in the same units but never scaled by a transform (Mitsuba's
  /// rule). All curves one after another.
  std::vector<glm::dvec4> control_points;
  /// Control points per curve, in order; each >= 2 (linear) or >= 4 (bspline); they sum to
  /// control_points.size().
  std::vector<uint32_t> curve_sizes;

  /// Turns the front to the other side: spheres face inward, triangles swap their winding
  /// (already applied to `indices` and `normals` for Kind::triangles; kept for messages).
  bool flip_normals = false;

  uint32_t material = 0;             ///< index into Scene::materials (not used by instances)
  glm::dvec3 emission{0, 0, 0};      ///< emitted radiance (W/(m^2 sr)), resolved from `power`
  /// When >= 0 the radiance is emission * textures[emission_texture](uv) (Mitsuba's area
  /// emitter with a textured `radiance`; emission then holds the scale, usually 1).
  int32_t emission_texture = -1;
  bool two_sided_emission = false;   ///< emits from both sides
  std::string origin;                ///< where it came from, for messages: "shapes[3]"
  /// Mesh files only: degenerate faces (zero area, or fewer than 3 vertices) dropped while
  /// loading; scanned meshes have some. Explicit geometry with one is an error instead.
  uint64_t dropped_triangles = 0;

  /// Participating media on either side (indices into Scene::media, -1 = vacuum): a ray that
  /// crosses the surface towards its back (against the front normal) enters `interior`, one
  /// towards its front enters `exterior` (Mitsuba's shape interior / exterior). Only for
  /// triangles and spheres at the top level.
  int32_t interior = -1;
  int32_t exterior = -1;

  bool is_emitter() const { return emission.x > 0 || emission.y > 0 || emission.z > 0; }
  bool bounds_medium() const { return interior >= 0 || exterior >= 0; }
};

// ---------------------------------------------------------------------------------------------
// Participating media (docs/scenes.md, "Media"), with Mitsuba's parameters and meaning.

enum class MediumKind {
  /// Mitsuba's `homogeneous`: constant sigma_t (free flights sampled analytically); albedo a
  /// constant or a volume texture looked up where the path scatters.
  homogeneous,
  /// Mitsuba's `heterogeneous`: sigma_t and albedo each a constant or a volume texture (a
  /// grid over its to_world, TextureKind::volume) looked up at the world position; free
  /// flights by delta tracking against the majorant (the grid's maximum times the scale).
  heterogeneous,
};

/// The phase function: isotropic, or Henyey-Greenstein with mean cosine g (Mitsuba's `hg`,
/// g > 0 scatters forward).
enum class PhaseKind { isotropic, hg };

struct Medium {
  std::string name;    ///< unique in the scene
  std::string origin;  ///< for messages: "media.fog" or "<file>: line <L>: <medium ...>"
  MediumKind kind = MediumKind::homogeneous;
  /// Extinction per scene unit before `scale`, per RGB channel, >= 0; heterogeneous: value *
  /// volume texture (value the texture's scale). Mitsuba's default 1.
  TexturedColor sigma_t{{1, 1, 1}, -1};
  /// Single-scattering albedo sigma_s / sigma_t in [0, 1] per channel, or value * volume
  /// texture (both kinds; clamped to [0, 1] at lookup); Mitsuba's default 0.75.
  TexturedColor albedo{{0.75, 0.75, 0.75}, -1};
  double scale = 1;  ///< multiplies sigma_t, >= 0 (Mitsuba's `scale`)
  PhaseKind phase = PhaseKind::isotropic;
  double g = 0;  ///< hg only: in (-1, 1)
  /// Next-event estimation at this medium's scattering vertices (Mitsuba's sample_emitters);
  /// false: light is found only by phase-sampled rays hitting it.
  bool sample_emitters = true;
};

/// Shapes declared once and placed by instances (Mitsuba's shapegroup). Group shapes are
/// triangles or spheres, never emitters or instances.
struct ShapeGroup {
  std::string name;
  std::string origin;
  std::vector<Shape> shapes;
};

struct Scene {
  Camera camera;
  Film film;
  RenderSettings render;
  std::vector<Material> materials;
  std::vector<Texture> textures;
  std::vector<Shape> shapes;
  std::vector<ShapeGroup> groups;
  std::vector<Light> lights;  ///< emitters that are not shapes
  /// Participating media, named by Shape::interior / exterior and Camera::medium. A scene
  /// without any renders with the surface path tracer, bit for bit as before media existed.
  std::vector<Medium> media;
  /// Files the scene references, relative to the bundle root ('/'-separated, no "..").
  /// Together with the scene file they are the job's bundle.
  std::vector<std::string> referenced_files;
  /// The reader the scene was loaded with (file_reader.h), kept so that whoever builds a
  /// renderer from it can read the files it references (textures, environment maps) without
  /// knowing where they live: a folder on disk or a bundle in memory. Set by the loaders; the
  /// caller keeps what it reads from (the bundle) alive while a renderer is built. Not part of
  /// the scene's content: the writer and comparisons ignore it.
  std::function<std::string(const std::string& bundle_path)> files;
};

}  // namespace tessera
