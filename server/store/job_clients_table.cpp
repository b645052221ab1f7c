#include "store/job_clients_table.h"

#include "store/job_state.h"

namespace tessera::server {

void JobClientsTable::add(int64_t job_id, const std::string& client) {
  db_.prepare("INSERT INTO job_clients (job_id, client) VALUES (?, ?)")
      ->bind(1, job_id)
      .bind(2, client)
      .run();
}

uint64_t JobClientsTable::unfinished_of(const std::string& client) {
  auto q = db_.prepare(
      "SELECT COUNT(*) FROM job_clients c JOIN jobs j ON j.id = c.job_id"
      " WHERE c.client = ? AND j.state IN (?, ?)");
  q->bind(1, client)
      .bind(2, std::string(to_string(JobState::queued)))
      .bind(3, std::string(to_string(JobState::running)));
  q->step();
  return uint64_t(q->int64(0));
}

}  // namespace tessera::server
