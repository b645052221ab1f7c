// `tessera submit SCENE`: checks the scene and its files here (a bad scene fails without the
// server), sends its bundle as a job, and with --wait or -o follows it to the end (docs/farm.md).
#include <CLI/CLI.hpp>
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>
#include <vector>

#include "cli/define_option.h"
#include "command_support.h"
#include "job/job_flags.h"
#include "job/job_options.h"
#include "json_view.h"
#include "wire/job_options_wire.h"

namespace tessera::client {
namespace {

struct SubmitOptions {
  std::string scene;
  std::string root;  ///< --root: the bundle root ("" = the scene's own, docs/mitsuba.md)
  std::vector<std::string> defines;  ///< -D name=value: Mitsuba parameters (docs/mitsuba.md)
  JobOverrides overrides;
  int priority = 0;
  bool any_build = false;  ///< --any-build: not pinned to one renderer build
  double verify = 0.01;    ///< --verify: spot checks' fraction of units (docs/reliability.md)
  bool denoise = false;    ///< --denoise: the server writes a denoised image too
  bool guides = false;     ///< --guides: the raw EXR keeps the denoiser's guides
  bool wait = false;
  std::string output;  ///< implies wait
};

/// The request for `s`, after checking the scene and the options against it locally.
v1::SubmitJobRequest submit_request(const SubmitOptions& s) {
  Scene scene;
  const wire::BundleContents bundle = wire::bundle_from_disk(
      s.scene, &scene,
      s.root.empty() ? std::nullopt : std::optional<std::filesystem::path>(s.root),
      parse_mitsuba_defines(s.defines));
  resolve_job_options(scene, s.overrides);
  v1::SubmitJobRequest request;
  *request.mutable_bundle() = wire::bundle_to_proto(bundle);
  *request.mutable_options() = wire::overrides_to_proto(s.overrides);
  if (s.any_build) request.mutable_options()->set_any_build(true);
  request.mutable_options()->set_verify_rate(s.verify);
  if (s.denoise) request.mutable_options()->set_denoise(true);
  if (s.guides) request.mutable_options()->set_guides(true);
  request.set_priority(s.priority);
  return request;
}

int submit(const GlobalOptions& g, const SubmitOptions& s) {
  return guarded([&] {
    if (!s.output.empty()) format_of(s.output);  // refuse an unwritable output before submitting
    const v1::SubmitJobRequest request = submit_request(s);
    JobClient client = connect(g);
    v1::JobInfo job = client.submit(request);
    const bool wait = s.wait || !s.output.empty();
    if (!wait) {
      if (g.json) {
        std::cout << to_json(job).dump() << std::endl;
      } else {
        std::cout << "job " << job.id() << " queued: " << job.options().width() << "x"
                  << job.options().height() << ", " << rule_text(job.options()) << ", "
                  << job.counters().units_total() << " units\n";
      }
      return 0;
    }
    if (!g.json) std::cerr << "job " << job.id() << " submitted\n";
    job = follow(client, job.id(), false);
    if (const int rc = final_status(job); rc != 0) return rc;
    if (!g.json) std::cerr << finished_line(job) << "\n";
    if (!s.output.empty()) {
      download(client, job.id(), s.output);
      if (!g.json) std::cerr << "wrote " << s.output << "\n";
    }
    if (g.json) std::cout << to_json(job).dump() << std::endl;
    return 0;
  });
}

}  // namespace

Command add_submit_command(CLI::App& app, GlobalOptions& g) {
  const auto s = std::make_shared<SubmitOptions>();
  CLI::App* cmd = app.add_subcommand("submit", "Submit a scene as a job");
  cmd->add_option("scene", s->scene, "Scene file: Tessera JSON (.json) or Mitsuba 3 XML (.xml)")
      ->required();
  cmd->add_option("--root", s->root,
                  "Bundle root: the folder every file the scene names must be in (default: the "
                  "common folder of them all)");
  cli::add_define_option(cmd, s->defines);
  add_job_override_flags(cmd, s->overrides);
  cmd->add_option("--priority", s->priority, "Higher runs first (default 0)");
  cmd->add_flag("--any-build", s->any_build,
                "Lease the job to workers of every renderer build (default: only to the build "
                "of the worker its first unit goes to; the image is then one build's bits)");
  cmd->add_option("--verify", s->verify,
                  "Spot checks: this fraction of units, and each worker's first, is rendered "
                  "again by another worker and compared bit for bit (0: none)")
      ->check(CLI::Range(0.0, 1.0))
      ->capture_default_str();
  add_denoise_flags(cmd, s->denoise, s->guides);
  cmd->add_flag("--wait", s->wait, "Follow the job until it ends (progress on stderr)");
  cmd->add_option("-o,--output", s->output,
                  "Write the final image here (.exr or .png); implies --wait");
  add_json_flag(cmd, g);
  return {cmd, [&g, s] { return submit(g, *s); }};
}

}  // namespace tessera::client
