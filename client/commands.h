// The `tessera` CLI's subcommands, one file each (submit_command.cpp, status_command.cpp, ...).
// Each add_*_command registers its subcommand and options on the CLI11 app and returns how to
// run it; main() runs the one that was parsed. A run returns the process exit code: 0 success,
// 1 failure (with a one-line reason on stderr). Usage errors (2) are CLI11's.
#pragma once

#include <functional>
#include <string>

#include "wire/transport_security.h"

namespace CLI {
class App;
}

namespace tessera::client {

/// The options every subcommand shares (before or after the subcommand's name).
struct GlobalOptions {
  std::string server = "127.0.0.1:50051";
  std::string token;
  std::string token_file;
  wire::ClientTls tls;
  double timeout_s = 30;  ///< deadline of each short call
  bool json = false;      ///< machine-readable output on stdout
};

/// A registered subcommand: its parser, and what runs it once parsing is done (reading the
/// options it bound, `g` included, which must outlive it).
struct Command {
  CLI::App* parser = nullptr;
  std::function<int()> run;
};

Command add_submit_command(CLI::App& app, GlobalOptions& g);
Command add_status_command(CLI::App& app, GlobalOptions& g);
Command add_watch_command(CLI::App& app, GlobalOptions& g);
Command add_get_command(CLI::App& app, GlobalOptions& g);
Command add_cancel_command(CLI::App& app, GlobalOptions& g);
Command add_delete_command(CLI::App& app, GlobalOptions& g);
Command add_list_command(CLI::App& app, GlobalOptions& g);
Command add_workers_command(CLI::App& app, GlobalOptions& g);

}  // namespace tessera::client
