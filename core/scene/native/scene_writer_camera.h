// Internal to write_scene_json (scene_writer.h), in namespace scene_writer: the camera and the
// film.
#pragma once

#include <string>

#include "scene/scene.h"

namespace tessera::scene_writer {

/// The "camera" member, with its trailing ",\n" (the caller may insert before "\n  },\n").
std::string camera_json(const Camera& c);

/// The "film" member, with its trailing ",\n".
std::string film_json(const Film& film);

}  // namespace tessera::scene_writer
