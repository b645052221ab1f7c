// The bundles table: each scene bundle's canonical bytes, stored once per SHA-256 however many
// jobs use it. Every statement on `bundles` is here.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "store/sqlite.h"

namespace tessera::server {

class BundlesTable {
 public:
  explicit BundlesTable(Database& db) : db_(db) {}

  /// A submit: the bundle's bytes under `sha256`, unless that hash is stored already.
  void insert_once(const std::string& sha256, const std::string& scene_file,
                   const std::string& bytes, int64_t now_unix_ms);
  /// The canonical bytes by hash; nullopt when unknown.
  std::optional<std::string> bytes(const std::string& sha256);
  /// A delete: the bundle goes when no job uses it any more. Returns true when it went.
  bool remove_unused(const std::string& sha256);

 private:
  Database& db_;
};

}  // namespace tessera::server
