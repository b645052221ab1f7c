#include "store/db_lock.h"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace tessera::server {
namespace {

std::string db_lock_host_name() {
  char name[256] = {};
  if (gethostname(name, sizeof name - 1) != 0) return "unknown host";
  return name;
}

/// "device D, inode I" of an open file.
std::string db_lock_identity(const struct stat& st) {
  return "device " + std::to_string(uint64_t(st.st_dev)) + ", inode " +
         std::to_string(uint64_t(st.st_ino));
}

/// The file a path names, symbolic links resolved (the path itself when it cannot be resolved).
std::string db_lock_resolved(const std::string& path) {
  std::error_code ec;
  const std::filesystem::path p = std::filesystem::canonical(path, ec);
  return ec ? path : p.string();
}

/// The note's lines: "pid <n> on host <h>", "database <path>" and "file <identity>".
struct DbLockNote {
  std::string holder, database, file;
};

DbLockNote db_lock_read_note(const std::string& note_path) {
  DbLockNote note;
  std::ifstream in(note_path);
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind("pid ", 0) == 0) note.holder = line;
    if (line.rfind("database ", 0) == 0) note.database = line.substr(9);
    if (line.rfind("file ", 0) == 0) note.file = line.substr(5);
  }
  return note;
}

/// The refusal: the holder's path, pid and host from its note when the note is for this file,
/// else what is known (the same file reached through another path: a hard link).
std::string db_lock_refusal(const std::string& db_path, const std::string& note_path,
                            const std::string& identity) {
  const DbLockNote note = db_lock_read_note(note_path);
  std::string who;
  if (note.file == identity && !note.holder.empty()) {
    who = "tessera-server " + note.holder;
    if (!note.database.empty() && note.database != db_path) who += " through " + note.database;
  } else if (note.file == identity) {
    who = "a tessera-server that has not written its pid yet";
  } else {
    who = "another tessera-server through another path to the same file (" + identity +
          "; a hard link?)";
  }
  return "database " + db_path + " is in use by " + who + " (lock note " + note_path +
         "): one server per database";
}

}  // namespace

DatabaseLock::DatabaseLock(const std::string& db_path) {
  if (db_path == ":memory:" || db_path.empty()) return;
  // The file itself, created empty when missing: a lock on "<db>.lock" belonged to a name, and a
  // second server reaching the same file through a link took its own.
  fd_ = ::open(db_path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (fd_ < 0) {
    throw std::runtime_error(db_path + ": cannot open the database to lock it: " +
                             std::strerror(errno));
  }
  struct stat st {};
  if (::fstat(fd_, &st) != 0) {
    const int err = errno;
    ::close(fd_);
    fd_ = -1;
    throw std::runtime_error(db_path + ": cannot read the database's device and inode: " +
                             std::strerror(err));
  }
  const std::string identity = db_lock_identity(st);
  note_path_ = db_lock_resolved(db_path) + ".lock";
  if (::flock(fd_, LOCK_EX | LOCK_NB) != 0) {
    const int err = errno;
    ::close(fd_);
    fd_ = -1;
    if (err == EWOULDBLOCK) {
      throw std::runtime_error(db_lock_refusal(db_path, note_path_, identity));
    }
    throw std::runtime_error(db_path + ": cannot lock: " + std::strerror(err));
  }
  // The note only names the holder for a refused second server: the lock holds without it.
  std::ofstream note(note_path_, std::ios::trunc);
  note << "pid " << ::getpid() << " on host " << db_lock_host_name() << "\n"
       << "database " << db_path << "\n"
       << "file " << identity << "\n";
}

DatabaseLock::~DatabaseLock() {
  if (fd_ >= 0) ::close(fd_);  // releases the lock
}

}  // namespace tessera::server
