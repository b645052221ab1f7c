#include "merge_bench_worker.h"

#include "tessera/v1/worker_service.grpc.pb.h"
#include "wire/rpc_channel.h"

namespace tessera::bench_merge {

std::shared_ptr<grpc::Channel> make_channel(const std::string& address, bool own_connection) {
  grpc::ChannelArguments args;
  args.SetMaxReceiveMessageSize(wire::kMaxMessageBytes);
  args.SetMaxSendMessageSize(wire::kMaxMessageBytes);
  args.SetInt(GRPC_ARG_KEEPALIVE_TIME_MS, wire::kKeepaliveTimeMs);
  args.SetInt(GRPC_ARG_KEEPALIVE_TIMEOUT_MS, wire::kKeepaliveTimeoutMs);
  args.SetInt(GRPC_ARG_KEEPALIVE_PERMIT_WITHOUT_CALLS, 1);
  if (own_connection) args.SetInt(GRPC_ARG_USE_LOCAL_SUBCHANNEL_POOL, 1);
  return grpc::CreateCustomChannel(address, grpc::InsecureChannelCredentials(), args);
}

void check_status(const grpc::Status& status, const std::string& call) {
  if (!status.ok()) throw BenchError(call + " failed: " + wire::status_line(status));
}

namespace {

using WorkerStub = v1::WorkerService::Stub;
/// The units one LeaseUnit call gave: (lease id, unit) each.
using HeldUnits = std::vector<std::pair<std::string, v1::WorkUnit>>;

/// Registers simulated worker `index`; waits for the channel, within the call's deadline.
v1::RegisterResponse register_bench_worker(WorkerStub& stub, int index) {
  v1::RegisterRequest reg;
  reg.set_name("bench-" + std::to_string(index));
  reg.set_threads(1);
  reg.set_isa("bench");
  reg.set_version("bench");
  v1::RegisterResponse reply;
  grpc::ClientContext ctx;
  wire::prepare_context(ctx, "", kCallTimeout);
  // Before the clock: N channels connecting at once sometimes saw a connection attempt fail
  // ("failed to connect to all addresses", and the run was lost); wait for the channel
  // instead, within the call's deadline.
  ctx.set_wait_for_ready(true);
  check_status(stub.Register(&ctx, reg, &reply), "Register");
  return reply;
}

/// Hands the held units back (a bounded run ending) rather than leave leases behind.
void release_held(WorkerStub& stub, uint64_t worker_id, const HeldUnits& held, WorkerTally& tally) {
  for (const auto& [lease_id, unit] : held) {
    v1::ReleaseUnitRequest release;
    release.set_worker_id(worker_id);
    release.set_lease_id(lease_id);
    release.set_reason(v1::ReleaseUnitRequest::REASON_SHUTDOWN);
    v1::ReleaseUnitResponse released;
    grpc::ClientContext ctx;
    wire::prepare_context(ctx, "", kCallTimeout);
    check_status(stub.ReleaseUnit(&ctx, release, &released), "ReleaseUnit");
    ++tally.released;
  }
}

/// The upload of the held units' results (from the bank), in one UploadResults call when
/// batched, else one UploadResult; *slots receives each unit's slot in shared.acked.
v1::UploadResultsRequest results_of(uint64_t worker_id, const HeldUnits& held, const ResultBank& bank,
                                    RunShared& shared, WorkerTally& tally, std::vector<size_t>* slots) {
  v1::UploadResultsRequest uploads;
  uploads.set_worker_id(worker_id);
  for (const auto& [lease_id, unit] : held) {
    v1::UploadResultRequest* upload = uploads.add_results();
    upload->set_worker_id(worker_id);
    upload->set_lease_id(lease_id);
    upload->set_job_id(unit.job_id());
    upload->set_tile(unit.tile());
    upload->set_batch(unit.batch());
    upload->set_accumulation(bank.get(unit.tile(), unit.sample_end() - unit.sample_begin()));
    upload->set_isa("bench");
    upload->set_render_ms(0);
    const size_t slot = size_t(unit.tile()) * shared.batch_count + unit.batch();
    if (slot >= shared.acked.size()) {
      throw BenchError("leased unit tile " + std::to_string(unit.tile()) + " batch " +
                       std::to_string(unit.batch()) + " is outside the job's plan");
    }
    if (unit.batch() > 0 && shared.acked[slot - 1] == 0) ++tally.early;
    slots->push_back(slot);
  }
  return uploads;
}

/// Uploads the held units' results and counts what the server accepted.
void upload_held(WorkerStub& stub, uint64_t worker_id, const HeldUnits& held, const Options& options,
                 const ResultBank& bank, RunShared& shared, WorkerTally& tally, size_t lease_bytes) {
  const bool batched = options.per_call > 1;
  std::vector<size_t> slots;
  const v1::UploadResultsRequest uploads = results_of(worker_id, held, bank, shared, tally, &slots);
  v1::UploadResultsResponse results;
  const auto t2 = Clock::now();
  {
    grpc::ClientContext ctx;
    wire::prepare_context(ctx, "", kUploadTimeout);
    check_status(batched ? stub.UploadResults(&ctx, uploads, &results)
                         : stub.UploadResult(&ctx, uploads.results(0), results.add_results()),
                 batched ? "UploadResults" : "UploadResult");
  }
  const auto t3 = Clock::now();
  if (results.results_size() != int(slots.size())) {
    throw BenchError("UploadResults answered " + std::to_string(results.results_size()) + " results for " +
                     std::to_string(slots.size()));
  }
  tally.upload_ms.push_back(ms_between(t2, t3));
  if (!options.trace.empty()) {
    tally.calls.push_back({"upload", ns_of(t2), ns_of(t3), uint32_t(slots.size()), held.front().first});
  }
  tally.proto_bytes += lease_bytes + (batched ? uploads.ByteSizeLong() + results.ByteSizeLong()
                                              : uploads.results(0).ByteSizeLong() + results.results(0).ByteSizeLong());
  tally.results += slots.size();
  for (size_t i = 0; i < slots.size(); ++i) {
    if (results.results(int(i)).accepted()) {
      ++tally.accepted;
      tally.last_accept = t3;
      tally.last_accept_upload_ms = tally.upload_ms.back();
      if (shared.acked[slots[i]].fetch_add(1) != 0) {
        throw BenchError("unit " + std::to_string(slots[i]) + " was accepted twice");
      }
    } else {
      ++tally.dropped;
    }
  }
}

}  // namespace

void simulated_worker(int index, std::shared_ptr<grpc::Channel> channel, const Options& options,
                      const ResultBank& bank, RunShared& shared, std::latch& registered,
                      std::latch& go, WorkerTally& tally) {
  auto stub = v1::WorkerService::NewStub(channel);
  bool counted = false;  // a latch must not be counted down twice
  try {
    const uint64_t worker_id = register_bench_worker(*stub, index).worker_id();
    registered.count_down();
    counted = true;
    go.wait();
    const bool batched = options.per_call > 1;
    while (!shared.stop) {
      v1::LeaseUnitRequest lease_req;
      lease_req.set_worker_id(worker_id);
      lease_req.set_wait_ms(options.wait_ms);
      if (batched) lease_req.set_max_units(options.per_call);
      v1::LeaseUnitResponse lease;
      const auto t0 = Clock::now();
      {
        grpc::ClientContext ctx;
        wire::prepare_context(ctx, "", kCallTimeout + std::chrono::milliseconds(options.wait_ms));
        check_status(stub->LeaseUnit(&ctx, lease_req, &lease), "LeaseUnit");
      }
      const auto t1 = Clock::now();
      if (!lease.leased()) {
        ++tally.no_work;
        if (shared.job_ended) break;
        continue;
      }
      tally.lease_ms.push_back(ms_between(t0, t1));
      // The leases of this call: one in the single-unit fields, or several in `leases`.
      HeldUnits held;
      if (batched) {
        for (const v1::UnitLease& l : lease.leases()) held.emplace_back(l.lease_id(), l.unit());
      } else {
        held.emplace_back(lease.lease_id(), lease.unit());
      }
      if (!options.trace.empty() && !held.empty()) {
        tally.calls.push_back({"lease", ns_of(t0), ns_of(t1), uint32_t(held.size()), held.front().first});
      }
      if (shared.stop) {  // bounded run: hand the units back rather than leave leases behind
        release_held(*stub, worker_id, held, tally);
        break;
      }
      upload_held(*stub, worker_id, held, options, bank, shared, tally,
                  lease_req.ByteSizeLong() + lease.ByteSizeLong());
    }
  } catch (const std::exception& e) {
    shared.fail("worker " + std::to_string(index) + ": " + e.what());
    if (!counted) registered.count_down();
  }
}

}  // namespace tessera::bench_merge
