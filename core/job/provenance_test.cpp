// The provenance keys (provenance.h): one set, local or farm; the facts one side alone knows are
// written only when set.
#include "job/provenance.h"

#include <gtest/gtest.h>

#include <set>
#include <stdexcept>

namespace tessera {
namespace {

JobOptions provenance_noise_options() {
  JobOptions o;
  o.width = 64;
  o.height = 48;
  o.spp = 1024;
  o.rule = StopRule::noise;
  o.noise_target = 0.02;
  o.max_depth = 8;
  o.seed = 7;
  o.tile_size = 32;
  o.batch_spp = 16;
  o.batch_kind = BatchKind::fixed;
  return o;
}

Provenance provenance_shared_facts(const JobOptions& options) {
  Provenance p;
  p.scene_file = "cornell.json";
  p.renderer = "tessera 0.1.0 (abc, GNU 12.2.0)";
  p.isa = "avx2";
  p.options = &options;
  p.stop_reason = StopReason::noise_target;
  p.spp = 96;
  p.reached.spp_min = 96;
  p.reached.spp_max = 512;
  p.reached.spp_mean = 230.5;
  p.reached.error_max = 0.019;
  p.reached.error_mean = 0.012;
  p.nan_dropped = 1;
  p.inf_dropped = 2;
  p.wall_time_s = 3.5;
  return p;
}

std::set<std::string> provenance_keys(const std::map<std::string, std::string>& m) {
  std::set<std::string> keys;
  for (const auto& [key, value] : m) keys.insert(key);
  return keys;
}

TEST(Provenance, LocalAndFarmWriteTheSameKeysForTheSameFacts) {
  const JobOptions options = provenance_noise_options();
  Provenance local = provenance_shared_facts(options);
  local.kernel_isa = "avx512";
  local.estimated_relative_error = 0.015;
  Provenance farm = provenance_shared_facts(options);
  farm.job_id = 12;
  farm.scene_sha256 = std::string(64, 'a');
  farm.options_json = "{}";
  farm.samples_merged = 1234;

  const auto l = provenance_metadata(local), f = provenance_metadata(farm);
  for (const std::string& key : provenance_keys(provenance_metadata(provenance_shared_facts(options)))) {
    ASSERT_TRUE(l.count(key) && f.count(key)) << key;
    EXPECT_EQ(l.at(key), f.at(key)) << key;
  }
  EXPECT_EQ(l.at("tessera:nan_dropped"), "1");
  EXPECT_EQ(l.at("tessera:inf_dropped"), "2");
  EXPECT_EQ(l.at("tessera:renderer_version"), "tessera 0.1.0 (abc, GNU 12.2.0)");
  EXPECT_EQ(l.at("tessera:noise_target"), std::to_string(0.02));
  EXPECT_EQ(l.at("tessera:max_spp"), "1024");
  EXPECT_EQ(l.at("tessera:stop_reason"), "noise_target");
  // What one side alone knows.
  EXPECT_EQ(l.at("tessera:kernel_isa"), "avx512");
  EXPECT_EQ(l.count("tessera:job_id"), 0u);
  EXPECT_EQ(l.count("tessera:samples_merged"), 0u);
  EXPECT_EQ(f.at("tessera:job_id"), "12");
  EXPECT_EQ(f.at("tessera:samples_merged"), "1234");
  EXPECT_EQ(f.count("tessera:kernel_isa"), 0u);
  EXPECT_EQ(f.count("tessera:estimated_relative_error"), 0u);
}

TEST(Provenance, AnSppJobHasNoTargetBudgetOrCap) {
  JobOptions options = provenance_noise_options();
  options.rule = StopRule::spp;
  Provenance p = provenance_shared_facts(options);
  p.wall_time_s.reset();
  const auto m = provenance_metadata(p);
  EXPECT_EQ(m.at("tessera:stop_rule"), "spp");
  EXPECT_EQ(m.count("tessera:noise_target"), 0u);
  EXPECT_EQ(m.count("tessera:time_budget_s"), 0u);
  EXPECT_EQ(m.count("tessera:max_spp"), 0u);
  EXPECT_EQ(m.count("tessera:wall_time_s"), 0u);
}

TEST(Provenance, NoOptionsIsAnError) {
  Provenance p;
  EXPECT_THROW(provenance_metadata(p), std::invalid_argument);
}

}  // namespace
}  // namespace tessera
