#include "scene/mitsuba/mitsuba_integrator.h"

#include <limits>
#include <string>

#include "scene/mitsuba/mitsuba_plugin.h"

namespace tessera {

int read_mitsuba_integrator(const MitsubaElement& element, const MitsubaIds& ids) {
  MitsubaPlugin integrator(element, ids);
  if (integrator.type() != "path") {
    fail_at(element,
            "unsupported integrator (Tessera is a unidirectional path tracer with "
            "next-event estimation: use type=\"path\")");
  }
  int max_depth = -1;
  if (std::optional<int64_t> depth = integrator.take_integer("max_depth")) {
    if (*depth == 0 || *depth < -1 || *depth > std::numeric_limits<int>::max()) {
      fail_at(*integrator.property("max_depth"),
              "must be -1 (unbounded) or >= 1 (got " + std::to_string(*depth) + ")");
    }
    max_depth = int(*depth);
  }
  integrator.ignore("rr_depth");
  if (integrator.take_boolean("hide_emitters").value_or(false)) {
    fail_at(*integrator.property("hide_emitters"),
            "Tessera always shows emitters seen directly (remove hide_emitters)");
  }
  integrator.finish();
  return max_depth;
}

}  // namespace tessera
