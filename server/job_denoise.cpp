#include "job_denoise.h"

#include "farm_error.h"

namespace tessera::server {

JobDenoise::JobDenoise(std::vector<std::string> candidates, SubmitBudget* budget,
                       std::chrono::milliseconds budget_wait)
    : candidates_(std::move(candidates)), budget_(budget), budget_wait_(budget_wait) {}

std::shared_ptr<const OidnLibrary> JobDenoise::library() const {
  std::lock_guard lock(load_mu_);
  if (!loaded_) {
    loaded_ = true;
    try {
      library_ = OidnLibrary::load(candidates_);
    } catch (const DenoiserUnavailable& e) {
      unavailable_ = e.what();
    }
  }
  if (!library_) throw DenoiserUnavailable(unavailable_);
  return library_;
}

std::string JobDenoise::unavailable() const {
  try {
    library();
    return "";
  } catch (const DenoiserUnavailable& e) {
    return e.what();
  }
}

JobDenoise::~JobDenoise() = default;

uint64_t JobDenoise::working_set_bytes(int width, int height) {
  constexpr uint64_t kBytesPerPixel = 768;
  constexpr uint64_t kFixedBytes = uint64_t(64) << 20;
  return uint64_t(width) * uint64_t(height) * kBytesPerPixel + kFixedBytes;
}

void JobDenoise::check_submit(int width, int height) const {
  if (budget_ != nullptr) {
    const uint64_t bytes = working_set_bytes(width, height);
    const uint64_t capacity = budget_->counters().capacity_bytes;
    if (bytes > capacity) {
      throw invalid_argument("denoising a " + std::to_string(width) + "x" +
                             std::to_string(height) + " image takes about " +
                             std::to_string(bytes >> 20) +
                             " MiB, more than the server's memory budget of " +
                             std::to_string(capacity >> 20) +
                             " MiB (server flag --submit-memory-mb)");
    }
  }
  if (const std::string why = unavailable(); !why.empty()) {
    throw FarmError(ErrorCode::failed_precondition, "the server cannot denoise: " + why);
  }
}

JobDenoise::Denoised JobDenoise::denoise(const std::string& what, int width, int height,
                                         const std::function<Input()>& input) {
  const std::shared_ptr<const OidnLibrary> loaded = library();
  std::lock_guard lock(mu_);
  // Released before the lock (declared after it), so the next denoise never overlaps it.
  std::optional<SubmitBudget::Reservation> reserved;
  if (budget_ != nullptr) {
    reserved.emplace(
        budget_->reserve(working_set_bytes(width, height), what, "denoising", budget_wait_));
  }
  if (!denoiser_) denoiser_ = std::make_unique<Denoiser>(loaded);
  const Input in = input();
  const bool guided = !in.guides.albedo.rgb.empty() && !in.guides.normal.rgb.empty();
  const DenoiseGuides with = guided ? DenoiseGuides{&in.guides.albedo, &in.guides.normal}
                                    : DenoiseGuides{};
  const auto start = std::chrono::steady_clock::now();
  Denoised out;
  out.image = denoiser_->denoise(in.color, with);
  out.seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  out.denoiser = denoiser_->description(guided);
  return out;
}

}  // namespace tessera::server
