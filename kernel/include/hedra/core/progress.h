// Progress and cancellation of long work (decomposition, hidden lines, shadows, rendering).
// A caller passes a ProgressCallback in the options; the work reports the fraction done and
// stops with hedra::Cancelled (hedra/core/error.h) as soon as the callback returns false,
// leaving no partial result.
#pragma once

#include <atomic>
#include <chrono>
#include <functional>
#include <mutex>
#include <thread>

#include "hedra/core/error.h"

namespace hedra {

/// Called with the fraction of the work done, 0 … 1, always on the thread that started the
/// work, at most about every 20 ms and once at the end of each stage; returning false cancels
/// (the work then throws Cancelled).
using ProgressCallback = std::function<bool(double done)>;

/// Counts units of work done by any thread of a parallel pass and relays them to a
/// ProgressCallback on the thread that created the meter. Thread-safe; with no callback every
/// call costs one relaxed atomic add. The stage's units are set by `stage`.
class ProgressMeter {
 public:
  /// `callback` may be empty (no reports, never cancelled). `what` names the cancelled work in
  /// the message of Cancelled.
  explicit ProgressMeter(ProgressCallback callback, const char* what = "cancelled")
      : callback_(std::move(callback)), what_(what), owner_(std::this_thread::get_id()),
        last_(std::chrono::steady_clock::now()) {}

  /// Starts a stage covering the fraction [from, to) of the whole, of `units` units.
  void stage(double from, double to, double units) {
    from_ = from;
    to_ = to;
    units_ = units > 0 ? units : 1;
    done_.store(0, std::memory_order_relaxed);
  }

  /// `units` more done. On the owner thread, reports now and then; on any thread, throws
  /// Cancelled once cancelled. Cost O(1).
  void add(double units = 1) {
    if (!callback_) return;
    done_.fetch_add(static_cast<long long>(units), std::memory_order_relaxed);
    if (cancelled_.load(std::memory_order_relaxed)) throw Cancelled(what_);
    if (std::this_thread::get_id() != owner_) return;
    const auto now = std::chrono::steady_clock::now();
    if (now - last_ < std::chrono::milliseconds(20)) return;
    last_ = now;
    report(fraction());
  }

  /// Reports the end of the current stage (owner thread). \throw Cancelled.
  void finish_stage() {
    if (!callback_) return;
    if (cancelled_.load(std::memory_order_relaxed)) throw Cancelled(what_);
    report(to_);
  }

  /// Throws Cancelled when a report asked to stop (any thread). Cost O(1).
  void check() const {
    if (cancelled_.load(std::memory_order_relaxed)) throw Cancelled(what_);
  }

  bool active() const { return static_cast<bool>(callback_); }

 private:
  double fraction() const {
    const double f = static_cast<double>(done_.load(std::memory_order_relaxed)) / units_;
    return from_ + (to_ - from_) * (f < 1 ? f : 1);
  }
  void report(double f) {
    if (!callback_(f)) {
      cancelled_.store(true, std::memory_order_relaxed);
      throw Cancelled(what_);
    }
  }

  ProgressCallback callback_;
  const char* what_;
  std::thread::id owner_;
  std::chrono::steady_clock::time_point last_;
  double from_ = 0, to_ = 1, units_ = 1;
  std::atomic<long long> done_{0};
  std::atomic<bool> cancelled_{false};
};

}  // namespace hedra
