#include "core/atomic_file.hpp"

#include <atomic>
#include <system_error>

#include <unistd.h>

#include "core/error.hpp"

namespace glmbslam {

std::filesystem::path temporary_path_for(const std::filesystem::path& target) {
  static std::atomic<unsigned> counter{0};
  auto tmp = target;
  tmp += ".tmp." + std::to_string(::getpid()) + "." + std::to_string(counter++);
  return tmp;
}

void commit_temporary(const std::filesystem::path& temporary, const std::filesystem::path& target) {
  std::error_code ec;
  std::filesystem::rename(temporary, target, ec);
  if (ec) {
    std::filesystem::remove(temporary, ec);
    throw InputError(target.string(), "cannot be written (rename from temporary file failed)");
  }
}

void write_text_file_atomically(const std::filesystem::path& target,
                                const std::function<void(std::ostream&)>& fill) {
  const auto tmp = temporary_path_for(target);
  try {
    std::ofstream out(tmp);
    if (!out) throw InputError(target.string(), "cannot open for writing");
    fill(out);
    out.flush();
    if (!out) throw InputError(target.string(), "write failed (disk full?)");
  } catch (...) {
    std::error_code ec;
    std::filesystem::remove(tmp, ec);
    throw;
  }
  commit_temporary(tmp, target);
}

void ensure_writable_directory(const std::filesystem::path& dir) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec || !std::filesystem::is_directory(dir)) {
    throw InputError(dir.string(),
                     "output folder cannot be created" + (ec ? " (" + ec.message() + ")" : std::string()));
  }
  if (::access(dir.c_str(), W_OK) != 0) {
    throw InputError(dir.string(), "output folder is not writable");
  }
}

}  // namespace glmbslam
