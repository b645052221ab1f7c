// A store damaged where a server's start-up does not read it, as a failing disk leaves one: the
// dashboard's tests of the store banner, /api/store, /metrics and the CLI's warning use it.
#pragma once

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "store/integrity.h"
#include "store/migrations.h"
#include "store/sqlite.h"

namespace tessera::server::testing {

/// Opens the store at `path` (creating and migrating it when new), appends `workers` worker rows
/// (which start-up never reads) so that they fill the file's last pages, checkpoints, and writes
/// garbage over the last 8 pages. Leaves no clean-shutdown mark: the next server start runs the
/// background check, which finds the damage.
inline void fill_and_damage_store(const std::filesystem::path& path, int workers = 3000) {
  int64_t page = 0;
  {
    Database db(path.string());
    migrate(db, 0);
    {
      Transaction t(db);
      for (int i = 0; i < workers; ++i) {
        db.exec(
            "INSERT INTO workers (name, threads, isa, version, registered_unix_ms,"
            " last_seen_unix_ms) VALUES ('worker with a long name to fill pages', 1, 'avx2',"
            " '0', 0, 0)");
      }
      t.commit();
    }
    ASSERT_TRUE(checkpoint_wal(db));
    auto q = db.prepare("PRAGMA page_size");
    ASSERT_TRUE(q->step());
    page = q->int64(0);
  }
  const auto size = std::filesystem::file_size(path);
  ASSERT_GT(size, uint64_t(page) * 40);
  std::fstream file(path, std::ios::in | std::ios::out | std::ios::binary);
  file.seekp(std::streamoff(size - uint64_t(page) * 8));
  const std::string garbage(size_t(page) * 8, '\x5a');
  file.write(garbage.data(), std::streamsize(garbage.size()));
  ASSERT_TRUE(file.good());
}

}  // namespace tessera::server::testing
