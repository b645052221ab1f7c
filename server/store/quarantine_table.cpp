#include "store/quarantine_table.h"

#include <algorithm>

namespace tessera::server {
namespace {

/// Job ids as stored: "3,5,8" ("" for none).
std::string join_ids(const std::vector<int64_t>& ids) {
  std::string out;
  for (const int64_t id : ids) out += (out.empty() ? "" : ",") + std::to_string(id);
  return out;
}

std::vector<int64_t> split_ids(const std::string& text) {
  std::vector<int64_t> out;
  size_t begin = 0;
  while (begin < text.size()) {
    const size_t end = std::min(text.find(',', begin), text.size());
    out.push_back(std::stoll(text.substr(begin, end - begin)));
    begin = end + 1;
  }
  return out;
}

}  // namespace

void QuarantineTable::put(const std::string& worker_name, const Quarantine& q) {
  db_.prepare(
         "INSERT OR IGNORE INTO worker_quarantines"
         " (worker_name, job_id, tile, batch, quarantined_unix_ms, reason, finished_jobs)"
         " VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7)")
      ->bind_all(worker_name, q.job_id, q.tile, q.batch, q.time_unix_ms, q.reason,
                 join_ids(q.finished_jobs))
      .run();
}

bool QuarantineTable::remove(const std::string& worker_name) {
  db_.prepare("DELETE FROM worker_quarantines WHERE worker_name = ?1")
      ->bind_all(worker_name)
      .run();
  return db_.changes() > 0;
}

std::map<std::string, Quarantine> QuarantineTable::all() {
  std::map<std::string, Quarantine> out;
  const auto rows =
      db_.prepare(
             "SELECT worker_name, job_id, tile, batch, quarantined_unix_ms, reason,"
             " finished_jobs FROM worker_quarantines")
          ->rows([](const Statement& q) {
            Quarantine r{q.int64(1), uint32_t(q.int64(2)), uint32_t(q.int64(3)), q.int64(4),
                         q.text(5), split_ids(q.text(6))};
            return std::pair(q.text(0), r);
          });
  for (const auto& [name, q] : rows) out.emplace(name, q);
  return out;
}

std::vector<int64_t> QuarantineTable::finished_jobs_of(const std::string& worker_name) {
  // A full pass over units: a quarantine is rare, and no index serves done units by worker.
  return db_.prepare(
                "SELECT DISTINCT u.job_id FROM units u JOIN workers w ON w.id = u.worker_id"
                " JOIN jobs j ON j.id = u.job_id"
                " WHERE w.name = ?1 AND u.state = 'done' AND j.state = 'done' ORDER BY u.job_id")
      ->bind_all(worker_name)
      .rows([](const Statement& q) { return q.int64(0); });
}

}  // namespace tessera::server
