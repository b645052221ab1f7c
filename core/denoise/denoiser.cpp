#include "denoise/denoiser.h"

#include <memory>
#include <stdexcept>
#include <utility>

namespace tessera {
namespace {

void check_guide_size(const RgbImage& color, const RgbImage& guide, const char* name) {
  if (guide.width != color.width || guide.height != color.height ||
      guide.rgb.size() != color.rgb.size()) {
    throw std::runtime_error(std::string("denoise: the ") + name + " guide is " +
                             std::to_string(guide.width) + "x" + std::to_string(guide.height) +
                             ", the image " + std::to_string(color.width) + "x" +
                             std::to_string(color.height));
  }
}

/// OIDN takes images through non-const pointers; it only reads its inputs.
void* oidn_input(const RgbImage& image) { return const_cast<float*>(image.rgb.data()); }

}  // namespace

Denoiser::Denoiser(std::shared_ptr<const OidnLibrary> library, int threads)
    : library_(std::move(library)) {
  const oidn::Api& api = library_->api();
  device_ = api.new_device(oidn::kDeviceTypeCpu);
  if (device_ == nullptr) {
    throw std::runtime_error("Open Image Denoise: no CPU device (" + library_->path() + ")");
  }
  if (threads > 0) api.set_device_int(device_, "numThreads", threads);
  api.commit_device(device_);
  try {
    check("creating its CPU device");
  } catch (...) {
    api.release_device(device_);
    throw;
  }
}

Denoiser::~Denoiser() { library_->api().release_device(device_); }

void Denoiser::check(const char* what) const {
  const char* message = nullptr;
  if (library_->api().get_device_error(device_, &message) != oidn::kErrorNone) {
    throw std::runtime_error(std::string("Open Image Denoise, ") + what + ": " +
                             (message != nullptr ? message : "unknown error"));
  }
}

std::string Denoiser::version() const {
  const int v = library_->api().get_device_int(device_, "version");  // major*10000+minor*100+patch
  return std::to_string(v / 10000) + "." + std::to_string(v / 100 % 100) + "." +
         std::to_string(v % 100);
}

std::string Denoiser::description(bool guided) const {
  return "Intel Open Image Denoise " + version() + " (RT filter, hdr, " +
         (guided ? "albedo and normal guides)" : "colour only)");
}

RgbImage Denoiser::denoise(const RgbImage& color, const DenoiseGuides& guides,
                           bool clean_guides) const {
  const bool guided = guides.albedo != nullptr && guides.normal != nullptr;
  if (guided) {
    check_guide_size(color, *guides.albedo, "albedo");
    check_guide_size(color, *guides.normal, "normal");
  }
  RgbImage out{color.width, color.height, std::vector<float>(color.rgb.size())};
  if (color.rgb.empty()) return out;
  const oidn::Api& api = library_->api();
  // Released on every way out, an error's included.
  const std::unique_ptr<oidn::FilterImpl, oidn::ReleaseFilterFn> filter(
      api.new_filter(device_, "RT"), api.release_filter);
  check("creating its RT filter");
  const auto set = [&](const char* name, void* pixels) {
    api.set_shared_filter_image(filter.get(), name, pixels, oidn::kFormatFloat3,
                                size_t(color.width), size_t(color.height), 0, 0, 0);
  };
  set("color", oidn_input(color));
  if (guided) {
    set("albedo", oidn_input(*guides.albedo));
    set("normal", oidn_input(*guides.normal));
    api.set_filter_bool(filter.get(), "cleanAux", clean_guides);
  }
  set("output", out.rgb.data());
  api.set_filter_bool(filter.get(), "hdr", true);
  api.commit_filter(filter.get());
  check("setting up its RT filter");
  api.execute_filter(filter.get());
  check("denoising");
  return out;
}

}  // namespace tessera
