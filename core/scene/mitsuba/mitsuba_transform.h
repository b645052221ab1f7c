// Mitsuba's <transform name="to_world"> element (docs/mitsuba.md, "Transforms").
#pragma once

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include "scene/mitsuba/mitsuba_xml_document.h"
#include "scene/transform.h"

namespace tessera {

/// Reads the operations of a <transform> element and composes them in document order, each
/// new one applied after those before it (left-multiplied: M = op * M), as Mitsuba does:
///
/// - <translate x= y= z=/> (missing ones 0) or <translate value="x, y, z"/>;
/// - <rotate x= y= z= angle=/> or <rotate value="x, y, z" angle=/>: right-handed rotation by
///   `angle` degrees about the axis; Mitsuba does not normalise the axis, and neither does
///   this (an axis not of unit length also scales and shears; a note on stderr says so); a
///   zero axis is refused;
/// - <scale value="s"/> (uniform), <scale value="x, y, z"/> or <scale x= y= z=/> (missing ones
///   1); every factor non-zero;
/// - <matrix value="16 numbers"/> row-major (the last row 0 0 0 1), or 9 numbers for the linear
///   part;
/// - <lookat origin="x, y, z" target="x, y, z" up="x, y, z"/> (up optional): the frame whose +z
///   looks from origin to target, +y up and +x = up x dir, placed at origin.
///
/// Throws SceneError naming the operation's element for unknown operations, bad values, an
/// undefined lookat, or a result that is not finite and invertible.
Transform read_mitsuba_transform(const MitsubaElement& transform);

/// Mitsuba's look_at matrix: columns (left, up', dir, origin) with dir = normalize(target -
/// origin), left = normalize(cross(up, dir)), up' = cross(dir, left). Not finite when origin =
/// target or up is parallel to dir.
glm::dmat4 mitsuba_look_at(const glm::dvec3& origin, const glm::dvec3& target,
                           const glm::dvec3& up);

/// Mitsuba's rotation matrix for `angle_deg` degrees about `axis`, right-handed: c I + (1 - c)
/// a a^T + s [a]x with the axis as given, not normalised (drjit's rotate, which Mitsuba 3's
/// Transform4f::rotate calls with the XML's axis), so a non-unit axis scales and shears too.
glm::dmat4 mitsuba_rotate(const glm::dvec3& axis, double angle_deg);

}  // namespace tessera
