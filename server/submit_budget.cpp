#include "submit_budget.h"

#include <algorithm>
#include <array>

#include "farm_error.h"
#include "scene/image_check.h"
#include "scene/mesh/serialized_loader.h"
#include "scene/scene_error.h"

namespace tessera::server {
namespace {

std::string submit_budget_mib(uint64_t bytes) {
  return std::to_string((bytes + (uint64_t(1) << 20) - 1) >> 20) + " MiB";
}

std::string submit_budget_extension(const std::string& path) {
  const size_t slash = path.rfind('/');
  const size_t dot = path.rfind('.');
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return "";
  std::string ext = path.substr(dot);
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return char(std::tolower(c)); });
  return ext;
}

/// Files that are never images: their headers are not shown to OpenImageIO.
bool submit_budget_not_image(const std::string& ext) {
  static constexpr std::array<std::string_view, 9> kNotImages = {
      ".xml", ".json", ".ply", ".obj", ".mtl", ".serialized", ".vol", ".spd", ".txt"};
  return std::find(kNotImages.begin(), kNotImages.end(), ext) != kNotImages.end();
}

/// What decoding `bytes` of `path` takes, from its header.
uint64_t submit_file_cost(const std::string& path, const std::string& bytes,
                          uint64_t max_texture_values) {
  const std::string ext = submit_budget_extension(path);
  // The loaded arrays, the scene's copy of them and what the parser adds (vertex normals,
  // transforms): a 1M-vertex, 1M-triangle mesh (36 MB of arrays in a 24 MB file) took about
  // 180 MB to check, 72 MB of it the bundle's copies.
  if (ext == ".serialized") return 3 * serialized_load_bytes(bytes, path);
  // PLY headers are checked against their bytes (ply_loader); text and binary rows widen to
  // doubles and triangles: a few times their bytes.
  if (ext == ".ply" || ext == ".obj") return 8 * uint64_t(bytes.size());
  // A volume grid holds its floats uncompressed: loaded, it is about its bytes.
  if (ext == ".vol") return uint64_t(bytes.size());
  if (submit_budget_not_image(ext)) return 0;
  ImageHeader header;
  try {
    header = probe_image_bytes(path, bytes);
  } catch (const SceneError&) {
    return 0;  // not an image OpenImageIO reads: refused at open, before any pixel, if used
  }
  if (header.values() > max_texture_values) {
    throw invalid_argument(path + ": " + std::to_string(header.width) + " x " +
                           std::to_string(header.height) + " x " +
                           std::to_string(header.channels) + " values, more than the farm's " +
                           std::to_string(max_texture_values) +
                           " per image (server flag --max-texture-values)");
  }
  return image_check_memory(header);
}

}  // namespace

SubmitBudget::Reservation::~Reservation() {
  if (budget_ != nullptr) budget_->release(bytes_);
}

SubmitBudget::Reservation SubmitBudget::reserve(uint64_t bytes, const std::string& what,
                                                const std::string& detail,
                                                std::chrono::milliseconds max_wait) {
  std::unique_lock lock(mutex_);
  if (bytes > capacity_) {
    ++counters_.refused_too_large;
    throw invalid_argument(what + ": checking it needs " + submit_budget_mib(bytes) +
                           (detail.empty() ? "" : " (" + detail + ")") +
                           ", more than the server's submit memory budget of " +
                           submit_budget_mib(capacity_) + " (server flag --submit-memory-mb)");
  }
  const uint64_t ticket = next_ticket_++;
  queue_.push_back(ticket);
  const auto first_and_fits = [&] {
    return queue_.front() == ticket && counters_.reserved_bytes + bytes <= capacity_;
  };
  const bool waits = !first_and_fits();
  if (!freed_.wait_for(lock, max_wait, first_and_fits)) {
    queue_.remove(ticket);
    ++counters_.refused_busy;
    freed_.notify_all();  // the next in line may fit now
    throw FarmError(ErrorCode::resource_exhausted,
                    what + ": checking it needs " + submit_budget_mib(bytes) + "; " +
                        submit_budget_mib(counters_.reserved_bytes) + " of the server's " +
                        submit_budget_mib(capacity_) +
                        " submit memory budget (server flag --submit-memory-mb) stayed taken"
                        " by other submits; try again");
  }
  queue_.pop_front();
  counters_.reserved_bytes += bytes;
  counters_.peak_reserved_bytes = std::max(counters_.peak_reserved_bytes, counters_.reserved_bytes);
  ++counters_.admitted;
  counters_.waited += waits ? 1 : 0;
  freed_.notify_all();  // the next in line may fit beside this one
  return Reservation(this, bytes);
}

void SubmitBudget::release(uint64_t bytes) {
  {
    std::lock_guard lock(mutex_);
    counters_.reserved_bytes -= bytes;
  }
  freed_.notify_all();
}

SubmitBudget::Counters SubmitBudget::counters() const {
  std::lock_guard lock(mutex_);
  Counters out = counters_;
  out.capacity_bytes = capacity_;
  out.waiting = queue_.size();
  return out;
}

SubmitCost submit_check_cost(const v1::SceneBundle& bundle, uint64_t max_texture_values) {
  SubmitCost cost;
  uint64_t bundle_bytes = 0;
  for (const v1::BundleFile& file : bundle.files()) {
    bundle_bytes += file.data().size();
    if (file.path() == bundle.scene_file()) continue;
    const uint64_t bytes = submit_file_cost(file.path(), file.data(), max_texture_values);
    cost.bytes += bytes;
    if (bytes > cost.largest_file_bytes) {
      cost.largest_file = file.path();
      cost.largest_file_bytes = bytes;
    }
  }
  cost.bytes += 3 * bundle_bytes;
  return cost;
}

}  // namespace tessera::server
