// hedra/core/parallel.h: the parallel loop and run_alongside.
#include "hedra/core/parallel.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <numeric>
#include <stdexcept>
#include <vector>

namespace hedra {
namespace {

TEST(Parallel, ChunksCoverTheRangeOnceAtAnyThreadCount) {
  for (int threads : {1, 2, 0}) {
    std::vector<int> hits(10001, 0);
    with_threads(threads, [&] {
      parallel_chunks(hits.size(), 97, [&](size_t, size_t begin, size_t end) {
        for (size_t i = begin; i != end; ++i) ++hits[i];
      });
    });
    EXPECT_EQ(std::accumulate(hits.begin(), hits.end(), 0), 10001) << threads << " threads";
    EXPECT_EQ(*std::min_element(hits.begin(), hits.end()), 1);
  }
}

TEST(Parallel, RunAlongsideRunsBothAndWaitsForTheSide) {
  for (int threads : {1, 2}) {
    std::vector<long> side_sum(1, 0);
    std::atomic<long> main_sum{0};
    with_threads(threads, [&] {
      run_alongside([&] { for (long i = 1; i <= 100000; ++i) side_sum[0] += i; },
                    [&] {
                      parallel_for(1000, 0, [&](size_t i) { main_sum += static_cast<long>(i); });
                    });
    });
    EXPECT_EQ(side_sum[0], 5000050000L);  // complete when run_alongside returns
    EXPECT_EQ(main_sum.load(), 499500L);
  }
}

TEST(Parallel, RunAlongsidePassesOnExceptionsFromEitherSide) {
  bool side_ran = false;
  EXPECT_THROW(run_alongside([&] { side_ran = true; }, [] { throw std::runtime_error("main"); }),
               std::runtime_error);
  EXPECT_TRUE(side_ran);  // waited for before the exception left
  EXPECT_THROW(run_alongside([] { throw std::runtime_error("side"); }, [] {}), std::runtime_error);
}

}  // namespace
}  // namespace hedra
