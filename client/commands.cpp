#include "commands.h"

#include <unistd.h>

#include <cstdio>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <iostream>

#include "build_text.h"
#include "cli/output_path.h"
#include "job_client.h"
#include "json_view.h"
#include "progress_view.h"
#include "scene/scene_error.h"
#include "wire/job_options_wire.h"
#include "wire/scene_bundle.h"

namespace tessera::client {
namespace {

JobClient connect(const GlobalOptions& g) {
  return JobClient(g.server, g.token, g.tls,
                   std::chrono::milliseconds(int64_t(g.timeout_s * 1000)));
}

int fail(const std::string& line) {
  std::cerr << "tessera: " << line << "\n";
  return 1;
}

std::string lower_extension(const std::filesystem::path& p) {
  std::string ext = p.extension().string();
  for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

/// .exr or .png from the output's name, after checking that the output can be written
/// (cli::check_output_path); throws std::runtime_error naming what is wrong otherwise.
v1::ImageFormat format_of(const std::string& output) {
  cli::check_output_path(output, {".exr", ".png"});
  return lower_extension(output) == ".exr" ? v1::IMAGE_FORMAT_EXR : v1::IMAGE_FORMAT_PNG;
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

/// Watches until final with a progress bar on stderr (when it is a terminal or `force_bar`).
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

/// One line on stderr when the server's last answer said its store is damaged (status, list).
void warn_store_damage(const JobClient& client) {
  if (client.store_damage().empty()) return;
  std::cerr << "tessera: warning: the server hands out no more work: "
            << client.store_damage() << " (docs/reliability.md)\n";
}

/// 0 when done; else prints why and returns 1.
int final_status(const v1::JobInfo& job) {
  switch (job.state()) {
    case v1::JOB_STATE_DONE: return 0;
    case v1::JOB_STATE_FAILED: return fail("job " + std::to_string(job.id()) + " failed: " + job.error());
    case v1::JOB_STATE_CANCELLED: return fail("job " + std::to_string(job.id()) + " was cancelled");
    default: return fail("job " + std::to_string(job.id()) + " is " + state_name(job.state()));
  }
}

/// Downloads the job's image to `output`; returns what it wrote.
v1::GetImageResponse download(JobClient& client, uint64_t job_id, const std::string& output) {
  const v1::ImageFormat format = format_of(output);
  v1::GetImageResponse image = client.image(job_id, format);
  write_file(output, image.data());
  return image;
}

std::string when(int64_t unix_ms) {
  if (unix_ms <= 0) return "-";
  const std::time_t t = std::time_t(unix_ms / 1000);
  char buf[64];
  std::strftime(buf, sizeof buf, "%Y-%m-%d %H:%M:%S", std::localtime(&t));
  return buf;
}

/// One line on what a finished job reached: the answer to "what did my stopping rule give me".
std::string finished_line(const v1::JobInfo& job) {
  const auto& r = job.reached();
  char buf[320];
  std::snprintf(buf, sizeof buf,
                "job %llu %s, rule %s, in %.1f s: spp min %u / mean %.1f / max %u, estimated error "
                "max %.4f / mean %.4f, NaN/Inf dropped %llu",
                static_cast<unsigned long long>(job.id()),
                reason_name(job.stop_reason()).empty() ? "ended"
                                                       : ("stopped by " + reason_name(job.stop_reason())).c_str(),
                rule_text(job.options()).c_str(), job.wall_time_s(), r.spp_min(), r.spp_mean(),
                r.spp_max(), r.error_max(), r.error_mean(),
                static_cast<unsigned long long>(job.counters().nan_dropped() +
                                                job.counters().inf_dropped()));
  return buf;
}

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

}  // namespace

int submit(const GlobalOptions& g, const SubmitOptions& s) {
  return guarded([&] {
    if (!s.output.empty()) format_of(s.output);  // refuse an unwritable output before submitting
    // Validate locally first: a bad scene or option fails here, without the server.
    Scene scene;
    const wire::BundleContents bundle = wire::bundle_from_disk(
        s.scene, &scene,
        s.root.empty() ? std::nullopt : std::optional<std::filesystem::path>(s.root),
        parse_mitsuba_defines(s.defines));
    resolve_job_options(scene, s.overrides);
    v1::SubmitJobRequest request;
    *request.mutable_bundle() = wire::bundle_to_proto(bundle);
    *request.mutable_options() = wire::overrides_to_proto(s.overrides);
    request.set_priority(s.priority);
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

int status(const GlobalOptions& g, uint64_t job_id) {
  return guarded([&] {
    JobClient client = connect(g);
    v1::JobInfo job;
    try {
      job = client.get(job_id);
    } catch (const ClientError&) {
      warn_store_damage(client);  // the damage may be why the call failed
      throw;
    }
    warn_store_damage(client);
    if (g.json) {
      std::cout << to_json(job).dump() << std::endl;
      return 0;
    }
    const auto& o = job.options();
    const auto& c = job.counters();
    std::printf("job %llu: %s, %.1f %% \u2014 every tile has at least %u of %u spp, "
                "priority %d\n",
                static_cast<unsigned long long>(job.id()), state_name(job.state()).c_str(),
                100.0 * job.progress(), job.spp_merged(), o.spp(), job.priority());
    std::printf("  scene     %s (bundle sha256 %s)\n", job.scene_file().c_str(),
                job.bundle_sha256().c_str());
    std::printf("  options   %dx%d, %u spp, max depth %d, seed %llu, tile %d, batch %u%s%s\n",
                o.width(), o.height(), o.spp(), o.max_depth(),
                static_cast<unsigned long long>(o.seed()), o.tile_size(), o.batch_spp(),
                o.isa().empty() ? "" : ", isa ", o.isa().c_str());
    std::printf("  units     %u total, %u done, %u leased, %u merged\n", c.units_total(),
                c.units_done(), c.units_leased(), c.results_merged());
    std::printf("  retries   %u stale results dropped, %u leases expired, %u units handed back\n",
                c.results_dropped(), c.leases_expired(), c.units_released());
    std::printf("  times     submitted %s, started %s, finished %s\n",
                when(job.submitted_unix_ms()).c_str(), when(job.started_unix_ms()).c_str(),
                when(job.finished_unix_ms()).c_str());
    std::printf("  rule      %s\n", rule_text(o).c_str());
    const auto& r = job.reached();
    std::printf("  reached   %s%sspp min %u / mean %.1f / max %u, estimated error max %.4f / mean "
                "%.4f, %u tiles finished, wall time %.1f s, NaN/Inf dropped %llu\n",
                reason_name(job.stop_reason()).empty() ? "" : "stopped by ",
                reason_name(job.stop_reason()).empty()
                    ? ""
                    : (reason_name(job.stop_reason()) + ": ").c_str(),
                r.spp_min(), r.spp_mean(), r.spp_max(), r.error_max(), r.error_mean(),
                r.tiles_finished(), job.wall_time_s(),
                static_cast<unsigned long long>(c.nan_dropped() + c.inf_dropped()));
    if (c.units_skipped() + c.results_wasted() > 0) {
      std::printf("  skipped   %u units not needed by the rule, %u results wasted\n",
                  c.units_skipped(), c.results_wasted());
    }
    std::fputs(renderer_builds_text(job).c_str(), stdout);
    if (!job.error().empty()) std::printf("  error     %s\n", job.error().c_str());
    if (!job.output_exr().empty()) {
      std::printf("  output    %s\n            %s\n", job.output_exr().c_str(),
                  job.output_png().c_str());
    }
    return 0;
  });
}

int watch(const GlobalOptions& g, uint64_t job_id) {
  return guarded([&] {
    JobClient client = connect(g);
    const v1::JobInfo last = follow(client, job_id, g.json);
    if (!g.json && last.state() == v1::JOB_STATE_DONE) std::cerr << finished_line(last) << "\n";
    return final_status(last);
  });
}

int get(const GlobalOptions& g, uint64_t job_id, const std::string& output) {
  return guarded([&] {
    format_of(output);  // before any call
    JobClient client = connect(g);
    const v1::GetImageResponse image = download(client, job_id, output);
    if (g.json) {
      std::cout << nlohmann::json{{"path", output},
                                  {"final", image.final()},
                                  {"spp", image.spp()},
                                  {"width", image.width()},
                                  {"height", image.height()}}
                       .dump()
                << std::endl;
    } else {
      std::cerr << "wrote " << output << " ("
                << (image.final() ? "final" : "preview") << ", " << image.spp() << " spp)\n";
    }
    return 0;
  });
}

int cancel(const GlobalOptions& g, uint64_t job_id) {
  return guarded([&] {
    JobClient client = connect(g);
    const v1::JobInfo job = client.cancel(job_id);
    if (g.json) {
      std::cout << to_json(job).dump() << std::endl;
    } else {
      std::cout << "job " << job.id() << " cancelled\n";
    }
    return 0;
  });
}

int list(const GlobalOptions& g) {
  return guarded([&] {
    JobClient client = connect(g);
    v1::ListJobsResponse jobs;
    try {
      jobs = client.list(0);
    } catch (const ClientError&) {
      warn_store_damage(client);  // the damage may be why the call failed
      throw;
    }
    warn_store_damage(client);
    if (g.json) {
      nlohmann::json out = nlohmann::json::array();
      for (const auto& job : jobs.jobs()) out.push_back(to_json(job));
      std::cout << out.dump() << std::endl;
      return 0;
    }
    std::printf("%6s  %-9s  %7s  %8s  %-11s  %-24s  %s\n", "ID", "STATE", "DONE", "PRIORITY",
                "SIZE", "RULE", "SCENE");
    for (const auto& job : jobs.jobs()) {
      const std::string size =
          std::to_string(job.options().width()) + "x" + std::to_string(job.options().height());
      std::printf("%6llu  %-9s  %6.1f%%  %8d  %-11s  %-24s  %s\n",
                  static_cast<unsigned long long>(job.id()), state_name(job.state()).c_str(),
                  100.0 * job.progress(), job.priority(), size.c_str(),
                  rule_text(job.options()).c_str(), job.scene_file().c_str());
    }
    return 0;
  });
}

int workers(const GlobalOptions& g) {
  return guarded([&] {
    JobClient client = connect(g);
    const v1::ListWorkersResponse workers = client.workers();
    if (g.json) {
      nlohmann::json out = nlohmann::json::array();
      for (const auto& w : workers.workers()) out.push_back(to_json(w));
      std::cout << out.dump() << std::endl;
      return 0;
    }
    std::printf("%4s  %-24s  %-7s  %7s  %-7s  %-22s  %6s  %5s\n", "ID", "NAME", "STATUS",
                "THREADS", "ISA", "UNIT", "DONE", "LOST");
    for (const auto& w : workers.workers()) {
      const std::string unit = w.job_id() == 0 ? "-"
                                               : "job " + std::to_string(w.job_id()) + " t" +
                                                     std::to_string(w.tile()) + " b" +
                                                     std::to_string(w.batch());
      std::printf("%4llu  %-24s  %-7s  %7u  %-7s  %-22s  %6llu  %5llu\n",
                  static_cast<unsigned long long>(w.id()), w.name().c_str(),
                  w.online() ? "online" : "offline", w.threads(),
                  w.isa().empty() ? "-" : w.isa().c_str(), unit.c_str(),
                  static_cast<unsigned long long>(w.units_done()),
                  static_cast<unsigned long long>(w.units_lost()));
      if (!w.health_warning().empty()) {
        std::printf("      warning: %s\n", w.health_warning().c_str());
      }
    }
    return 0;
  });
}

}  // namespace tessera::client
