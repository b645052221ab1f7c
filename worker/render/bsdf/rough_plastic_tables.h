// The rough plastic tables of one scene, one per distinct coating: a table depends only on
// (distribution, alpha, eta) (not on the colours, `nonlinear` or `sample_visible`), and costs
// ~0.35 s of CPU (spread over the caller's TBB threads), so a scene with many rough plastics of
// few coatings builds few tables.
#pragma once

#include <cstddef>
#include <map>
#include <memory>
#include <tuple>

#include "render/bsdf/rough_plastic.h"

namespace tessera {

/// Owned by the scene being built (TraceableScene): nothing is shared between scenes or
/// renders. Not thread-safe (a scene's materials are made on one thread).
class RoughPlasticTables {
 public:
  /// The table of these parameters, computed on first request. alpha and eta must be finite
  /// and > 0. The pointer stays valid as long as this object.
  const RoughPlasticTable* get(MicrofacetDistribution distribution, float alpha, float eta);
  /// How many tables were computed.
  size_t size() const { return tables_.size(); }

 private:
  using Key = std::tuple<MicrofacetDistribution, float, float>;
  std::map<Key, std::unique_ptr<const RoughPlasticTable>> tables_;
};

}  // namespace tessera
