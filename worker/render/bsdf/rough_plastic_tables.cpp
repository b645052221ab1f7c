#include "render/bsdf/rough_plastic_tables.h"

#include <cmath>
#include <stdexcept>
#include <string>

namespace tessera {

const RoughPlasticTable* RoughPlasticTables::get(MicrofacetDistribution distribution, float alpha,
                                                 float eta) {
  if (!(alpha > 0) || !(eta > 0) || !std::isfinite(alpha) || !std::isfinite(eta)) {
    // A NaN key would break the map's ordering.
    throw std::invalid_argument("rough plastic table: alpha " + std::to_string(alpha) +
                                " and eta " + std::to_string(eta) + " must be finite and > 0");
  }
  std::unique_ptr<const RoughPlasticTable>& table = tables_[Key{distribution, alpha, eta}];
  if (!table) {
    table = std::make_unique<const RoughPlasticTable>(
        make_rough_plastic_table(distribution, alpha, eta));
  }
  return table.get();
}

}  // namespace tessera
