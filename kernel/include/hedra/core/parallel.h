// The one parallel loop of hedra: every data-parallel pass (decomposition rounds, batch
// clipping, hidden lines, shadows, rendering) runs through it, so that thread counts mean the
// same everywhere and an absurd count can never reach the task scheduler. TBB stays private
// (kernel/src/core/parallel.cpp).
#pragma once

#include <cstddef>
#include <functional>

namespace hedra {

/// The number of workers a requested count means: ≤ 0 → every hardware thread; otherwise
/// the request clamped to [1, 4 × hardware threads]. Cost O(1).
int bounded_threads(int requested);

/// Calls f(begin, end) on disjoint blocks that cover [0, n), each of about `grain` indices or
/// more. threads = 1: one block, on the calling thread; threads ≤ 0: every thread of the
/// current scope (all, or the limit of an enclosing with_threads); k > 1: at most
/// bounded_threads(k). Exceptions thrown by f propagate to the caller. Callers write each
/// index's results to its own place, so results never depend on the thread count.
void parallel_blocks(size_t n, int threads, size_t grain,
                     const std::function<void(size_t begin, size_t end)>& f);

/// f(i) for every i in [0, n), with the threads of parallel_blocks (blocks of one index).
template <class F>
void parallel_for(size_t n, int threads, F&& f) {
  parallel_blocks(n, threads, 1, [&f](size_t begin, size_t end) {
    for (size_t i = begin; i != end; ++i) f(i);
  });
}

/// f(c, begin, end) for every fixed chunk c of [0, n): [c·chunk, min(n, (c + 1)·chunk)), with
/// the threads of parallel_blocks (threads ≤ 0). The chunks do not depend on the threads, so
/// per-chunk results (a first failure, a partial sum, a list) combined in chunk order are the
/// same at any thread count. There are (n + chunk − 1) / chunk chunks.
template <class F>
void parallel_chunks(size_t n, size_t chunk, F&& f) {
  parallel_for((n + chunk - 1) / chunk, 0, [&f, n, chunk](size_t c) {
    const size_t begin = c * chunk;
    f(c, begin, n - begin < chunk ? n : begin + chunk);
  });
}

/// Runs `side` and `main` possibly at the same time (side as a task of the current scope, main
/// on the calling thread, whose parallel loops the other workers join once side is done) and
/// returns when both are done. For a serial step whose result is needed only later, overlapped
/// with parallel work. An exception from either propagates (side's after main has finished).
void run_alongside(const std::function<void()>& side, const std::function<void()>& main);

/// Runs f so that every parallel loop inside it with threads ≤ 0 uses at most
/// bounded_threads(threads) workers (threads ≤ 0: no limit). For a pipeline of several loops
/// and nested library calls under one thread option (the renderer).
void with_threads(int threads, const std::function<void()>& f);

}  // namespace hedra
