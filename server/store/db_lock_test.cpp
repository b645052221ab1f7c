// One server per database (store/db_lock.h): a second lock on the same database is refused
// naming the holder's pid and host, also through a symbolic or a hard link to the file; a holder
// killed with SIGKILL releases it.
#include "store/db_lock.h"

#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <stdexcept>
#include <string>

namespace tessera::server {
namespace {

std::filesystem::path fresh_dir(const std::string& name) {
  const auto dir = std::filesystem::temp_directory_path() /
                   ("tessera-db-lock-" + name + "-" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

std::string refusal(const std::string& db) {
  try {
    DatabaseLock second(db);
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "";
}

TEST(DatabaseLock, ASecondHolderIsRefusedNamingTheFirst) {
  const std::string db = (fresh_dir("second") / "farm.db").string();
  std::string why;
  {
    DatabaseLock first(db);
    EXPECT_EQ(first.path(), db + ".lock");
    why = refusal(db);
    EXPECT_NE(why.find("database " + db + " is in use by tessera-server pid " +
                       std::to_string(::getpid()) + " on host "),
              std::string::npos)
        << why;
  }
  EXPECT_EQ(refusal(db), "");  // released with its holder
  EXPECT_EQ(refusal(":memory:"), "");
}

TEST(DatabaseLock, ASecondHolderThroughASymbolicLinkIsRefusedNamingBothPaths) {
  const std::filesystem::path dir = fresh_dir("symlink");
  const std::string db = (dir / "farm.db").string();
  const std::string link = (dir / "link.db").string();
  std::string why;
  {
    DatabaseLock first(db);
    std::filesystem::create_symlink(db, link);
    why = refusal(link);
    EXPECT_NE(why.find("database " + link + " is in use by tessera-server pid " +
                       std::to_string(::getpid()) + " on host "),
              std::string::npos)
        << why;
    EXPECT_NE(why.find(" through " + db), std::string::npos) << why;
  }
  EXPECT_EQ(refusal(link), "");  // released with its holder
  // And the other way round: a holder through the link refuses the file's own path.
  DatabaseLock through_link(link);
  why = refusal(db);
  EXPECT_NE(why.find("database " + db + " is in use by tessera-server pid "), std::string::npos)
      << why;
  EXPECT_NE(why.find(" through " + link), std::string::npos) << why;
}

TEST(DatabaseLock, ASecondHolderThroughAHardLinkIsRefused) {
  const std::filesystem::path dir = fresh_dir("hardlink");
  std::filesystem::create_directories(dir / "elsewhere");
  const std::string db = (dir / "farm.db").string();
  const std::string link = (dir / "elsewhere" / "farm.db").string();
  DatabaseLock first(db);
  std::filesystem::create_hard_link(db, link);
  const std::string why = refusal(link);
  // Its note is beside the other name: the refusal names the file by device and inode.
  EXPECT_NE(why.find("database " + link + " is in use by another tessera-server through another"
                     " path to the same file (device "),
            std::string::npos)
      << why;
  EXPECT_NE(why.find("; a hard link?"), std::string::npos) << why;
  EXPECT_NE(refusal(db).find("pid " + std::to_string(::getpid())), std::string::npos);
}

TEST(DatabaseLock, AMissingDatabaseIsCreatedEmptyAndLocked) {
  const std::string db = (fresh_dir("missing") / "farm.db").string();
  DatabaseLock first(db);
  EXPECT_TRUE(std::filesystem::exists(db));
  EXPECT_EQ(std::filesystem::file_size(db), 0u);
  EXPECT_NE(refusal(db), "");
}

TEST(DatabaseLock, AHolderKilledWithSigkillReleasesIt) {
  const std::string db = (fresh_dir("kill") / "farm.db").string();
  int ready[2];
  ASSERT_EQ(::pipe(ready), 0);
  const pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    DatabaseLock held(db);
    const char c = 'x';
    if (::write(ready[1], &c, 1) != 1) _exit(2);
    for (;;) ::pause();
  }
  char c = 0;
  ASSERT_EQ(::read(ready[0], &c, 1), 1);
  EXPECT_NE(refusal(db).find("pid " + std::to_string(child) + " on host "), std::string::npos);
  ASSERT_EQ(::kill(child, SIGKILL), 0);
  int status = 0;
  ASSERT_EQ(::waitpid(child, &status, 0), child);
  EXPECT_EQ(refusal(db), "");  // the kernel released the dead holder's lock
  ::close(ready[0]);
  ::close(ready[1]);
}

}  // namespace
}  // namespace tessera::server
