#include "render/light/envmap_light.h"

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>
#include <glm/matrix.hpp>
#include <sstream>

#include "accum/accumulation.h"
#include "render/sampling/warp.h"
#include "scene/scene_error.h"

namespace tessera {
namespace {

std::string where(const Light& light) { return light.origin + ": " + light.file; }

float srgb_to_linear(float c) {
  return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f);
}

/// Throws unless every texel channel (and the scale) is finite and >= 0.
void check_texels(const Light& light, uint32_t width, const std::vector<float>& rgb) {
  for (int c = 0; c < 3; ++c) {
    if (!std::isfinite(light.value[c]) || light.value[c] < 0) {
      throw SceneError(where(light) + ": scale must be finite and >= 0");
    }
  }
  for (size_t i = 0; i < rgb.size(); ++i) {
    const float v = rgb[i];
    if (std::isfinite(v) && v >= 0) continue;
    const size_t texel = i / 3;
    std::ostringstream message;
    message << where(light) << ": texel (x " << texel % width << ", y " << texel / width
            << ") channel " << "RGB"[i % 3] << " is "
            << (std::isnan(v)   ? "NaN"
                : std::isinf(v) ? "infinite"
                                : "negative (" + std::to_string(v) + ")")
            << "; environment maps must hold finite radiance >= 0";
    throw SceneError(message.str());
  }
}

}  // namespace

EnvmapLight EnvmapLight::from_file(const Light& light, const FileReader& reader) {
  const std::string bytes = reader(light.file);
  OIIO::Filesystem::IOMemReader memory(bytes.data(), bytes.size());
  auto in = OIIO::ImageInput::open(light.file, nullptr, &memory);
  if (!in) {
    throw SceneError(where(light) + ": cannot decode the environment map (" + OIIO::geterror() +
                     ")");
  }
  const OIIO::ImageSpec& spec = in->spec();
  if (spec.width < 1 || spec.height < 1 || spec.nchannels < 1 || spec.depth != 1) {
    throw SceneError(where(light) + ": the environment map is empty or not a 2D image");
  }
  const size_t w = size_t(spec.width), h = size_t(spec.height), nc = size_t(spec.nchannels);
  std::vector<float> pixels(w * h * nc);
  if (!in->read_image(0, 0, 0, int(nc), OIIO::TypeDesc::FLOAT, pixels.data())) {
    throw SceneError(where(light) + ": cannot read the environment map's pixels (" +
                     in->geterror() + ")");
  }
  // Mitsuba linearises 8-bit sRGB images when it converts them to float; EXR and HDR are linear.
  const bool srgb =
      spec.format.basetype == OIIO::TypeDesc::UINT8 &&
      OIIO::Strutil::iequals(spec.get_string_attribute("oiio:ColorSpace", "sRGB"), "sRGB");
  std::vector<float> rgb(w * h * 3);
  for (size_t i = 0; i < w * h; ++i) {
    for (size_t c = 0; c < 3; ++c) {
      // One or two channels (Y, YA) are grey; more are RGB(A...).
      const float v = pixels[i * nc + (nc >= 3 ? c : 0)];
      rgb[i * 3 + c] = srgb ? srgb_to_linear(v) : v;
    }
  }
  return EnvmapLight(light, uint32_t(w), uint32_t(h), std::move(rgb));
}

EnvmapLight::EnvmapLight(const Light& light, uint32_t width, uint32_t height,
                         std::vector<float> rgb)
    : width_(width), height_(height), rgb_(std::move(rgb)), scale_(glm::vec3(light.value)) {
  if (width < 1 || height < 1 || rgb_.size() != size_t(width) * height * 3) {
    throw SceneError(where(light) + ": environment map of " + std::to_string(width) + " x " +
                     std::to_string(height) + " texels has " + std::to_string(rgb_.size()) +
                     " values, expected 3 per texel and at least one texel");
  }
  check_texels(light, width, rgb_);
  if (height_ == 1) {  // one row: the same radiance at both poles, constant in v
    rgb_.insert(rgb_.end(), rgb_.begin(), rgb_.end());
    height_ = 2;
  }
  const glm::dmat3 rotation(light.to_world);
  to_world_ = glm::mat3(rotation);
  to_local_ = glm::mat3(glm::inverse(rotation));

  cos_theta_.resize(height_);
  for (uint32_t y = 0; y < height_; ++y) cos_theta_[y] = std::cos(kPiD * y / double(height_ - 1));
  cos_theta_.back() = -1.0;  // exact at the south pole
  cell_omega_.resize(height_ - 1);
  std::vector<double> weights(size_t(width_) * (height_ - 1));
  for (uint32_t y = 0; y + 1 < height_; ++y) {
    cell_omega_[y] = 2.0 * kPiD / width_ * (cos_theta_[y] - cos_theta_[y + 1]);
    for (uint32_t x = 0; x < width_; ++x) {
      const uint32_t x1 = (x + 1) % width_;
      const glm::vec3 sum = texel(x, y) + texel(x1, y) + texel(x, y + 1) + texel(x1, y + 1);
      const glm::dvec3 mean = glm::dvec3(scale_) * glm::dvec3(sum) * 0.25;
      weights[size_t(y) * width_ + x] =
          std::max(0.0, luminance(mean.x, mean.y, mean.z)) * cell_omega_[y];
    }
  }
  distribution_ = PiecewiseConstant2D(weights, width_, height_ - 1);
}

glm::vec3 EnvmapLight::texel(uint32_t x, uint32_t y) const {
  const size_t i = (size_t(y) * width_ + x) * 3;
  return {rgb_[i], rgb_[i + 1], rgb_[i + 2]};
}

glm::vec2 EnvmapLight::direction_to_uv(glm::vec3 world_d) const {
  const glm::vec3 d = glm::normalize(to_local_ * world_d);
  float u = std::atan2(d.x, -d.z) * (0.5f * kInvPi);
  u -= std::floor(u);
  const float v = std::acos(std::clamp(d.y, -1.0f, 1.0f)) * kInvPi;
  return {u, v};
}

glm::u32vec2 EnvmapLight::cell_of(glm::vec2 uv) const {
  // Texel columns sit at u = (x + 0.5) / W: shift by half a texel, wrap.
  float gx = uv.x * float(width_) - 0.5f;
  if (gx < 0) gx += float(width_);
  const float gy = uv.y * float(height_ - 1);
  // Written so that a NaN (from a NaN direction) lands on cell 0 rather than in an undefined
  // float-to-integer conversion.
  const auto index = [](float g, uint32_t last) {
    return g >= 0 ? std::min(uint32_t(std::min(g, float(last))), last) : 0u;
  };
  return {index(gx, width_ - 1), index(gy, height_ - 2)};
}

glm::vec3 EnvmapLight::radiance(glm::vec3 d) const {
  const glm::vec2 uv = direction_to_uv(d);
  const glm::u32vec2 cell = cell_of(uv);
  float gx = uv.x * float(width_) - 0.5f;
  if (gx < 0) gx += float(width_);
  const float fx = std::clamp(gx - float(cell.x), 0.0f, 1.0f);
  const float fy = std::clamp(uv.y * float(height_ - 1) - float(cell.y), 0.0f, 1.0f);
  const uint32_t x1 = (cell.x + 1) % width_;
  const glm::vec3 top = (1.0f - fx) * texel(cell.x, cell.y) + fx * texel(x1, cell.y);
  const glm::vec3 bottom = (1.0f - fx) * texel(cell.x, cell.y + 1) + fx * texel(x1, cell.y + 1);
  return scale_ * ((1.0f - fy) * top + fy * bottom);
}

glm::vec3 EnvmapLight::sample(glm::vec2 u, float* pdf) const {
  *pdf = 0;
  if (distribution_.empty()) return {0.0f, 0.0f, 1.0f};
  float pmf = 0;
  glm::vec2 inside;
  const glm::u32vec2 cell = distribution_.sample(u, &pmf, &inside);
  // Uniform in solid angle inside the cell: phi linear, cos(theta) linear.
  const double phi = 2.0 * kPiD * (double(cell.x) + double(inside.x) + 0.5) / double(width_);
  const double cos_theta =
      cos_theta_[cell.y] + double(inside.y) * (cos_theta_[cell.y + 1] - cos_theta_[cell.y]);
  const double sin_theta = std::sqrt(std::max(0.0, 1.0 - cos_theta * cos_theta));
  const glm::vec3 local(float(std::sin(phi) * sin_theta), float(cos_theta),
                        float(-std::cos(phi) * sin_theta));
  *pdf = float(double(pmf) / cell_omega_[cell.y]);
  return glm::normalize(to_world_ * local);
}

float EnvmapLight::pdf(glm::vec3 d) const {
  if (distribution_.empty()) return 0.0f;
  const glm::u32vec2 cell = cell_of(direction_to_uv(d));
  return float(double(distribution_.pmf(cell.x, cell.y)) / cell_omega_[cell.y]);
}

double EnvmapLight::power(double scene_radius) const {
  return kPiD * scene_radius * scene_radius * distribution_.total();
}

}  // namespace tessera
