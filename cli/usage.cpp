#include "cli/usage.h"

#include <CLI/CLI.hpp>
#include <cmath>
#include <cstdio>

namespace hedra::cli {
namespace {

constexpr size_t kMaxTokenBytes = 200;

// Length of the valid UTF-8 sequence starting at s[i], or 0 when it is not one.
size_t utf8_length(const std::string& s, size_t i) {
  const auto byte = [&](size_t k) { return static_cast<unsigned char>(s[k]); };
  const unsigned char c = byte(i);
  size_t n = 0;
  unsigned min = 0;
  if (c < 0x80) return 1;
  if ((c & 0xE0) == 0xC0) n = 2, min = 0x80;
  else if ((c & 0xF0) == 0xE0) n = 3, min = 0x800;
  else if ((c & 0xF8) == 0xF0) n = 4, min = 0x10000;
  else return 0;
  if (i + n > s.size()) return 0;
  unsigned code = c & (0x7F >> n);
  for (size_t k = 1; k < n; ++k) {
    if ((byte(i + k) & 0xC0) != 0x80) return 0;
    code = (code << 6) | (byte(i + k) & 0x3F);
  }
  if (code < min || code > 0x10FFFF || (code >= 0xD800 && code <= 0xDFFF)) return 0;
  return n;
}

}  // namespace

CLI::Option* add_threads_option(CLI::App& app, int& threads) {
  return app.add_option("--threads", threads, "worker threads, 1 to 1024 (default 0: all)")
      ->check(CLI::Range(0, kMaxThreads));
}

std::string sanitize_message(const std::string& message) {
  std::string out;
  out.reserve(message.size());
  size_t token = 0;  // bytes of the current run without a space, as written
  bool cut = false;  // the current run has been cut
  char buf[8];
  for (size_t i = 0; i < message.size();) {
    const unsigned char c = static_cast<unsigned char>(message[i]);
    if (c == ' ') {
      out += ' ';
      token = 0;
      cut = false;
      ++i;
      continue;
    }
    std::string piece;
    size_t n = utf8_length(message, i);
    if (n == 0) {
      std::snprintf(buf, sizeof buf, "\\x%02x", c);
      piece = buf;
      n = 1;
    } else if (n == 1 && (c < 0x20 || c == 0x7F)) {
      if (c == '\n') piece = "\\n";
      else if (c == '\t') piece = "\\t";
      else if (c == '\r') piece = "\\r";
      else {
        std::snprintf(buf, sizeof buf, "\\x%02x", c);
        piece = buf;
      }
    } else {
      piece = message.substr(i, n);
    }
    i += n;
    if (cut) continue;
    if (token + piece.size() > kMaxTokenBytes) {
      out += "…";
      cut = true;
      continue;
    }
    out += piece;
    token += piece.size();
  }
  return out;
}

std::string format_number(double value) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", value);
  return buf;
}

CLI::Validator finite_number(bool positive) {
  return CLI::Validator(
      [positive](std::string& text) -> std::string {
        double v = 0;
        if (!CLI::detail::lexical_cast(text, v)) return "'" + text + "' is not a number";
        if (!std::isfinite(v) || v < 0 || (positive && v == 0))
          return "expected a finite " + std::string(positive ? "positive" : "non-negative") +
                 " number, got '" + text + "'";
        return "";
      },
      positive ? "POSITIVE" : "NON-NEGATIVE");
}

}  // namespace hedra::cli
