// The scene's list of materials while it is being parsed.
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "scene/scene.h"

namespace tessera {

/// Materials declared by the file (found by name) plus those the parser derives: the black
/// material of emitters without one, two-sided copies for two-sided shapes, and MTL materials
/// of OBJ meshes. Indices are stable: they become Shape::material.
class MaterialTable {
 public:
  /// Adds a material of the "materials" object. Its name must be new.
  uint32_t declare(Material material);
  /// The index of the declared material `name`, or nullopt.
  std::optional<uint32_t> find_declared(const std::string& name) const;

  /// The built-in black diffuse material "(black)" of emitters without a material; added on
  /// first use.
  uint32_t black();
  /// Adds a derived material (e.g. "CornellBox-Sphere.obj:leftSphere") unless one of that name
  /// was derived before, in which case that one's index is returned.
  uint32_t derive(const Material& material);
  /// A material reflecting alike on both sides: `index` itself when it already does (two-sided,
  /// glass, or a principled material that transmits), else its copy "<name> (two-sided)", made
  /// once per material.
  uint32_t two_sided(uint32_t index);

  const Material& operator[](uint32_t index) const { return materials_[index]; }
  /// Sets Material::back of material `index`.
  void set_back(uint32_t index, int32_t back) { materials_[index].back = back; }
  /// The materials in index order; the table is empty afterwards.
  std::vector<Material> take();

 private:
  uint32_t push(Material material);

  std::vector<Material> materials_;
  std::map<std::string, uint32_t> declared_;
  std::map<std::string, uint32_t> derived_;
  std::map<uint32_t, uint32_t> two_sided_copies_;
};

}  // namespace tessera
