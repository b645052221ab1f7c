#include "scene/native/material_table.h"

#include <utility>

#include "scene/native/material_parser.h"

namespace tessera {

uint32_t MaterialTable::push(Material material) {
  materials_.push_back(std::move(material));
  return static_cast<uint32_t>(materials_.size() - 1);
}

uint32_t MaterialTable::declare(Material material) {
  std::string name = material.name;
  uint32_t index = push(std::move(material));
  declared_[name] = index;
  return index;
}

std::optional<uint32_t> MaterialTable::find_declared(const std::string& name) const {
  auto it = declared_.find(name);
  if (it == declared_.end()) return std::nullopt;
  return it->second;
}

uint32_t MaterialTable::black() {
  Material black;
  black.name = "(black)";
  black.type = MaterialType::diffuse;
  black.reflectance.value = {0, 0, 0};
  return derive(black);
}

uint32_t MaterialTable::derive(const Material& material) {
  auto it = derived_.find(material.name);
  if (it != derived_.end()) return it->second;
  uint32_t index = push(material);
  derived_[material.name] = index;
  return index;
}

uint32_t MaterialTable::two_sided(uint32_t index) {
  const Material& original = materials_[index];
  if (original.two_sided || original.transmits()) return index;
  auto it = two_sided_copies_.find(index);
  if (it != two_sided_copies_.end()) return it->second;
  Material copy = original;
  copy.name += " (two-sided)";
  copy.two_sided = true;
  uint32_t copy_index = push(std::move(copy));
  two_sided_copies_[index] = copy_index;
  return copy_index;
}

std::vector<Material> MaterialTable::take() {
  std::vector<Material> result = std::move(materials_);
  *this = MaterialTable();
  return result;
}

}  // namespace tessera
