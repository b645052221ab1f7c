// A map whose entries are evicted least recently stored first once their bytes exceed a budget:
// the one LRU behind the server's in-memory caches of the store (MergeCache: decoded tiles;
// WaitingResults: decoded results waiting for an earlier batch). Entries are taken out (not
// read in place): a caller takes an entry, uses it, and puts it back, so an entry in use is
// never evicted under it. Not thread-safe: the coordinator serialises its callers.
#pragma once

#include <cstddef>
#include <iterator>
#include <list>
#include <map>
#include <optional>
#include <utility>

namespace tessera::server {

template <typename Key, typename Value>
class ByteBoundedLru {
 public:
  explicit ByteBoundedLru(size_t budget_bytes) : budget_(budget_bytes) {}

  /// Bytes an entry costs beyond what its value holds on the heap (callers add this to the
  /// `bytes` they pass to put()).
  static constexpr size_t kEntryBytes = sizeof(std::pair<Key, std::pair<Value, size_t>>);

  /// Stores `value` under `key` as the most recently stored entry, counting `bytes` against the
  /// budget (an entry already under `key` is replaced), then evicts the least recently stored
  /// entries while the bytes exceed the budget: `value` itself too when it alone exceeds it.
  /// `evicted(key)` is called for each entry evicted so (not for one replaced under `key`).
  template <typename Evicted = void (*)(const Key&)>
  void put(const Key& key, Value value, size_t bytes, Evicted evicted = [](const Key&) {}) {
    if (const auto found = index_.find(key); found != index_.end()) erase(found->second);
    order_.push_front(Entry{key, std::move(value), bytes});
    index_[key] = order_.begin();
    bytes_ += bytes;
    while (bytes_ > budget_ && !order_.empty()) {
      const auto last = std::prev(order_.end());
      evicted(last->key);
      erase(last);
    }
  }

  /// Removes the entry of `key` and returns its value; nullopt when there is none.
  std::optional<Value> take(const Key& key) {
    const auto found = index_.find(key);
    if (found == index_.end()) return std::nullopt;
    std::optional<Value> out(std::move(found->second->value));
    erase(found->second);
    return out;
  }

  /// Removes the entries from `first` on (in key order) while `in_range(key)` holds: e.g. every
  /// entry of one job, its keys being contiguous.
  template <typename InRange>
  void erase_from(const Key& first, InRange in_range) {
    auto it = index_.lower_bound(first);
    while (it != index_.end() && in_range(it->first)) {
      const auto entry = it->second;
      ++it;
      erase(entry);
    }
  }

  size_t bytes() const { return bytes_; }
  size_t entries() const { return index_.size(); }
  size_t budget_bytes() const { return budget_; }

 private:
  struct Entry {
    Key key;
    Value value;
    size_t bytes;
  };
  void erase(typename std::list<Entry>::iterator it) {
    bytes_ -= it->bytes;
    index_.erase(it->key);
    order_.erase(it);
  }

  size_t budget_;
  size_t bytes_ = 0;
  std::list<Entry> order_;  ///< most recently stored first
  std::map<Key, typename std::list<Entry>::iterator> index_;
};

}  // namespace tessera::server
