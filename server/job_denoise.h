// The server's denoiser: Intel Open Image Denoise (core/denoise/), loaded when the server
// starts from --oidn-library, TESSERA_OIDN_LIBRARY, the path found at build time or the
// system's (the worker's search order). A job submitted with denoise is refused at submit when
// it cannot be loaded. Denoising takes the whole image (colour, guides, output) at once, so
// it runs one job at a time, its working set reserved in the server's memory budget
// (SubmitBudget, --submit-memory-mb) while it runs.
#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "accum/guide_tile.h"
#include "denoise/denoiser.h"
#include "submit_budget.h"

namespace tessera::server {

class JobDenoise {
 public:
  /// The library is loaded from the first of `candidates` that loads (oidn_library_candidates)
  /// when a job first asks for denoise, so that a server that never denoises never maps it;
  /// when none loads, every such job is refused with DenoiserUnavailable's line. `budget` (may
  /// be null: nothing reserved) must outlive this.
  JobDenoise(std::vector<std::string> candidates, SubmitBudget* budget,
             std::chrono::milliseconds budget_wait = std::chrono::minutes(1));
  ~JobDenoise();

  /// "" when the denoiser can run (loading the library the first time); else one line saying
  /// what was tried and how to install it.
  std::string unavailable() const;

  /// What denoising a width x height image may take, as reserved in the budget: 768 bytes a
  /// pixel and 64 MiB. The server's peak grew by 213 MB, 793 MB and 3,100 MB denoising 512,
  /// 1024 and 2048 px squares (VmHWM with and without --denoise --guides, Cornell box at 1 spp):
  /// about 750 bytes a pixel (OIDN's buffers the most of it; the colour, guides and output in
  /// float 48, the guides' sums while they merge 56) and 25 MB.
  static uint64_t working_set_bytes(int width, int height);

  /// Why a job of width x height asking for denoise is refused at submit ("" when it is not):
  /// the denoiser unavailable (FAILED_PRECONDITION), or a working set larger than the whole
  /// memory budget (INVALID_ARGUMENT). Throws FarmError.
  void check_submit(int width, int height) const;

  /// What a denoise takes: the colour and its guides (both images set, else colour alone).
  struct Input {
    RgbImage color;
    GuideImages guides;
  };
  struct Denoised {
    RgbImage image;
    std::string denoiser;  ///< Denoiser::description, for the file's provenance
    double seconds = 0;    ///< the filter alone
  };
  /// Waits for the denoises before it (one at a time), reserves the working set of a width x
  /// height image in the budget (`what` names it there), and only then calls `input()` for the
  /// image, so that assembling it is counted too; returns it denoised. Throws
  /// DenoiserUnavailable, FarmError from the budget (resource_exhausted when it stays taken),
  /// std::runtime_error with OIDN's message, and what `input` throws.
  Denoised denoise(const std::string& what, int width, int height,
                   const std::function<Input()>& input);

 private:
  /// The library, loaded by the first call that needs it; its error otherwise.
  std::shared_ptr<const OidnLibrary> library() const;

  std::vector<std::string> candidates_;
  mutable std::mutex load_mu_;
  mutable bool loaded_ = false;                         ///< guarded by load_mu_
  mutable std::shared_ptr<const OidnLibrary> library_;  ///< guarded by load_mu_
  mutable std::string unavailable_;                     ///< guarded by load_mu_
  SubmitBudget* budget_;
  std::chrono::milliseconds budget_wait_;
  std::mutex mu_;                        ///< one denoise at a time
  std::unique_ptr<Denoiser> denoiser_;   ///< made by the first denoise; guarded by mu_
};

}  // namespace tessera::server
