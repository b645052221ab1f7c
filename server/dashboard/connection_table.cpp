#include "dashboard/connection_table.h"

#include <algorithm>
#include <stdexcept>

namespace tessera::server {

ConnectionTable::ConnectionTable(int per_client, int max_total)
    : per_client_(per_client),
      max_total_(max_total),
      max_admitted_(max_total - std::max(1, max_total / 8)) {
  if (per_client < 1 || max_total < 2) {
    throw std::invalid_argument("connection limits: per client " + std::to_string(per_client) +
                                " (at least 1), in all " + std::to_string(max_total) +
                                " (at least 2)");
  }
}

void ConnectionTable::forget_head(const std::string& address, uint64_t id) {
  auto it = clients_.find(address);
  if (it == clients_.end()) return;
  std::erase(it->second.heads, id);
}

void ConnectionTable::drop_client_if_idle(const std::string& address) {
  auto it = clients_.find(address);
  if (it != clients_.end() && it->second.heads.empty() && it->second.admitted == 0) {
    clients_.erase(it);
  }
}

ConnectionTable::Opened ConnectionTable::open(const std::string& address) {
  Opened opened;
  Client& client = clients_[address];
  if (int(client.heads.size()) >= per_client_) {
    const uint64_t oldest = client.heads.front();
    client.heads.pop_front();
    stage_.erase(oldest);
    opened.drop.push_back(oldest);
  }
  if (int(stage_.size()) >= max_total_) {
    // The oldest head in progress of any address: ids grow, so the first found is the oldest.
    auto head = std::find_if(stage_.begin(), stage_.end(),
                             [](const auto& entry) { return entry.second.stage == Stage::head; });
    if (head == stage_.end()) {
      drop_client_if_idle(address);
      return opened;  // every slot holds a request past its head: refused
    }
    const uint64_t oldest = head->first;
    const std::string oldest_address = head->second.address;
    stage_.erase(head);
    forget_head(oldest_address, oldest);
    if (oldest_address != address) drop_client_if_idle(oldest_address);
    opened.drop.push_back(oldest);
  }
  opened.id = next_id_++;
  stage_.emplace(opened.id, Entry{address, Stage::head});
  clients_[address].heads.push_back(opened.id);
  return opened;
}

ConnectionTable::Admission ConnectionTable::head_done(uint64_t id, bool exempt) {
  auto it = stage_.find(id);
  if (it == stage_.end()) return Admission::exempt;
  Entry& entry = it->second;
  if (entry.stage != Stage::head) return entry.stage == Stage::admitted ? Admission::admitted
                                                                        : Admission::exempt;
  forget_head(entry.address, id);
  Client& client = clients_[entry.address];
  Admission admission = Admission::admitted;
  if (exempt) {
    admission = Admission::exempt;
  } else if (client.admitted >= per_client_) {
    admission = Admission::client_full;
  } else if (int(admitted_total_) >= max_admitted_) {
    admission = Admission::server_full;
  }
  if (admission == Admission::admitted) {
    entry.stage = Stage::admitted;
    ++client.admitted;
    ++admitted_total_;
  } else {
    entry.stage = Stage::exempt;  // answered at once (the probe, or the refusal), then closed
  }
  return admission;
}

std::vector<uint64_t> ConnectionTable::heads() const {
  std::vector<uint64_t> ids;
  for (const auto& [id, entry] : stage_) {
    if (entry.stage == Stage::head) ids.push_back(id);
  }
  return ids;
}

void ConnectionTable::close(uint64_t id) {
  auto it = stage_.find(id);
  if (it == stage_.end()) return;
  const Entry entry = it->second;
  stage_.erase(it);
  if (entry.stage == Stage::head) {
    forget_head(entry.address, id);
  } else if (entry.stage == Stage::admitted) {
    --clients_[entry.address].admitted;
    --admitted_total_;
  }
  drop_client_if_idle(entry.address);
}

}  // namespace tessera::server
