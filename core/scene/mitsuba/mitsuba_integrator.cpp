#include "scene/mitsuba/mitsuba_integrator.h"

#include <limits>
#include <string>

#include "scene/mitsuba/mitsuba_plugin.h"

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

}  // namespace

MitsubaIntegrator read_mitsuba_integrator(const MitsubaElement& element, const MitsubaIds& ids) {
  MitsubaPlugin integrator(element, ids);
  const std::string& type = integrator.type();
  MitsubaIntegrator result;
  if (type == "path" || type == "ptracer" || type == "volpath") {
    result.max_depth = read_max_depth(integrator);
    integrator.ignore("rr_depth");
    if (type == "ptracer") {
      integrator.ignore("samples_per_pass");
      result.note = "the ptracer integrator is rendered by Tessera's path tracer (the same "
                    "image, other noise)";
    } else if (type == "volpath") {
      result.note = "the volpath integrator is rendered by Tessera's path tracer (the same "
                    "image without media)";
    }
  } else if (type == "direct") {
    result.max_depth = 2;
    result.emitter_samples = integrator.take_integer("emitter_samples").value_or(1);
    for (const char* samples : {"bsdf_samples", "shading_samples"}) {
      integrator.ignore(samples);  // how many samples of each strategy: noise only
    }
    result.note = "the direct integrator is rendered as Tessera's path tracer with max_depth 2 "
                  "(direct illumination only)";
  } else if (type == "aov" || type == "moment" || type == "stokes" || type == "depth") {
    fail_at(element,
            "this integrator makes another kind of image than a rendered picture (Tessera "
            "renders path, ptracer, volpath without media and direct)");
  } else if (type == "volpathmis" || type == "prbvolpath") {
    fail_at(element,
            "integrators for participating media are not supported (Tessera renders path, "
            "ptracer, volpath without media and direct)");
  } else {
    fail_at(element,
            "unsupported integrator (Tessera renders path, ptracer, volpath without media and "
            "direct)");
  }
  result.hide_emitters = integrator.take_boolean("hide_emitters").value_or(false);
  integrator.finish();
  return result;
}

}  // namespace tessera
