#include <gtest/gtest.h>

#include <atomic>
#include <vector>

#include "engine/core/error.h"
#include "engine/core/parallel.h"

using namespace cumulo;

TEST(Parallel, VisitsEveryIndexOnce) {
  std::vector<std::atomic<int>> hits(10007);
  parallel_for(hits.size(), [&](size_t b, size_t e) {
    for (size_t i = b; i < e; ++i) hits[i]++;
  });
  for (auto& h : hits) ASSERT_EQ(h.load(), 1);
}

TEST(Parallel, PropagatesExceptions) {
  EXPECT_THROW(parallel_for(1000, [](size_t b, size_t) {
                 if (b > 500) throw Error("boom");
               }),
               Error);
}
