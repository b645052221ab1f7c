// Mitsuba's rawconstant texture.
#pragma once

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "bitmap_texture.h"

namespace tessera {

/// The same value at every (u, v), used as written: no colour conversion, no range (Mitsuba's
/// src/spectra/rawconstant.cpp). A one-channel value reads as itself in scalar lookups; a
/// three-channel one as its luminance, as RGB bitmaps do (Mitsuba refuses scalar lookups of it,
/// and so does the importer; the native format allows them with this meaning). Immutable.
class RawConstant {
 public:
  RawConstant(glm::vec3 value, bool one_channel) : value_(value), one_channel_(one_channel) {}

  glm::vec3 eval(glm::vec2 /*uv*/) const { return value_; }
  float eval_1(glm::vec2 /*uv*/) const {
    return one_channel_ ? value_.x : mitsuba_luminance(value_);
  }

 private:
  glm::vec3 value_;
  bool one_channel_;
};

}  // namespace tessera
