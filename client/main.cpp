// tessera: the render farm's command-line client (docs/farm.md).
#include <CLI/CLI.hpp>
#include <cstdint>
#include <iostream>
#include <optional>

#include "build_info.h"
#include "cli/host_port.h"
#include "cli/usage_exit.h"
#include "commands.h"
#include "job/job_flags.h"
#include "wire/client_tls_flags.h"

namespace {

void json_flag(CLI::App* app, bool& json) {
  app->add_flag("--json", json, "Machine-readable JSON on stdout");
}

}  // namespace

int main(int argc, char** argv) {
  namespace tc = tessera::client;
  CLI::App app{"tessera: submit scenes to a Tessera render farm and follow them"};
  app.set_version_flag("--version", "tessera " + tessera::build_version(),
                       "Print the version, commit and compiler, and exit");
  app.require_subcommand(1);
  app.fallthrough();  // global options may follow the subcommand

  tc::GlobalOptions g;
  app.add_option("--server", g.server, "Server address HOST:PORT")
      ->envname("TESSERA_SERVER")
      ->check(tessera::cli::host_port_check())
      ->capture_default_str();
  tessera::wire::add_client_auth_flags(
      app, g.token, g.token_file, g.tls, "Access token (sent as 'authorization: Bearer TOKEN')",
      "Client certificate (PEM) for a server that requires mutual TLS");
  app.add_option("--timeout", g.timeout_s, "Deadline of each call in seconds")
      ->envname("TESSERA_TIMEOUT")
      ->check(CLI::Range(0.1, 86400.0))
      ->capture_default_str();

  tc::SubmitOptions submit;
  CLI::App* submit_cmd = app.add_subcommand("submit", "Submit a scene as a job");
  submit_cmd->add_option("scene", submit.scene, "Scene file: Tessera JSON (.json) or Mitsuba 3 XML (.xml)")
      ->required();
  submit_cmd->add_option("--root", submit.root, "Bundle root: the folder every file the scene names must be in (default: the common folder of them all)");
  submit_cmd->add_option("-D", submit.defines,
                         "name=value: the Mitsuba scene's parameter $name, overriding its "
                         "<default> (repeatable)");
  tessera::add_job_override_flags(submit_cmd, submit.overrides);
  submit_cmd->add_option("--priority", submit.priority, "Higher runs first (default 0)");
  submit_cmd->add_flag("--wait", submit.wait, "Follow the job until it ends (progress on stderr)");
  submit_cmd->add_option("-o,--output", submit.output,
                         "Write the final image here (.exr or .png); implies --wait");
  json_flag(submit_cmd, g.json);

  uint64_t job_id = 0;
  std::string output;
  // Checked before CLI11 converts it, so "status abc" says what a job id is rather than
  // "Could not convert: job = abc"; 0 and negative ids are refused after parsing (exit 1).
  const CLI::Validator job_id_text(
      [](std::string& text) -> std::string {
        if (!text.empty() && text.find_first_not_of("-0123456789") == std::string::npos &&
            text.find('-', 1) == std::string::npos) {
          return {};
        }
        return "must be a job id, a whole number (got \"" + text + "\")";
      },
      "JOB");
  CLI::App* status_cmd = app.add_subcommand("status", "Show a job");
  status_cmd->add_option("job", job_id, "Job id")->required()->check(job_id_text);
  json_flag(status_cmd, g.json);
  CLI::App* watch_cmd = app.add_subcommand("watch", "Follow a job with a progress bar until it ends");
  watch_cmd->add_option("job", job_id, "Job id")->required()->check(job_id_text);
  json_flag(watch_cmd, g.json);
  CLI::App* get_cmd = app.add_subcommand("get", "Download a job's image (the current preview while it renders)");
  get_cmd->add_option("job", job_id, "Job id")->required()->check(job_id_text);
  get_cmd->add_option("-o,--output", output, "Output file (.exr or .png)")->required();
  json_flag(get_cmd, g.json);
  CLI::App* cancel_cmd = app.add_subcommand("cancel", "Cancel a job");
  cancel_cmd->add_option("job", job_id, "Job id")->required()->check(job_id_text);
  json_flag(cancel_cmd, g.json);
  CLI::App* delete_cmd =
      app.add_subcommand("delete", "Delete a finished or cancelled job and its outputs");
  delete_cmd->add_option("job", job_id, "Job id")->required()->check(job_id_text);
  json_flag(delete_cmd, g.json);
  CLI::App* list_cmd = app.add_subcommand("list", "List jobs, newest first");
  json_flag(list_cmd, g.json);
  CLI::App* workers_cmd = app.add_subcommand("workers", "List workers");
  json_flag(workers_cmd, g.json);

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return tessera::cli::exit_for_parse_error(app, e, "tessera");
  }
  try {
    g.token = tessera::wire::resolve_token(g.token, g.token_file, "--token");
  } catch (const std::exception& e) {
    std::cerr << "tessera: " << e.what() << "\n";
    return tessera::cli::kExitFailure;
  }

  if (submit_cmd->parsed()) return tc::submit(g, submit);
  if (status_cmd->parsed()) return tc::status(g, job_id);
  if (watch_cmd->parsed()) return tc::watch(g, job_id);
  if (get_cmd->parsed()) return tc::get(g, job_id, output);
  if (cancel_cmd->parsed()) return tc::cancel(g, job_id);
  if (delete_cmd->parsed()) return tc::delete_job(g, job_id);
  if (list_cmd->parsed()) return tc::list(g);
  if (workers_cmd->parsed()) return tc::workers(g);
  return tessera::cli::kExitUsage;
}
