#include "texture_set.h"

#include <stdexcept>
#include <string>
#include <type_traits>

#include "scene/scene_error.h"
#include "texel_image.h"

namespace tessera {
namespace {

glm::vec3 to_float(const glm::dvec3& v) { return {float(v.x), float(v.y), float(v.z)}; }

BitmapTexture open_bitmap(const Texture& t, const FileReader& reader) {
  std::string bytes;
  try {
    bytes = reader(t.file);
  } catch (const SceneError& e) {
    throw SceneError(t.origin + ": " + e.what());
  }
  return BitmapTexture(decode_texel_image(bytes, t.file, t.color_space, t.origin), t.filter, t.wrap,
                       UvTransform::from(t.to_uv));
}

}  // namespace

TextureSet::TextureSet(const std::vector<Texture>& textures, const FileReader& reader) {
  textures_.reserve(textures.size());
  for (const Texture& t : textures) {
    switch (t.kind) {
      case TextureKind::bitmap:
        textures_.emplace_back(open_bitmap(t, reader));
        break;
      case TextureKind::checkerboard:
        textures_.emplace_back(
            Checkerboard(to_float(t.color0), to_float(t.color1), UvTransform::from(t.to_uv)));
        break;
      case TextureKind::rawconstant:
        textures_.emplace_back(RawConstant(to_float(t.value), t.channels == 1));
        break;
      case TextureKind::mesh_attribute:
        textures_.emplace_back(MeshAttributeRef{});
        break;
      case TextureKind::volume:
        if (t.grid) {
          textures_.emplace_back(VolumeTexture(t.grid, t.volume_to_world, t.filter, t.wrap));
        } else {
          textures_.emplace_back(VolumeTexture(to_float(t.value), t.channels == 1));
        }
        break;
    }
  }
}

const TextureSet::Entry& TextureSet::at(int32_t texture) const {
  if (texture < 0 || size_t(texture) >= textures_.size()) {
    throw std::out_of_range("TextureSet: texture index " + std::to_string(texture) + " of " +
                            std::to_string(textures_.size()));
  }
  return textures_[size_t(texture)];
}

glm::vec3 TextureSet::lookup(int32_t texture, glm::vec2 uv) const {
  return std::visit([uv](const auto& t) { return t.eval(uv); }, at(texture));
}

float TextureSet::lookup_1(int32_t texture, glm::vec2 uv) const {
  const Entry& e = at(texture);
  if (const auto* b = std::get_if<BitmapTexture>(&e)) return b->eval_1(uv);
  if (const auto* r = std::get_if<RawConstant>(&e)) return r->eval_1(uv);
  if (std::holds_alternative<MeshAttributeRef>(e)) return 0.0f;
  if (const auto* v = std::get_if<VolumeTexture>(&e)) {
    return v->grid() ? 0.0f : v->eval_1(glm::vec3(0.0f));
  }
  return mitsuba_luminance(std::get<Checkerboard>(e).eval_scalar_order(uv));
}

// One dispatch on the kind per lookup (a surface point's lookups are the hot ones).
glm::vec3 TextureSet::lookup(int32_t texture, const TexturePoint& at) const {
  return std::visit(
      [&](const auto& t) -> glm::vec3 {
        using T = std::decay_t<decltype(t)>;
        if constexpr (std::is_same_v<T, VolumeTexture>) {
          return t.eval(at.p);
        } else if constexpr (std::is_same_v<T, MeshAttributeRef>) {
          if (!at.attributes) return glm::vec3(0.0f);
          int channels = 0;
          const glm::vec3 v = at.attributes->eval(texture, at.primitive, at.barycentric, channels);
          return channels == 1 ? glm::vec3(v.x) : v;
        } else {
          return t.eval(at.uv);
        }
      },
      this->at(texture));
}

float TextureSet::lookup_1(int32_t texture, const TexturePoint& at) const {
  return std::visit(
      [&](const auto& t) -> float {
        using T = std::decay_t<decltype(t)>;
        if constexpr (std::is_same_v<T, VolumeTexture>) {
          return t.eval_1(at.p);
        } else if constexpr (std::is_same_v<T, MeshAttributeRef>) {
          if (!at.attributes) return 0.0f;
          int channels = 0;
          const glm::vec3 v = at.attributes->eval(texture, at.primitive, at.barycentric, channels);
          return channels == 1 ? v.x : 0.0f;
        } else if constexpr (std::is_same_v<T, Checkerboard>) {
          return mitsuba_luminance(t.eval_scalar_order(at.uv));
        } else {
          return t.eval_1(at.uv);
        }
      },
      this->at(texture));
}

glm::vec2 TextureSet::gradient(int32_t texture, glm::vec2 uv) const {
  const Entry& e = at(texture);
  if (const auto* b = std::get_if<BitmapTexture>(&e)) return b->gradient(uv);
  return {0.0f, 0.0f};
}

glm::vec3 TextureSet::eval(const TexturedColor& c, glm::vec2 uv) const {
  const glm::vec3 value = to_float(c.value);
  return c.is_constant() ? value : value * lookup(c.texture, uv);
}

float TextureSet::eval(const TexturedFloat& f, glm::vec2 uv) const {
  return f.is_constant() ? float(f.value) : float(f.value) * lookup_1(f.texture, uv);
}

}  // namespace tessera
