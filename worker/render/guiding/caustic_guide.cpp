#include "render/guiding/caustic_guide.h"

#include <algorithm>
#include <utility>

#include <glm/geometric.hpp>

namespace tessera {

CausticGuide CausticGuide::on_grid(float cell_side) {
  CausticGuide guide;
  guide.inv_cell_ = 1.0f / cell_side;
  return guide;
}

std::vector<CausticGuide::Candidate> CausticGuide::group(std::vector<Deposit> deposits) {
  // Deposits grouped by cell, then by bin, each group summed in photon order (a stable sort
  // keeps it), so the same bits on every machine.
  std::stable_sort(deposits.begin(), deposits.end(), [](const Deposit& a, const Deposit& b) {
    return a.key != b.key ? a.key < b.key : a.bin < b.bin;
  });
  std::vector<Candidate> candidates;
  for (size_t begin = 0; begin < deposits.size();) {
    size_t end = begin;
    while (end < deposits.size() && deposits[end].key == deposits[begin].key) ++end;
    if (end - begin >= kMinPhotons) {
      Candidate c;
      c.key = deposits[begin].key;
      c.photons = uint32_t(end - begin);
      glm::dvec3 position(0.0), normal(0.0);
      for (size_t j = begin; j < end; ++j) {
        position += glm::dvec3(deposits[j].p);
        normal += glm::dvec3(deposits[j].ng);
      }
      c.position = glm::vec3(position / double(end - begin));
      c.normal = glm::length(normal) > 0 ? glm::vec3(glm::normalize(normal)) : deposits[begin].ng;
      for (size_t j = begin; j < end;) {
        float sum = 0;
        size_t next = j;
        while (next < end && deposits[next].bin == deposits[j].bin) sum += deposits[next++].weight;
        c.bins.emplace_back(deposits[j].bin, sum);
        c.total += sum;
        j = next;
      }
      candidates.push_back(std::move(c));
    }
    begin = end;
  }
  return candidates;
}

void CausticGuide::keep(const std::vector<Candidate>& candidates, const std::vector<float>& indirect,
                        float power_to_irradiance, uint64_t deposited) {
  photons_deposited_ = deposited;
  std::vector<uint64_t> cell_keys;
  for (size_t c = 0; c < candidates.size(); ++c) {
    const Candidate& candidate = candidates[c];
    const float e_caustic = candidate.total * power_to_irradiance;
    const float p = e_caustic / (e_caustic + indirect[c]);
    if (!(p >= kMinProbability)) continue;
    Cell cell;
    cell.photons = candidate.photons;
    cell.position = candidate.position;
    cell.normal = candidate.normal;
    cell.probability = std::min(p, kMaxProbability);
    cell.first = uint32_t(bin_ids_.size());
    cell.count = uint32_t(candidate.bins.size());
    float cdf = 0;
    for (const auto& [bin, sum] : candidate.bins) {
      bin_ids_.push_back(bin);
      prob_.push_back(sum / candidate.total);
      cdf += prob_.back();
      cdf_.push_back(cdf);
    }
    cdf_.back() = 1.0f;
    cells_.push_back(cell);
    cell_keys.push_back(candidate.key);
    photons_kept_ += cell.photons;
  }

  // The table from cell keys to cells: open addressing, at most half full.
  size_t capacity = 16;
  while (capacity < 2 * cell_keys.size()) capacity *= 2;
  mask_ = capacity - 1;
  keys_.assign(capacity, kEmptyKey);
  slot_cell_.assign(capacity, -1);
  for (size_t c = 0; c < cell_keys.size(); ++c) {
    uint64_t s = mix64(cell_keys[c]) & mask_;
    while (keys_[s] != kEmptyKey) s = (s + 1) & mask_;
    keys_[s] = cell_keys[c];
    slot_cell_[s] = int32_t(c);
  }
}

}  // namespace tessera
