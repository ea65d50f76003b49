// Typed errors of hedra. Messages name what is wrong and where, in plain words. Every error
// hedra throws derives from hedra::Error (a std::runtime_error), so a caller can catch them
// all in one place and still tell them apart.
#pragma once

#include <stdexcept>
#include <string>

namespace hedra {

/// The base of every error hedra throws.
class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Input that violates a documented precondition: an invalid body, a malformed file, NaN.
/// The CLI prints what() on one line and exits with code 3.
class InvalidInput : public Error {
 public:
  using Error::Error;
};

/// A file that cannot be opened, read or written.
class IoError : public Error {
 public:
  using Error::Error;
};

/// Long work stopped because its progress callback asked to (the `progress` of
/// DecomposeOptions, HlrOptions, ShadowOptions, RenderOptions): no partial result is returned.
/// The CLI prints the message on one line and exits with code 130 (interrupted).
class Cancelled : public Error {
 public:
  explicit Cancelled(const std::string& what = "cancelled") : Error(what) {}
};

/// A decomposition stopped because its progress callback asked to (DecomposeOptions::progress).
class DecompositionCancelled : public Cancelled {
 public:
  DecompositionCancelled() : Cancelled("decomposition cancelled") {}
};

/// The floating-point decomposition variant failed (a crack, a broken piece, a loop that found
/// no cut).
class DecompositionFailed : public Error {
 public:
  explicit DecompositionFailed(const std::string& why)
      : Error("floating-point decomposition failed: " + why) {}
};

/// A broken internal invariant (HEDRA_ASSERT): a bug in hedra, not bad input. The CLI prints
/// "internal error: …" and exits with code 1.
class InternalError : public Error {
 public:
  using Error::Error;
};

namespace detail {
/// Throws InternalError(what). The target of HEDRA_ASSERT.
[[noreturn]] void assertion_failed(const char* what);
/// Whether HEDRA_EXPENSIVE_ASSERT checks run: when the environment variable
/// HEDRA_EXPENSIVE_CHECKS is set to a value other than 0 (the test suite sets it), read once.
bool expensive_checks();
}  // namespace detail

}  // namespace hedra

/// An internal invariant: throws hedra::InternalError(msg) when cond is false, in every build
/// (the checks are cheap, and a wrong result is worse than an error). msg: a string literal.
#define HEDRA_ASSERT(cond, msg)                                   \
  do {                                                            \
    if (!(cond)) ::hedra::detail::assertion_failed(msg);          \
  } while (false)

/// A code path an invariant rules out: throws hedra::InternalError(msg).
#define HEDRA_UNREACHABLE(msg) ::hedra::detail::assertion_failed(msg)

/// An invariant too costly to check on every call (O(n) or more on top of the work): checked
/// only when detail::expensive_checks() (the tests), else cond is not evaluated.
#define HEDRA_EXPENSIVE_ASSERT(cond, msg)                                            \
  do {                                                                               \
    if (::hedra::detail::expensive_checks() && !(cond))                              \
      ::hedra::detail::assertion_failed(msg);                                        \
  } while (false)
