#include "verify/export/atomic_file.h"

#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <system_error>

#include <fmt/format.h>

#include "core/error.h"

namespace furnace::exporter {

void write_file_atomically(const std::filesystem::path& path, const std::string& contents) {
  // Same directory as the destination, so the rename never crosses a file
  // system; pid and a counter keep concurrent writers apart.
  static std::atomic<unsigned> counter{0};
  const std::filesystem::path dir = path.has_parent_path() ? path.parent_path() : std::filesystem::path(".");
  const std::filesystem::path temp =
      dir / fmt::format(".{}.tmp-{}-{}", path.filename().string(), ::getpid(), counter++);

  std::FILE* file = std::fopen(temp.c_str(), "wb");
  if (!file)
    throw Error(fmt::format("cannot write '{}': cannot create '{}' ({}).", path.string(), temp.string(),
                            std::strerror(errno)));
  const bool written = std::fwrite(contents.data(), 1, contents.size(), file) == contents.size();
  const int write_errno = errno;
  const bool closed = std::fclose(file) == 0;
  if (!written || !closed) {
    std::remove(temp.c_str());
    throw Error(fmt::format("cannot write '{}' ({}).", path.string(), std::strerror(written ? errno : write_errno)));
  }
  std::error_code ec;
  std::filesystem::rename(temp, path, ec);
  if (ec) {
    std::remove(temp.c_str());
    throw Error(fmt::format("cannot write '{}': renaming '{}' over it failed ({}).", path.string(), temp.string(),
                            ec.message()));
  }
}

}  // namespace furnace::exporter
