#include "store/bundles_table.h"

namespace tessera::server {

void BundlesTable::insert_once(const std::string& sha256, const std::string& scene_file,
                               const std::string& bytes, int64_t now) {
  db_.prepare(
         "INSERT OR IGNORE INTO bundles (sha256, scene_file, data, size_bytes, created_unix_ms)"
         " VALUES (?, ?, ?, ?, ?)")
      ->bind(1, sha256)
      .bind(2, scene_file)
      .bind_blob(3, bytes)
      .bind(4, int64_t(bytes.size()))
      .bind(5, now)
      .run();
}

std::optional<std::string> BundlesTable::bytes(const std::string& sha256) {
  return db_.prepare("SELECT data FROM bundles WHERE sha256 = ?")
      ->bind_all(sha256)
      .first_row([](const Statement& r) { return r.blob(0); });
}

bool BundlesTable::remove_unused(const std::string& sha256) {
  db_.prepare(
         "DELETE FROM bundles WHERE sha256 = ?1 AND NOT EXISTS"
         " (SELECT 1 FROM jobs WHERE bundle_sha256 = ?1)")
      ->bind(1, sha256)
      .run();
  return db_.changes() == 1;
}

}  // namespace tessera::server
