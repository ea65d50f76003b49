#include "hedra/core/parallel.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>
#include <tbb/task_group.h>

#include <algorithm>
#include <thread>

namespace hedra {

int bounded_threads(int requested) {
  const int hardware = std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
  if (requested <= 0) return hardware;
  // More workers than 4 per hardware thread only add scheduling; far more exhaust memory.
  return std::clamp(requested, 1, 4 * hardware);
}

void parallel_blocks(size_t n, int threads, size_t grain,
                     const std::function<void(size_t, size_t)>& f) {
  if (n == 0) return;
  // One block in the current arena: no task (decompositions build many Bodies of a few faces).
  if (threads == 1 || (threads <= 0 && n <= grain)) {
    f(0, n);
    return;
  }
  const auto run = [&] {
    tbb::parallel_for(tbb::blocked_range<size_t>(0, n, std::max<size_t>(grain, 1)),
                      [&](const tbb::blocked_range<size_t>& r) { f(r.begin(), r.end()); });
  };
  if (threads <= 0) {
    run();
    return;
  }
  tbb::task_arena arena(bounded_threads(threads));
  arena.execute(run);
}

void run_alongside(const std::function<void()>& side, const std::function<void()>& main) {
  tbb::task_group group;
  group.run([&side] { side(); });
  try {
    main();
  } catch (...) {
    group.wait();
    throw;
  }
  group.wait();
}

void with_threads(int threads, const std::function<void()>& f) {
  if (threads <= 0) {
    f();
    return;
  }
  tbb::task_arena arena(bounded_threads(threads));
  arena.execute(f);
}

}  // namespace hedra
