#pragma once

#include <stdexcept>
#include <string>

namespace tessera {

/// A scene that cannot be rendered. what() is one line naming the place that is wrong, e.g.
/// "shapes[3].radius: must be > 0" or "meshes/bunny.ply: line 12: expected 3 vertex indices".
class SceneError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace tessera
