// One server per database: an exclusive flock(2) on the database file itself, held for the
// server's life and released by the kernel on any exit (SIGKILL included), so a restarted server
// gets it back at once. A flock belongs to the file (its device and inode), not to the name it
// was opened by, so a second server that reaches the same file through a symbolic link or a hard
// link is refused too. The holder writes its pid, host and database path into "<db>.lock" (next
// to the file the path resolves to); a second server is refused with one line naming them
// (docs/reliability.md, "One server per database").
#pragma once

#include <string>

namespace tessera::server {

class DatabaseLock {
 public:
  /// Locks the database file `db_path` (created empty if missing: an empty file is an empty
  /// SQLite database) and writes the holder's note. Throws std::runtime_error naming the
  /// database, the path the holder opened it by and the holder's pid and host when another
  /// process holds it (when the holder came through a hard link, whose note this path cannot
  /// find, the file's device and inode instead), or the file and the system's reason when it
  /// cannot be opened. ":memory:" locks nothing.
  ///
  /// Must outlive every SQLite connection to the file: closing a descriptor of a file drops the
  /// process's POSIX (fcntl) locks on it, which are SQLite's.
  explicit DatabaseLock(const std::string& db_path);
  ~DatabaseLock();
  DatabaseLock(const DatabaseLock&) = delete;
  DatabaseLock& operator=(const DatabaseLock&) = delete;

  /// The holder's note: "<db>.lock" beside the file the path resolves to (empty for
  /// ":memory:").
  const std::string& path() const { return note_path_; }

 private:
  std::string note_path_;
  int fd_ = -1;  ///< the database file, flocked
};

}  // namespace tessera::server
