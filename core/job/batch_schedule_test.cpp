#include "job/batch_schedule.h"

#include <gtest/gtest.h>

#include <bit>
#include <vector>

#include "job/job_plan.h"

namespace tessera {
namespace {

std::vector<std::pair<uint32_t, uint32_t>> ranges(const BatchSchedule& s) {
  std::vector<std::pair<uint32_t, uint32_t>> out;
  for (uint32_t b = 0; b < s.count(); ++b) out.emplace_back(s.begin(b), s.end(b));
  return out;
}

using Ranges = std::vector<std::pair<uint32_t, uint32_t>>;

TEST(BatchSchedule, ProgressiveDoublesToTheCapThenStaysThere) {
  EXPECT_EQ(ranges({BatchKind::progressive, 4, 16}),
            (Ranges{{0, 1}, {1, 2}, {2, 4}, {4, 8}, {8, 12}, {12, 16}}));
  // The last batch is short.
  EXPECT_EQ(ranges({BatchKind::progressive, 4, 10}),
            (Ranges{{0, 1}, {1, 2}, {2, 4}, {4, 8}, {8, 10}}));
  // spp below the cap: the doubling stops at spp.
  EXPECT_EQ(ranges({BatchKind::progressive, 256, 5}), (Ranges{{0, 1}, {1, 2}, {2, 4}, {4, 5}}));
  EXPECT_EQ(ranges({BatchKind::progressive, 256, 1}), (Ranges{{0, 1}}));
  EXPECT_EQ(ranges({BatchKind::progressive, 1, 3}), (Ranges{{0, 1}, {1, 2}, {2, 3}}));
  // A default 256-spp job at 64-px tiles: 9 rounds, each doubling every tile's samples.
  EXPECT_EQ(BatchSchedule({BatchKind::progressive, 256, 256}).count(), 9u);
}

TEST(BatchSchedule, FixedIsEqualSlices) {
  EXPECT_EQ(ranges({BatchKind::fixed, 4, 10}), (Ranges{{0, 4}, {4, 8}, {8, 10}}));
  EXPECT_EQ(ranges({BatchKind::fixed, 3, 3}), (Ranges{{0, 3}}));
}

// Every schedule tiles [0, spp) without gap or overlap; every progressive batch that is not the
// short last one is an aligned power-of-two block (a (0,k,2)-net of the sampler).
TEST(BatchSchedule, CoversEverySampleOnceInAlignedBlocks) {
  for (BatchKind kind : {BatchKind::fixed, BatchKind::progressive}) {
    for (uint32_t cap : {1u, 2u, 8u, 64u, 1024u}) {
      for (uint32_t spp : {1u, 2u, 3u, 7u, 8u, 9u, 100u, 1000u, 4096u, 5000u}) {
        const BatchSchedule s{kind, cap, spp};
        uint32_t next = 0;
        for (uint32_t b = 0; b < s.count(); ++b) {
          ASSERT_EQ(s.begin(b), next) << "cap " << cap << " spp " << spp << " batch " << b;
          ASSERT_LT(s.begin(b), s.end(b)) << "empty batch " << b;
          const uint32_t size = s.end(b) - s.begin(b);
          if (kind == BatchKind::progressive && s.end(b) < spp) {
            EXPECT_TRUE(std::has_single_bit(size)) << "batch " << b << " size " << size;
            EXPECT_EQ(s.begin(b) % size, 0u) << "batch " << b << " not aligned";
            EXPECT_LE(size, cap);
          }
          next = s.end(b);
          EXPECT_EQ(s.spp_after(b + 1), next);
        }
        EXPECT_EQ(next, spp) << "cap " << cap << " spp " << spp;
        EXPECT_EQ(s.spp_after(0), 0u);
        EXPECT_EQ(s.end(s.count() + 5), spp);  // clamped past the end
      }
    }
  }
}

TEST(BatchSchedule, KindNamesRoundTrip) {
  for (BatchKind k : {BatchKind::fixed, BatchKind::progressive}) {
    EXPECT_EQ(batch_kind_from_string(to_string(k)), k);
  }
  EXPECT_FALSE(batch_kind_from_string("geometric").has_value());
}

TEST(JobPlan, DefaultIsProgressiveWithAPowerOfTwoCap) {
  const JobPlan p = make_job_plan(192, 192, 64, 256, 0);
  EXPECT_EQ(p.batch_kind, BatchKind::progressive);
  EXPECT_EQ(p.batch_spp, 256u);  // 2^20 samples / 4096 pixels
  EXPECT_EQ(p.batch_count(), 9u);
  // The cap never exceeds spp rounded up to a power of two.
  EXPECT_EQ(make_job_plan(192, 192, 64, 100, 0).batch_spp, 128u);
  // --batch fixes every batch.
  const JobPlan fixed = make_job_plan(192, 192, 64, 256, 16);
  EXPECT_EQ(fixed.batch_kind, BatchKind::fixed);
  EXPECT_EQ(fixed.batch_count(), 16u);
  // A stored progressive job keeps its cap; a cap that is not a power of two is refused.
  EXPECT_EQ(make_job_plan(192, 192, 64, 256, 64, BatchKind::progressive).batch_count(), 1u + 6u + 3u);
  EXPECT_THROW(make_job_plan(192, 192, 64, 256, 48, BatchKind::progressive),
               std::invalid_argument);
}

}  // namespace
}  // namespace tessera
