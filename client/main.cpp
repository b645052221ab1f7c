// tessera: the render farm's command-line client (docs/farm.md). The global options are here;
// each subcommand is a file of its own (commands.h).
#include <CLI/CLI.hpp>
#include <iostream>
#include <vector>

#include "build_info.h"
#include "cli/host_port.h"
#include "cli/usage_exit.h"
#include "commands.h"
#include "wire/client_tls_flags.h"

namespace {

void add_global_options(CLI::App& app, tessera::client::GlobalOptions& g) {
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
  add_global_options(app, g);
  // In the order `tessera --help` lists them.
  const std::vector<tc::Command> commands = {
      tc::add_submit_command(app, g), tc::add_status_command(app, g),
      tc::add_watch_command(app, g),  tc::add_get_command(app, g),
      tc::add_cancel_command(app, g), tc::add_delete_command(app, g),
      tc::add_list_command(app, g),   tc::add_workers_command(app, g)};

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
  for (const tc::Command& command : commands) {
    if (command.parser->parsed()) return command.run();
  }
  return tessera::cli::kExitUsage;
}
