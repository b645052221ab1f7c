#include "store/job_contributors_table.h"

namespace tessera::server {
namespace {

std::string read_text(const Statement& q) { return q.text(0); }

}  // namespace

void JobContributorsTable::add(int64_t job_id, const std::string& isa, int64_t worker_id) {
  db_.prepare(
         "INSERT OR IGNORE INTO job_contributors (job_id, isa, version)"
         " SELECT ?, ?, version FROM workers WHERE id = ?")
      ->bind(1, job_id)
      .bind(2, isa)
      .bind(3, worker_id)
      .run();
}

std::vector<std::string> JobContributorsTable::isas(int64_t job_id) {
  return db_.prepare("SELECT DISTINCT isa FROM job_contributors WHERE job_id = ? ORDER BY isa")
      ->bind_all(job_id)
      .rows(read_text);
}

std::vector<std::string> JobContributorsTable::versions(int64_t job_id) {
  return db_
      .prepare("SELECT DISTINCT version FROM job_contributors WHERE job_id = ? ORDER BY version")
      ->bind_all(job_id)
      .rows(read_text);
}

}  // namespace tessera::server
