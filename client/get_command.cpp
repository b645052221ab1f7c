// `tessera get JOB -o FILE`: downloads a job's image, the final one or, while it renders, the
// current preview.
#include <CLI/CLI.hpp>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>

#include "command_support.h"

namespace tessera::client {
namespace {

struct GetOptions {
  uint64_t job_id = 0;
  std::string output;
  bool denoised = false;  ///< --denoised: the denoised image of a --denoise job
};

int get(const GlobalOptions& g, const GetOptions& o) {
  return guarded([&] {
    format_of(o.output);  // before any call
    JobClient client = connect(g);
    const v1::GetImageResponse image = download(client, o.job_id, o.output, o.denoised);
    if (g.json) {
      std::cout << nlohmann::json{{"path", o.output},
                                  {"final", image.final()},
                                  {"spp", image.spp()},
                                  {"width", image.width()},
                                  {"height", image.height()}}
                       .dump()
                << std::endl;
    } else {
      std::cerr << "wrote " << o.output << " ("
                << (image.final() ? "final" : "preview") << (o.denoised ? ", denoised" : "")
                << ", " << image.spp() << " spp)\n";
    }
    return 0;
  });
}

}  // namespace

Command add_get_command(CLI::App& app, GlobalOptions& g) {
  const auto o = std::make_shared<GetOptions>();
  CLI::App* cmd =
      app.add_subcommand("get", "Download a job's image (the current preview while it renders)");
  add_job_argument(cmd, o->job_id);
  cmd->add_option("-o,--output", o->output, "Output file (.exr or .png)")->required();
  cmd->add_flag("--denoised", o->denoised,
                "The denoised image of a job submitted with --denoise (while it renders, the "
                "merged tiles so far denoised now)");
  add_json_flag(cmd, g);
  return {cmd, [&g, o] { return get(g, *o); }};
}

}  // namespace tessera::client
