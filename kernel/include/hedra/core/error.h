// Typed errors of hedra. Messages name what is wrong and where, in plain words.
#pragma once

#include <stdexcept>
#include <string>

namespace hedra {

/// Input that violates a documented precondition: an invalid body, a malformed file, NaN.
/// The CLI prints what() on one line and exits with code 3.
class InvalidInput : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// A file that cannot be opened, read or written.
class IoError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace hedra
