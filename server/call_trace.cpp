#include "call_trace.h"

#include <sys/syscall.h>
#include <time.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <mutex>
#include <vector>

namespace tessera::server::call_trace {
namespace detail {
std::atomic<bool> on{false};
}

namespace {

struct Event {
  const char* kind;
  int64_t begin_ns, end_ns, a, b;
  long tid;
  std::string id;
};

std::mutex mu;
std::vector<Event> events;  // guarded by mu
std::string path;           // set once before `on`

}  // namespace

int64_t now_ns() {
  if (!enabled()) return 0;
  timespec t{};
  clock_gettime(CLOCK_MONOTONIC, &t);
  return int64_t(t.tv_sec) * 1'000'000'000 + t.tv_nsec;
}

void record(const char* kind, int64_t begin_ns, int64_t end_ns, int64_t a, int64_t b,
            std::string_view id) {
  if (!enabled()) return;
  std::lock_guard lock(mu);
  thread_local const long tid = syscall(SYS_gettid);
  events.push_back(Event{kind, begin_ns, end_ns, a, b, tid, std::string(id)});
}

void start_from_environment() {
  const char* file = std::getenv("TESSERA_CALL_TRACE");
  if (!file || !*file) return;
  path = file;
  {
    std::lock_guard lock(mu);
    events.reserve(1 << 20);
  }
  detail::on = true;
}

bool write() {
  if (!enabled()) return true;
  std::lock_guard lock(mu);
  FILE* out = std::fopen(path.c_str(), "w");
  if (!out) return false;
  for (const Event& e : events) {
    std::fprintf(out, "%s %ld %lld %lld %lld %lld %s\n", e.kind, e.tid, static_cast<long long>(e.begin_ns),
                 static_cast<long long>(e.end_ns), static_cast<long long>(e.a),
                 static_cast<long long>(e.b), e.id.empty() ? "-" : e.id.c_str());
  }
  return std::fclose(out) == 0;
}

}  // namespace tessera::server::call_trace
