// tessera-worker: the farm's worker (`--server HOST:PORT`), the local renderer (`render`) and the
// scene converter (`convert`).
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <optional>
#include <new>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <tbb/global_control.h>
#include <unistd.h>

#include "accum/film.h"
#include "cli/define_option.h"
#include "cli/host_port.h"
#include "cli/output_path.h"
#include "cli/usage_exit.h"
#include "converge_command.h"
#include "denoise/denoised_outputs.h"
#include "image/image_output.h"
#include "job/job_flags.h"
#include "job/provenance.h"
#include "job/tile_summary.h"
#include "local_render.h"
#include "progress_bar.h"
#include "render/renderer_build.h"
#include "scene/scene_error.h"
#include "scene/loader/scene_loader.h"
#include "scene/native/scene_writer.h"
#include "signal_cancellation.h"
#ifdef TESSERA_HAVE_FARM
#include "farm/farm_worker.h"
#include "wire/client_tls_flags.h"
#endif

namespace {

struct RenderArgs {
  std::string scene;
  std::string root;  ///< --root: the bundle root ("" = the scene's own, docs/mitsuba.md)
  std::vector<std::string> defines;  ///< -D name=value: Mitsuba parameters
  std::vector<std::string> outputs;
  tessera::JobOverrides overrides;
  int threads = 0;
  std::string integrator = "wavefront";  ///< --integrator (renderer.h's IntegratorKind)
  std::string kernel_isa = "auto";       ///< --kernel-isa (render/wavefront/kernel_isa.h)
  bool half = false;
  bool quiet = false;
  bool denoise = false;      ///< --denoise: NAME.denoised.EXT beside each output
  bool guides = false;       ///< --guides: the raw EXR also holds the denoiser's guides
  std::string oidn_library;  ///< --oidn-library ("" = TESSERA_OIDN_LIBRARY, then the search)
};

std::optional<std::filesystem::path> bundle_root(const std::string& root) {
  if (root.empty()) return std::nullopt;
  return std::filesystem::path(root);
}

/// The denoiser of a render that asks for one (null otherwise), made before the scene is read:
/// a render whose denoising cannot run is refused up front (DenoiserUnavailable, exit 1).
std::unique_ptr<tessera::Denoiser> make_denoiser(const RenderArgs& args) {
  if (!args.denoise) return nullptr;
  for (const std::string& out : tessera::denoised_output_paths(args.outputs)) {
    tessera::cli::check_output_path(out, {".exr", ".png"});
  }
  return std::make_unique<tessera::Denoiser>(tessera::OidnLibrary::load_for_flag(args.oidn_library),
                                             args.threads);
}

/// The raw image's provenance (EXR header attributes, PNG text chunks).
std::map<std::string, std::string> render_metadata(const RenderArgs& args,
                                                   const tessera::JobOptions& options,
                                                   const tessera::LocalRenderResult& result,
                                                   const tessera::TileSummary& summary,
                                                   double rel_error, uint64_t nan, uint64_t inf) {
  tessera::Provenance p;
  p.scene_file = std::filesystem::path(args.scene).filename().string();
  p.renderer = tessera::renderer_build();  // as a farm worker registers it
  p.isa = result.isa;
  p.options = &options;
  p.stop_reason = result.reason;
  p.spp = summary.spp_min;
  p.reached = summary;
  p.nan_dropped = nan;
  p.inf_dropped = inf;
  p.wall_time_s = result.seconds;
  p.kernel_isa = result.kernel_isa;
  p.estimated_relative_error = rel_error;
  return tessera::provenance_metadata(p);
}

/// Writes the raw `image` to every output (under --guides with the guides as EXR channels) and,
/// given a denoiser, the denoised image beside each, guided by the render's guides. Returns the
/// seconds the denoising took (0 without a denoiser).
double write_outputs(const RenderArgs& args, const tessera::JobOptions& options,
                     const tessera::RgbImage& image, const tessera::LocalRenderResult& result,
                     const tessera::ImageWriteOptions& write, const tessera::Denoiser* denoiser) {
  const tessera::GuideImages guides =
      result.guides.empty() ? tessera::GuideImages{}
                            : tessera::resolve_guides(options.width, options.height, result.guides);
  tessera::ImageWriteOptions raw_write = write;
  if (args.guides) {
    for (tessera::ExtraChannel& c : tessera::guide_channels(guides)) {
      raw_write.extra_channels.push_back(std::move(c));
    }
  }
  for (const std::string& out : args.outputs) tessera::write_image(image, out, raw_write);
  if (denoiser == nullptr) return 0;
  return tessera::write_denoised_outputs(*denoiser, image, {&guides.albedo, &guides.normal},
                                         args.outputs, write);
}

int run_render(const RenderArgs& args) {
  // First, before any thread starts: Ctrl-C and SIGTERM then cancel the render (the threads
  // inherit the blocked signals) rather than kill the process wherever it is.
  tessera::RenderCancellation cancel;
  const tessera::SignalCancellation signals(cancel);
  // Every output is checked before the scene is read: a render never runs to be thrown away.
  for (const std::string& out : args.outputs) tessera::cli::check_output_path(out, {".exr", ".png"});
  const std::unique_ptr<tessera::Denoiser> denoiser = make_denoiser(args);
  const tessera::Scene scene = tessera::load_scene_file(args.scene, bundle_root(args.root),
                                                        tessera::parse_mitsuba_defines(args.defines));
  const tessera::JobOptions options = tessera::resolve_job_options(scene, args.overrides);

  std::optional<tbb::global_control> thread_limit;
  if (args.threads > 0) {
    thread_limit.emplace(tbb::global_control::max_allowed_parallelism, size_t(args.threads));
  }
  const uint64_t total = uint64_t(options.width) * uint64_t(options.height) * options.spp;
  tessera::ProgressBar bar(args.quiet ? nullptr : stderr, total,
                           options.rule == tessera::StopRule::time ? options.time_budget_s : 0);
  tessera::LocalRenderResult result;
  try {
    result = tessera::render_job(scene, options,
                                 [&](const tessera::LocalRenderProgress& p) {
                                   bar.update(p.samples_done, p.samples_traced);
                                 },
                                 tessera::integrator_kind_from_name(args.integrator),
                                 tessera::kernel_isa_from_name(args.kernel_isa), &cancel, {},
                                 args.denoise || args.guides);
  } catch (const tessera::RenderCancelled&) {
    const int signal_number = signals.signal_number();
    std::fprintf(stderr, "\ntessera-worker: render cancelled by %s; no image written\n",
                 signal_number == SIGTERM ? "SIGTERM" : "SIGINT");
    return 128 + signal_number;
  }
  // The samples the image holds, which a job that stopped early (time, noise) has fewer of than
  // its total; the rate counts what was traced, a batch the budget cut included.
  uint64_t samples_taken = 0;
  const std::vector<tessera::TileRect> rects = options.plan().tiles();
  for (size_t t = 0; t < rects.size(); ++t) {
    samples_taken += uint64_t(rects[t].pixel_count()) * result.tile_spp[t];
  }
  bar.finish(samples_taken, result.stats.samples);

  const tessera::RgbImage image = tessera::resolve_image(options.width, options.height, result.tiles);
  uint64_t nan = 0, inf = 0;
  for (const tessera::Accumulation& t : result.tiles) {
    nan += t.nan_dropped;
    inf += t.inf_dropped;
  }
  const double rel_error = tessera::estimate_relative_error(result.tiles);
  const tessera::TileSummary summary = tessera::summarize_tiles(result.tile_spp, result.tile_error);

  tessera::ImageWriteOptions write;
  write.half = args.half;
  write.metadata = render_metadata(args, options, result, summary, rel_error, nan, inf);
  if (options.rule != tessera::StopRule::spp) {
    write.extra_channels.push_back({"spp", tessera::spp_channel(options.width, options.height,
                                                               options.plan().tiles(),
                                                               result.tile_spp)});
  }
  const double denoise_s = write_outputs(args, options, image, result, write, denoiser.get());

  for (const tessera::Accumulation& t : result.tiles) {
    for (const tessera::DroppedSample& d : t.dropped_examples) {
      std::fprintf(stderr, "dropped a NaN/Inf sample: pixel (%d, %d), sample index %u\n", d.x, d.y,
                   d.sample_index);
    }
  }
  const double seconds = result.seconds;
  std::fprintf(stderr,
               "rendered %dx%d in %.2f s (%s rule, stopped: %s): spp min %u mean %.1f max %u, "
               "%llu samples, %s samples/s, %s rays/s (%llu rays, %llu shadow rays), estimated "
               "relative error %s (tiles: max %s, mean %s), NaN/Inf dropped %llu, isa %s, kernel %s\n",
               options.width, options.height, seconds,
               std::string(tessera::to_string(options.rule)).c_str(),
               std::string(tessera::to_string(result.reason)).c_str(), summary.spp_min,
               summary.spp_mean, summary.spp_max, static_cast<unsigned long long>(samples_taken),
               tessera::si_count(double(result.stats.samples) / seconds).c_str(),
               tessera::si_count(double(result.stats.rays + result.stats.shadow_rays) / seconds).c_str(),
               static_cast<unsigned long long>(result.stats.rays),
               static_cast<unsigned long long>(result.stats.shadow_rays),
               tessera::error_text(rel_error, summary.spp_max).c_str(),
               tessera::error_text(summary.error_max, summary.spp_max).c_str(),
               tessera::error_text(summary.error_mean, summary.spp_max).c_str(),
               static_cast<unsigned long long>(nan + inf),
               result.isa.c_str(), result.kernel_isa.c_str());
  if (denoiser) {
    std::fprintf(stderr, "denoised in %.2f s with %s\n", denoise_s,
                 denoiser->description(true).c_str());
  }
  return 0;
}

struct ConvertArgs {
  std::string scene;
  std::string root;  ///< --root: the bundle root ("" = the scene's own)
  std::vector<std::string> defines;  ///< -D name=value: Mitsuba parameters
  std::string output;
};

/// Writes `text` to `path` through a temporary file in the same folder, so that a reader never
/// sees half a file.
void write_file_atomically(const std::filesystem::path& path, const std::string& text) {
  std::filesystem::path temporary = path;
  temporary += ".tmp" + std::to_string(::getpid());
  {
    std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
    out.write(text.data(), std::streamsize(text.size()));
    out.close();
    if (!out) {
      std::error_code ignored;
      std::filesystem::remove(temporary, ignored);
      throw std::runtime_error(path.string() + ": cannot be written");
    }
  }
  std::error_code error;
  std::filesystem::rename(temporary, path, error);
  if (error) {
    std::filesystem::remove(temporary, error);
    throw std::runtime_error(path.string() + ": cannot be written");
  }
}

/// `tessera-worker convert IN -o OUT.json`: any scene Tessera reads (a Mitsuba .xml scene, or
/// native JSON) as native JSON that reads back to the same Scene (scene_writer.h).
int run_convert(const ConvertArgs& args) {
  tessera::cli::check_output_path(args.output, {".json"});
  const tessera::Scene scene = tessera::load_scene_file(args.scene, bundle_root(args.root),
                                                        tessera::parse_mitsuba_defines(args.defines));
  const std::string source = std::filesystem::path(args.scene).filename().string();
  write_file_atomically(
      args.output, tessera::write_scene_json(
                       scene, "Converted by tessera-worker " TESSERA_VERSION " from " + source));
  size_t triangles = 0;
  for (const tessera::Shape& shape : scene.shapes) triangles += shape.indices.size();
  std::fprintf(stderr, "converted %s: %zu shapes (%zu triangles), %zu materials -> %s\n",
               source.c_str(), scene.shapes.size(), triangles, scene.materials.size(),
               args.output.c_str());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"tessera-worker: Tessera's render worker and local renderer"};
  app.set_version_flag("--version", "tessera-worker " + tessera::renderer_build(),
                       "Print the renderer's build (version, commit, compiler, Embree, C library) and exit");
  app.require_subcommand(0, 1);

  RenderArgs render;
  CLI::App* render_cmd = app.add_subcommand(
      "render", "Render a scene locally through the farm's tile/batch/merge path");
  render_cmd->add_option("scene", render.scene, "Scene file: Tessera JSON (.json) or Mitsuba 3 XML (.xml)")->required();
  render_cmd->add_option("--root", render.root, "Bundle root: the folder every file the scene names must be in (default: the common folder of them all)");
  tessera::cli::add_define_option(render_cmd, render.defines);
  render_cmd->add_option("-o,--output", render.outputs, "Output image(s): .exr (linear float) or .png (sRGB)")
      ->required();
  tessera::add_job_override_flags(render_cmd, render.overrides);
  render_cmd->add_option("--threads", render.threads, "Threads, 0 to 1024 (default 0: all cores)")
      ->check(CLI::Range(0, 1024));
  render_cmd->add_option("--integrator", render.integrator,
                         "scalar (one path at a time) or wavefront (a bounce of many paths at a time, rays in "
                         "Embree packets); the same bits either way (default wavefront)")
      ->check(CLI::IsMember({"scalar", "wavefront"}));
  render_cmd->add_option("--kernel-isa", render.kernel_isa,
                         "Instruction set of the wavefront loop: auto (TESSERA_KERNEL_ISA, else the best for "
                         "this CPU), baseline, avx2 or avx512; the same bits on each. --isa pins Embree's")
      ->check(CLI::IsMember({"auto", "baseline", "avx2", "avx512"}));
  render_cmd->add_flag("--half", render.half, "Write EXR as half floats (clamped to half's range)");
  render_cmd->add_flag("-q,--quiet", render.quiet, "No progress bar");
  render_cmd->add_flag("--denoise", render.denoise,
                       "Also write NAME.denoised.exr (and .png for a PNG output) beside each output, "
                       "denoised by Intel Open Image Denoise (scripts/install-deps.sh installs it); "
                       "the raw image is unchanged");
  render_cmd->add_flag("--guides", render.guides,
                       "Also render the denoiser's guides (albedo and normal at the first non-specular "
                       "surface) into the EXR outputs, as channels albedo.R/G/B and N.X/Y/Z");
  render_cmd->add_option("--oidn-library", render.oidn_library,
                         "libOpenImageDenoise.so.2 to load for --denoise (default: "
                         "TESSERA_OIDN_LIBRARY, else the one found at build time, else the system's)");

  ConvertArgs convert;
  CLI::App* convert_cmd = app.add_subcommand(
      "convert", "Convert a scene (Mitsuba 3 .xml, or .json) to Tessera's native JSON");
  convert_cmd->add_option("scene", convert.scene, "Scene file (.xml or .json)")->required();
  convert_cmd->add_option("--root", convert.root, "Bundle root: the folder every file the scene names must be in (default: the common folder of them all)");
  tessera::cli::add_define_option(convert_cmd, convert.defines);
  convert_cmd->add_option("-o,--output", convert.output, "Output scene (.json)")->required();

  tessera::ConvergeCommand converge;
  converge.add_to(app);

#ifdef TESSERA_HAVE_FARM
  tessera::FarmWorkerConfig farm;
  farm.server = "127.0.0.1:50051";
  app.add_option("--server", farm.server, "Server address HOST:PORT")
      ->envname("TESSERA_SERVER")
      ->check(tessera::cli::host_port_check());
  app.add_option("--threads", farm.threads, "Render threads, 0 to 1024 (default 0: all cores)")
      ->check(CLI::Range(0, 1024));
  app.add_option("--cache", farm.cache_dir, "Folder caching scene bundles")->envname("TESSERA_CACHE");
  std::string token_file;
  tessera::wire::add_client_auth_flags(app, farm.token, token_file, farm.tls,
                                       "Access token (the server's worker token)",
                                       "Worker certificate (PEM) for mutual TLS");
  app.add_option("--name", farm.name, "Worker name shown by the server (default: host name and pid)");
#endif

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return tessera::cli::exit_for_parse_error(app, e, "tessera-worker");
  }
  try {
    if (render_cmd->parsed()) return run_render(render);
    if (convert_cmd->parsed()) return run_convert(convert);
    if (converge.app->parsed()) return converge.run();
#ifdef TESSERA_HAVE_FARM
    farm.token = tessera::wire::resolve_token(farm.token, token_file, "--token");
    return tessera::run_farm_worker(farm);
#else
    std::fprintf(stderr, "tessera-worker: this build has no farm mode; use `tessera-worker render`\n");
    return tessera::cli::kExitUsage;
#endif
  } catch (const tessera::SceneError& e) {
    std::fprintf(stderr, "tessera-worker: %s\n", e.what());
  } catch (const std::bad_alloc&) {
    // Most often the image: a local render holds every tile's sums (about 50 bytes a pixel).
    std::fprintf(stderr,
                 "tessera-worker: out of memory (a local render holds about 50 bytes per pixel "
                 "of the image besides the scene: render a smaller --width/--height, or give "
                 "the process more memory)\n");
  } catch (const std::exception& e) {
    std::fprintf(stderr, "tessera-worker: %s\n", e.what());
  }
  return tessera::cli::kExitFailure;
}
