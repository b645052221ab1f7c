// What the `tessera` subcommands share: the connection, the job-id argument and --json flag,
// downloading an image, following a job, and turning any exception into a one-line failure.
#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>

#include "commands.h"
#include "job_client.h"
#include "scene/scene_error.h"
#include "wire/scene_bundle.h"

namespace tessera::client {

/// The `--json` flag of a subcommand (sets g.json).
void add_json_flag(CLI::App* command, GlobalOptions& g);
/// The required JOB argument. Its text is checked before CLI11 converts it, so "status abc"
/// says what a job id is rather than "Could not convert: job = abc"; 0 and negative ids are
/// refused after parsing (exit 1).
void add_job_argument(CLI::App* command, uint64_t& job_id);

JobClient connect(const GlobalOptions& g);

/// Prints "tessera: LINE" on stderr and returns 1.
int fail(const std::string& line);

/// .exr or .png from the output's name, after checking that the output can be written
/// (cli::check_output_path); throws std::runtime_error naming what is wrong otherwise.
v1::ImageFormat format_of(const std::string& output);

/// Downloads the job's image to `output`; returns what it wrote.
/// --denoise and --guides of `tessera submit` (--guides needs --denoise).
void add_denoise_flags(CLI::App* cmd, bool& denoise, bool& guides);

v1::GetImageResponse download(JobClient& client, uint64_t job_id, const std::string& output,
                             bool denoised = false);

/// Watches until final: a progress bar on stderr (plain lines when it is no terminal), or with
/// `json_lines` each update as a JSON line on stdout. Returns the last update.
v1::JobInfo follow(JobClient& client, uint64_t job_id, bool json_lines);

/// One line on stderr when the server's last answer said its store is damaged (status, list).
void warn_store_damage(const JobClient& client);

/// 0 when done; else prints why and returns 1.
int final_status(const v1::JobInfo& job);

/// One line on what a finished job reached: the answer to "what did my stopping rule give me".
std::string finished_line(const v1::JobInfo& job);

/// Runs a subcommand's body; any exception becomes "tessera: WHAT" on stderr and exit code 1.
template <typename F>
int guarded(F&& body) {
  try {
    return body();
  } catch (const SceneError& e) {
    return fail(e.what());
  } catch (const wire::BundleError& e) {
    return fail(e.what());
  } catch (const ClientError& e) {
    return fail(e.what());
  } catch (const std::invalid_argument& e) {
    return fail(e.what());
  } catch (const std::exception& e) {
    return fail(e.what());
  }
}

}  // namespace tessera::client
