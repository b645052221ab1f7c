#include "command_support.h"

#include <CLI/CLI.hpp>
#include <cctype>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>

#include "cli/output_path.h"
#include "job/tile_summary.h"
#include "json_view.h"
#include "progress_view.h"
#include "scene/message_text.h"

namespace tessera::client {
namespace {

std::string lower_extension(const std::filesystem::path& p) {
  std::string ext = p.extension().string();
  for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

void write_file(const std::string& path, const std::string& bytes) {
  const std::string temp = path + ".partial";
  {
    std::ofstream out(temp, std::ios::binary | std::ios::trunc);
    out.write(bytes.data(), std::streamsize(bytes.size()));
    out.flush();
    if (!out) throw ClientError(path + ": cannot write");
  }
  std::error_code ec;
  std::filesystem::rename(temp, path, ec);
  if (ec) throw ClientError(path + ": cannot write: " + ec.message());
}

}  // namespace

void add_json_flag(CLI::App* command, GlobalOptions& g) {
  command->add_flag("--json", g.json, "Machine-readable JSON on stdout");
}

void add_job_argument(CLI::App* command, uint64_t& job_id) {
  const CLI::Validator job_id_text(
      [](std::string& text) -> std::string {
        // Digits only: CLI11 would read "-5" into the unsigned id as 2^64 - 5.
        if (!text.empty() && text.find_first_not_of("0123456789") == std::string::npos) return {};
        return "must be a job id, a whole number (got \"" + printable(text) + "\")";
      },
      "JOB");
  command->add_option("job", job_id, "Job id")->required()->check(job_id_text);
}

JobClient connect(const GlobalOptions& g) {
  return JobClient(g.server, g.token, g.tls,
                   std::chrono::milliseconds(int64_t(g.timeout_s * 1000)));
}

int fail(const std::string& line) {
  std::cerr << "tessera: " << line << "\n";
  return 1;
}

v1::ImageFormat format_of(const std::string& output) {
  cli::check_output_path(output, {".exr", ".png"});
  return lower_extension(output) == ".exr" ? v1::IMAGE_FORMAT_EXR : v1::IMAGE_FORMAT_PNG;
}

void add_denoise_flags(CLI::App* cmd, bool& denoise, bool& guides) {
  CLI::Option* with = cmd->add_flag(
      "--denoise", denoise,
      "When done, the server also writes job-N.denoised.exr and .png, denoised by Intel Open "
      "Image Denoise with albedo and normal guides (fetch it with `tessera get N --denoised`); "
      "the raw image is unchanged");
  cmd->add_flag("--guides", guides,
                "With --denoise: the raw EXR also holds the guides as channels albedo.R/G/B, "
                "N.X/Y/Z")
      ->needs(with);
}

v1::GetImageResponse download(JobClient& client, uint64_t job_id, const std::string& output,
                             bool denoised) {
  const v1::ImageFormat format = format_of(output);
  v1::GetImageResponse image = client.image(job_id, format, denoised);
  write_file(output, image.data());
  return image;
}

v1::JobInfo follow(JobClient& client, uint64_t job_id, bool json_lines) {
  ProgressView view(json_lines ? nullptr : stderr);
  const v1::JobInfo last = client.watch(job_id, [&](const v1::JobInfo& info) {
    if (json_lines) {
      std::cout << to_json(info).dump() << std::endl;
    } else {
      view.update(info);
    }
  });
  view.finish();
  return last;
}

void warn_store_damage(const JobClient& client) {
  if (client.store_damage().empty()) return;
  std::cerr << "tessera: warning: the server hands out no more work: "
            << client.store_damage() << " (docs/reliability.md)\n";
}

int final_status(const v1::JobInfo& job) {
  switch (job.state()) {
    case v1::JOB_STATE_DONE: return 0;
    case v1::JOB_STATE_FAILED: return fail("job " + std::to_string(job.id()) + " failed: " + job.error());
    case v1::JOB_STATE_CANCELLED: return fail("job " + std::to_string(job.id()) + " was cancelled");
    default: return fail("job " + std::to_string(job.id()) + " is " + state_name(job.state()));
  }
}

std::string finished_line(const v1::JobInfo& job) {
  const auto& r = job.reached();
  char buf[320];
  std::snprintf(buf, sizeof buf,
                "job %llu %s, rule %s, in %.1f s: spp min %u / mean %.1f / max %u, estimated error "
                "max %s / mean %s, NaN/Inf dropped %llu",
                static_cast<unsigned long long>(job.id()),
                reason_name(job.stop_reason()).empty() ? "ended"
                                                       : ("stopped by " + reason_name(job.stop_reason())).c_str(),
                rule_text(job.options()).c_str(), job.wall_time_s(), r.spp_min(), r.spp_mean(),
                r.spp_max(), error_text(r.error_max(), r.spp_max()).c_str(),
                error_text(r.error_mean(), r.spp_max()).c_str(),
                static_cast<unsigned long long>(job.counters().nan_dropped() +
                                                job.counters().inf_dropped()));
  return buf;
}

}  // namespace tessera::client
