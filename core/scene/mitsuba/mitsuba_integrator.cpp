#include "scene/mitsuba/mitsuba_integrator.h"

#include <algorithm>
#include <initializer_list>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "scene/mitsuba/mitsuba_plugin.h"
#include "scene/mitsuba/mitsuba_values.h"
#include "scene/message_text.h"

namespace tessera {
namespace {

int read_max_depth(MitsubaPlugin& integrator) {
  std::optional<int64_t> depth = integrator.take_integer("max_depth");
  if (!depth) return -1;
  if (*depth == 0 || *depth < -1 || *depth > std::numeric_limits<int>::max()) {
    fail_at(*integrator.property("max_depth"),
            "must be -1 (unbounded) or >= 1 (got " + std::to_string(*depth) + ")");
  }
  return int(*depth);
}

/// rr_depth as Tessera counts it (RenderSettings::rr_depth: roulette from that scattering event
/// on, 1 = the camera ray's hit), from the integrator's rr_depth (> 0, Mitsuba's default 5).
/// Mitsuba's path applies roulette where depth >= rr_depth after the event, as Tessera does;
/// volpath, volpathmis and ptracer where depth > rr_depth, one event later. Absent, Tessera's
/// default (kDefaultRrDepth): where roulette starts changes the noise, not the image.
int read_rr_depth(MitsubaPlugin& integrator) {
  std::optional<int64_t> rr_depth = integrator.take_integer("rr_depth");
  if (!rr_depth) return kDefaultRrDepth;
  if (*rr_depth <= 0) {
    fail_at(*integrator.property("rr_depth"),
            "must be > 0 (got " + std::to_string(*rr_depth) + ")");
  }
  // Past 2^31 - 2 no path gets there either.
  const int depth = int(std::min<int64_t>(*rr_depth, std::numeric_limits<int>::max() - 1));
  return integrator.type() == "path" ? depth : depth + 1;
}

/// Mitsuba's projective-sampling integrators read a string option from a fixed set and throw on
/// any other value; so does the importer.
void check_choice(MitsubaPlugin& integrator, std::string_view name,
                  std::initializer_list<std::string_view> choices) {
  std::optional<std::string> value = integrator.take_string(name);
  if (!value) return;
  std::string list;
  for (std::string_view choice : choices) {
    if (*value == choice) return;
    list += (list.empty() ? "" : ", ") + std::string(choice);
  }
  fail_at(*integrator.property(name), "must be one of " + list + " (got \"" + *value + "\")");
}

/// direct_projective (Mitsuba's Python plugin ad/integrators/direct_projective.py): its primal
/// image is direct illumination with emitter and BSDF sampling weighed by MIS, one emitter
/// sample, max_depth forced to 2, exactly the image of `direct`. Its other options choose how
/// gradients are sampled and change no pixel of the primal image.
void read_direct_projective(MitsubaPlugin& integrator, MitsubaIntegrator& result) {
  // PSIntegrator reads max_depth and rr_depth, checks them, then direct_projective sets them
  // to 2: checked as Mitsuba checks them and otherwise ignored.
  std::optional<int64_t> depth = integrator.take_integer("max_depth");
  if (depth && *depth < -1) {
    fail_at(*integrator.property("max_depth"),
            "must be -1 (unbounded) or >= 0 (got " + std::to_string(*depth) + ")");
  }
  std::optional<int64_t> rr_depth = integrator.take_integer("rr_depth");
  if (rr_depth && *rr_depth <= 0) {
    fail_at(*integrator.property("rr_depth"),
            "must be > 0 (got " + std::to_string(*rr_depth) + ")");
  }
  for (const char* samples : {"sppc", "sppp", "sppi", "guiding_rounds"}) {
    integrator.take_integer(samples);  // gradient samples only
  }
  integrator.take_boolean("guiding_proj");
  check_choice(integrator, "guiding", {"none", "grid", "octree"});
  check_choice(integrator, "project_seed", {"both", "bsdf", "emitter"});
  result.max_depth = 2;
  result.note = "the direct_projective integrator's image is direct illumination: rendered as "
                "Tessera's path tracer with max_depth 2 (its gradient options are ignored)";
}

/// The picture of an integrator that wraps others and adds channels of its own (moment, aov):
/// its nested integrators, read as if they stood alone; the first one's picture is the image.
MitsubaIntegrator read_first_nested(MitsubaPlugin& integrator, const MitsubaIds& ids,
                                    const std::string& what, const std::string& channels) {
  const std::vector<MitsubaObject> nested = integrator.take_objects("integrator");
  if (nested.empty()) {
    fail_at(integrator.element(), "the " + integrator.type() +
                                      " integrator needs a nested integrator (" + what + ")");
  }
  MitsubaIntegrator result = read_mitsuba_integrator(*nested.front().element, ids);
  const std::string* first = nested.front().element->attribute("type");
  result.note = "the " + integrator.type() + " integrator's picture is its first nested integrator's (" +
                (first ? *first : std::string("?")) + ")" +
                (result.note.empty() ? std::string() : ": " + result.note) + "; " + channels +
                " are not written";
  return result;
}

/// moment: Mitsuba 3.9.1 writes the first nested integrator's picture to the film's R, G, B
/// (bit for bit the image that integrator renders alone, same seed: measured on mitsuba-data's
/// tests/scenes/spot_light/test_spot_direct.xml) and adds AOV channels, each nested
/// integrator's X, Y, Z and their second moments (m2_*). Tessera renders that picture and
/// writes no AOV channels; the note says so.
MitsubaIntegrator read_moment(MitsubaPlugin& integrator, const MitsubaIds& ids) {
  MitsubaIntegrator result = read_first_nested(
      integrator, ids, "its picture is the first one's",
      "its AOV channels (each nested integrator's X, Y, Z and second moments m2_*)");
  // The moment integrator samples its nested integrators itself, so its own hide_emitters
  // changes no channel.
  integrator.ignore("hide_emitters");
  integrator.finish();
  return result;
}

/// The AOV types Mitsuba 3.9.1's aov integrator knows (src/integrators/aov.cpp throws on any
/// other).
constexpr std::string_view kAovTypes[] = {
    "albedo", "depth",  "position", "uv",     "geo_normal", "sh_normal",  "boundary_test",
    "dp_du",  "dp_dv",  "duv_dx",   "duv_dy", "prim_index", "shape_index"};

/// aov: Mitsuba 3.9.1 renders each nested integrator on its own (same seed) and writes the first
/// one's picture to the film's R, G, B, then each one's RGBA and the listed AOVs (depth,
/// normals, albedo...) as extra channels; measured on mitsuba-data's docs/scenes/integrator_aov.xml
/// with `direct` and `path` nested: R, G, B equal `direct` alone to 4e-7. Without a nested
/// integrator its image is the AOVs alone, not a rendered picture: refused. The `aovs` list is
/// checked as Mitsuba checks it (a <name>:<type> pair each, a known type), so a scene Mitsuba
/// refuses is refused here too; the channels themselves are not written.
MitsubaIntegrator read_aov(MitsubaPlugin& integrator, const MitsubaIds& ids) {
  const std::string list = integrator.take_string("aovs").value_or("");
  std::vector<std::string> names;
  // Split as Mitsuba's string::tokenize splits it: at commas and spaces, empty items dropped.
  for (std::string_view item : split_mitsuba_list(list)) {
    const std::string token(item);
    const size_t colon = token.find(':');
    const std::string name = colon == std::string::npos ? token : token.substr(0, colon);
    const std::string type = colon == std::string::npos ? std::string() : token.substr(colon + 1);
    if (colon == std::string::npos || name.empty() || type.empty() ||
        type.find(':') != std::string::npos) {
      fail_at(*integrator.property("aovs"),
              "\"" + token + "\" is not a <name>:<type> pair (e.g. \"nn:sh_normal\")");
    }
    bool known = false;
    for (std::string_view t : kAovTypes) known = known || type == t;
    if (!known) {
      std::string types;
      for (std::string_view t : kAovTypes) types += (types.empty() ? "" : ", ") + std::string(t);
      fail_at(*integrator.property("aovs"),
              "unknown AOV type \"" + type + "\" (Mitsuba's are " + types + ")");
    }
    names.push_back(name);
  }
  std::string channels = "its AOV channels (";
  for (size_t i = 0; i < names.size(); ++i) channels += (i ? ", " : "") + names[i];
  channels += names.empty() ? "each nested integrator's RGBA)" : ", and each nested integrator's RGBA)";
  MitsubaIntegrator result = read_first_nested(
      integrator, ids,
      "without one its image is the AOVs alone, not a rendered picture", channels);
  integrator.ignore("hide_emitters");  // as in moment: the nested integrators sample
  integrator.finish();
  return result;
}

/// Whether Mitsuba's particle tracer cannot show the camera this material's surface or what lies
/// behind it (mitsuba_ptracer_note).
bool hidden_from_particle_tracer(const Material& m) {
  switch (m.type) {
    case MaterialType::mirror:
    case MaterialType::glass:
    case MaterialType::conductor:
    case MaterialType::thin_glass:
    case MaterialType::plastic:
    case MaterialType::polarizer:
      return true;
    default:
      break;
  }
  if (!m.opacity.is_constant() || m.opacity.value < 1) return true;  // mask or null BSDF
  return std::any_of(m.blend.begin(), m.blend.end(), hidden_from_particle_tracer);
}

}  // namespace

std::string mitsuba_ptracer_note(const Scene& scene) {
  std::vector<bool> used(scene.materials.size(), false);
  auto use = [&](uint32_t index) {
    if (index >= used.size() || used[index]) return;
    used[index] = true;
    const int32_t back = scene.materials[index].back;
    if (back >= 0 && size_t(back) < used.size()) used[size_t(back)] = true;
  };
  // Instances name no material; their groups' shapes do.
  for (const Shape& shape : scene.shapes) {
    if (shape.kind != Shape::Kind::instance) use(shape.material);
  }
  for (const ShapeGroup& group : scene.groups) {
    for (const Shape& shape : group.shapes) use(shape.material);
  }
  std::string names;
  for (size_t i = 0; i < used.size(); ++i) {
    if (!used[i] || !hidden_from_particle_tracer(scene.materials[i])) continue;
    names += (names.empty() ? "\"" : ", \"") + printable(scene.materials[i].name) + "\"";
  }
  if (names.empty()) return "the same image (the scene has no smooth or see-through surface)";
  return "not the same image on the smooth or see-through surfaces the camera sees, directly or "
         "through other smooth ones: Mitsuba's particle tracer cannot connect them to the camera "
         "(a smooth lobe has no value toward it; a see-through surface blocks the connection), "
         "so it leaves them black (smooth plastic: its diffuse base only) where Tessera renders "
         "them lit; such materials here: " +
         names;
}

MitsubaIntegrator read_mitsuba_integrator(const MitsubaElement& element, const MitsubaIds& ids) {
  MitsubaPlugin integrator(element, ids);
  const std::string& type = integrator.type();
  MitsubaIntegrator result;
  if (type == "path" || type == "ptracer" || type == "volpath" || type == "volpathmis") {
    result.max_depth = read_max_depth(integrator);
    result.rr_depth = read_rr_depth(integrator);
    if (type == "ptracer") {
      integrator.ignore("samples_per_pass");
      result.particle_tracer = true;
      result.note = "the ptracer integrator is rendered by Tessera's path tracer (other noise)";
    } else if (type == "volpath" || type == "volpathmis") {
      // volpathmis weighs its spectral free-flight strategies by MIS: the same image as volpath.
      if (type == "volpathmis") integrator.ignore("use_spectral_mis");
      result.counts_null_interactions = false;
      result.volumetric = true;
    }
  } else if (type == "direct") {
    result.max_depth = 2;
    result.emitter_samples = integrator.take_integer("emitter_samples").value_or(1);
    for (const char* samples : {"bsdf_samples", "shading_samples"}) {
      integrator.ignore(samples);  // how many samples of each strategy: noise only
    }
    result.note = "the direct integrator is rendered as Tessera's path tracer with max_depth 2 "
                  "(direct illumination only)";
  } else if (type == "direct_projective") {
    read_direct_projective(integrator, result);
  } else if (type == "moment") {
    return read_moment(integrator, ids);
  } else if (type == "aov") {
    return read_aov(integrator, ids);
  } else if (type == "stokes" || type == "depth") {
    fail_at(element,
            "this integrator makes another kind of image than a rendered picture (Tessera "
            "renders path, ptracer, volpath, volpathmis, direct, direct_projective and "
            "the first nested integrator of moment and aov)");
  } else {
    fail_at(element,
            "unsupported integrator (Tessera renders path, ptracer, volpath, volpathmis, direct, "
            "direct_projective and the first nested integrator of moment and aov)");
  }
  result.hide_emitters = integrator.take_boolean("hide_emitters").value_or(false);
  integrator.finish();
  return result;
}

}  // namespace tessera
