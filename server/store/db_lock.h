// One server per database: an exclusive flock(2) on "<db>.lock", held for the server's life and
// released by the kernel on any exit (SIGKILL included), so a restarted server gets it back at
// once. The holder writes its pid and host into the file; a second server is refused with one
// line naming them (docs/reliability.md, "One server per database").
#pragma once

#include <string>

namespace tessera::server {

class DatabaseLock {
 public:
  /// Locks `db_path` + ".lock" (created if missing). Throws std::runtime_error naming the
  /// database and the holder's pid and host when another process holds it, or the lock file and
  /// the system's reason when it cannot be opened. ":memory:" locks nothing.
  explicit DatabaseLock(const std::string& db_path);
  ~DatabaseLock();
  DatabaseLock(const DatabaseLock&) = delete;
  DatabaseLock& operator=(const DatabaseLock&) = delete;

  /// The lock file's path (empty for ":memory:").
  const std::string& path() const { return path_; }

 private:
  std::string path_;
  int fd_ = -1;
};

}  // namespace tessera::server
