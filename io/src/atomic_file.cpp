#include "hedra/io/atomic_file.h"

#include <atomic>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <system_error>
#include <unistd.h>

#include "hedra/core/error.h"

namespace hedra::io {
namespace {

namespace fs = std::filesystem;

// A name next to `target` that no other writer (another process, another staged file of this
// one) uses.
fs::path temporary_name(const fs::path& target) {
  static std::atomic<int> counter{0};
  fs::path temp = target;
  temp += ".tmp-" + std::to_string(::getpid()) + "-" + std::to_string(counter++);
  return temp;
}

using Producer = std::function<void(const std::function<void(std::string_view)>& write)>;

// Writes what `produce` hands over to `file`; on any failure (or an exception from `produce`)
// the file is removed.
void write_produced(const fs::path& file, const std::string& name, const Producer& produce) {
  std::ofstream out(file, std::ios::binary | std::ios::trunc);
  if (!out) throw IoError(name + ": cannot open for writing");
  const auto discard = [&] {
    out.close();
    std::error_code ignored;
    fs::remove(file, ignored);
  };
  try {
    produce([&out](std::string_view bytes) { out.write(bytes.data(), static_cast<std::streamsize>(bytes.size())); });
  } catch (...) {
    discard();
    throw;
  }
  out.flush();
  if (!out) {
    discard();
    throw IoError(name + ": write error");
  }
}

void write_bytes(const fs::path& file, const std::string& name, const std::string& bytes) {
  write_produced(file, name, [&bytes](const std::function<void(std::string_view)>& write) { write(bytes); });
}

}  // namespace

void write_file_atomically(const std::string& path, const std::string& bytes) {
  OutputTransaction t;
  t.add(path, bytes);
  t.commit();
}

OutputTransaction::~OutputTransaction() {
  if (committed_) return;
  for (const Staged& s : staged_) {
    std::error_code ignored;
    fs::remove_all(s.temp, ignored);
  }
}

void OutputTransaction::add(const std::string& path, const std::string& bytes) {
  add(path, [&bytes](const std::function<void(std::string_view)>& write) { write(bytes); });
}

void OutputTransaction::add(const std::string& path, const Producer& produce) {
  const fs::path target(path);
  std::error_code ec;
  if (fs::is_directory(target, ec)) throw IoError(path + ": is a directory");
  const fs::path temp = temporary_name(target);
  write_produced(temp, path, produce);
  staged_.push_back({temp, target, path});
}

void OutputTransaction::add_directory(
    const std::string& dir, const std::vector<std::pair<std::string, std::string>>& files) {
  const fs::path target(dir);
  std::error_code ec;
  const fs::file_status status = fs::status(target, ec);
  if (fs::exists(status)) {
    if (!fs::is_directory(status))
      throw IoError(dir + ": exists and is not a directory (give a directory for the output files)");
    for (const auto& [name, bytes] : files) add((target / name).string(), bytes);
    return;
  }
  const fs::path temp = temporary_name(target);
  if (!fs::create_directory(temp, ec) || ec)
    throw IoError(dir + ": cannot create the directory" + (ec ? ": " + ec.message() : ""));
  staged_.push_back({temp, target, dir});  // removed with everything in it on failure
  for (const auto& [name, bytes] : files)
    write_bytes(temp / name, (target / name).string(), bytes);
}

void OutputTransaction::commit() {
  for (const Staged& s : staged_) {
    std::error_code ec;
    fs::rename(s.temp, s.target, ec);
    if (ec) throw IoError(s.name + ": cannot put the output in place: " + ec.message());
  }
  committed_ = true;
}

}  // namespace hedra::io
