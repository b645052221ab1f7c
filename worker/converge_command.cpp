#include "converge_command.h"

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <optional>
#include <stdexcept>

#include <tbb/global_control.h>

#include "converge.h"
#include "job/job_flags.h"
#include "scene/loader/scene_loader.h"

namespace tessera {
namespace {

template <typename T>
CLI::Option* optional_option(CLI::App* app, const std::string& name, std::optional<T>& target,
                             const std::string& help) {
  return app->add_option_function<T>(name, [&target](const T& v) { target = v; }, help);
}

void write_text(const std::string& path, const std::string& text) {
  const std::filesystem::path temporary = path + ".tmp";
  {
    std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
    out << text;
    out.close();
    if (!out) throw std::runtime_error(path + ": cannot be written");
  }
  std::error_code error;
  std::filesystem::rename(temporary, path, error);
  if (error) {
    std::filesystem::remove(temporary, error);
    throw std::runtime_error(path + ": cannot be written");
  }
}

}  // namespace

void ConvergeCommand::add_to(CLI::App& parent) {
  app = parent.add_subcommand(
      "converge",
      "Render at 1, 2, 4, ... spp and measure RMSE and relative MSE against a reference image "
      "(table and log-log plot versus spp and wall time)");
  app->add_option("scene", scene, "Scene file (.json or .xml)")->required();
  app->add_option("--reference", reference, "Reference image (.exr), the size of the render")->required();
  app->add_option("--csv", csv, "Write the table as CSV");
  app->add_option("--md", markdown, "Write the table as Markdown (it is printed to stdout as well)");
  app->add_option("--plot", plot, "Write the plot (.png)");
  app->add_option("--images", images,
                  "Write each level's image to DIR/raw-SPP.exr (and DIR/denoised-SPP.exr), for "
                  "metrics of one's own");
  app->add_flag("--denoise", denoise,
                "Also denoise each level's image (Intel Open Image Denoise, guided by albedo and "
                "normal as render --denoise) and measure it at its time: the guides' and the "
                "denoising's included");
  app->add_option("--oidn-library", oidn_library,
                  "libOpenImageDenoise.so.2 to load for --denoise (default: TESSERA_OIDN_LIBRARY, "
                  "else the one scripts/install-deps.sh installed, else the system's)");
  app->add_option("--fit-from", fit_from, "Fit the slopes from this spp on (default 4)")
      ->check(CLI::PositiveNumber);
  optional_option(app, "--spp", overrides.spp, "Largest spp (default 1024); levels are powers of two up to it");
  optional_option(app, "--max-depth", overrides.max_depth, "Path segments incl. the camera ray, -1 = unbounded");
  optional_option(app, "--seed", overrides.seed, "Random seed in [0, 2^64-1] (default: the scene's)")
      ->check(seed_check());
  optional_option(app, "--isa", overrides.isa, "Pin Embree's instruction set");
  app->add_option("--threads", threads, "Threads, 0 to 1024 (default 0: all cores)")
      ->check(CLI::Range(0, 1024));
  app->add_flag("-q,--quiet", quiet, "Print only the table");
}

int ConvergeCommand::run() const {
  if (!plot.empty() && std::filesystem::path(plot).extension() != ".png") {
    throw std::invalid_argument("--plot " + plot + ": the plot must be a .png");
  }
  if (!images.empty() && !std::filesystem::is_directory(images)) {
    throw std::invalid_argument("--images " + images + ": not a directory");
  }
  // Made before the scene is read: a run whose denoising cannot run is refused up front.
  const std::unique_ptr<Denoiser> denoiser =
      denoise ? std::make_unique<Denoiser>(OidnLibrary::load_for_flag(oidn_library), threads) : nullptr;
  const Scene s = load_scene_file(scene);
  RgbImage ref;
  try {
    ref = read_image(reference);
  } catch (const std::exception& e) {
    throw std::invalid_argument("--reference: " + std::string(e.what()));
  }
  JobOverrides o = overrides;
  if (!o.spp) o.spp = 1024;
  o.width = ref.width;  // the render is the reference's size; a different aspect is an error
  o.height = ref.height;
  if (std::abs(double(s.film.width) / s.film.height - double(ref.width) / ref.height) > 1e-3) {
    throw std::invalid_argument("--reference " + reference + ": " + std::to_string(ref.width) + "x" +
                                std::to_string(ref.height) + " has another aspect ratio than the scene's " +
                                std::to_string(s.film.width) + "x" + std::to_string(s.film.height));
  }
  JobOptions options = resolve_job_options(s, o);

  std::optional<tbb::global_control> limit;
  if (threads > 0) limit.emplace(tbb::global_control::max_allowed_parallelism, size_t(threads));
  ConvergenceHooks hooks;
  hooks.denoiser = denoiser.get();
  hooks.on_row = [&](const ConvergenceRow& r) {
    if (quiet) return;
    std::fprintf(stderr, "converge: %u spp, %.2f s, RMSE %.5f", r.spp, r.seconds, r.rmse);
    if (r.denoised) std::fprintf(stderr, "; denoised %.2f s, RMSE %.5f", r.denoised->seconds, r.denoised->rmse);
    std::fputc('\n', stderr);
  };
  if (!images.empty()) {
    hooks.on_images = [&](uint32_t spp, const RgbImage& raw, const RgbImage* denoised_image) {
      const std::filesystem::path dir(images);
      const std::string level = std::to_string(spp) + ".exr";
      write_image(raw, (dir / ("raw-" + level)).string());
      if (denoised_image) write_image(*denoised_image, (dir / ("denoised-" + level)).string());
    };
  }
  ConvergenceResult result = measure_convergence(s, options, ref, fit_from, hooks);
  result.scene_name = std::filesystem::path(scene).filename().string();
  const std::string md = convergence_markdown(result);
  std::fputs(md.c_str(), stdout);
  if (!csv.empty()) write_text(csv, convergence_csv(result));
  if (!markdown.empty()) write_text(markdown, md);
  if (!plot.empty()) write_convergence_plot(result, plot);
  return 0;
}

}  // namespace tessera
