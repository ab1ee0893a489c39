#include "core/atomic_file.h"

#include <fcntl.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>
#include <exception>
#include <system_error>

#include <fmt/format.h>

#include "core/error.h"

namespace furnace {

namespace {

// Collisions come only from stale temporaries of a dead process that had our
// pid; a handful of retries with the next counter value gets past them.
constexpr int kMaxNameAttempts = 100;

// Error texts from the C library and OpenEXR sometimes end with a period and
// sometimes hold two sentences; the message must stay one sentence.
std::string as_clause(std::string text) {
  while (!text.empty() && (text.back() == '.' || text.back() == ' ' || text.back() == '\n')) text.pop_back();
  for (size_t at = text.find(". "); at != std::string::npos; at = text.find(". ", at)) text.replace(at, 2, "; ");
  return text;
}

// Creates an empty file under a name unique to this process and call, next to
// `path`, and returns its name.
std::filesystem::path create_temporary_next_to(const std::filesystem::path& path, std::string_view what) {
  static std::atomic<unsigned> counter{0};
  const std::filesystem::path dir = path.parent_path();
  for (int attempt = 0; attempt < kMaxNameAttempts; ++attempt) {
    const std::filesystem::path tmp =
        dir / fmt::format(".{}.tmp-{}-{}", path.filename().string(), ::getpid(), counter++);
    const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    if (fd >= 0) {
      ::close(fd);
      return tmp;
    }
    if (errno != EEXIST)
      throw Error(fmt::format("cannot write {} '{}': cannot create a temporary file in '{}' ({}).", what,
                              path.string(), dir.empty() ? "." : dir.string(), std::strerror(errno)));
  }
  throw Error(fmt::format("cannot write {} '{}': no unused temporary file name after {} attempts.", what,
                          path.string(), kMaxNameAttempts));
}

// Flushes the file's data to the device, so the rename never publishes a
// file whose blocks are not yet written.
void sync_file(const std::filesystem::path& file) {
  const int fd = ::open(file.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) throw std::system_error(errno, std::generic_category(), "cannot reopen the temporary file");
  const int rc = ::fsync(fd);
  const int saved = errno;
  ::close(fd);
  if (rc != 0) throw std::system_error(saved, std::generic_category(), "cannot flush the temporary file");
}

}  // namespace

void write_file_atomically(const std::filesystem::path& path,
                           const std::function<void(const std::filesystem::path& temporary)>& write_to,
                           std::string_view what) {
  if (path.empty()) throw Error(fmt::format("cannot write {}: the file name is empty.", what));
  const std::filesystem::path tmp = create_temporary_next_to(path, what);
  auto remove_temporary = [&] {
    std::error_code ignored;
    std::filesystem::remove(tmp, ignored);
  };
  try {
    write_to(tmp);
    sync_file(tmp);
    std::filesystem::rename(tmp, path);
  } catch (const Error&) {
    remove_temporary();
    throw;
  } catch (const std::exception& e) {
    remove_temporary();
    throw Error(fmt::format("cannot write {} '{}': {}.", what, path.string(), as_clause(e.what())));
  }
}

void write_text_file_atomically(const std::filesystem::path& path, const std::string& text, std::string_view what) {
  write_file_atomically(
      path,
      [&](const std::filesystem::path& tmp) {
        const int fd = ::open(tmp.c_str(), O_WRONLY | O_TRUNC | O_CLOEXEC);
        if (fd < 0) throw std::system_error(errno, std::generic_category(), "cannot open the temporary file");
        size_t written = 0;
        while (written < text.size()) {
          const ssize_t n = ::write(fd, text.data() + written, text.size() - written);
          if (n < 0 && errno == EINTR) continue;
          if (n < 0) {
            const int saved = errno;
            ::close(fd);
            throw std::system_error(saved, std::generic_category(), "cannot write the temporary file");
          }
          written += size_t(n);
        }
        if (::close(fd) != 0) throw std::system_error(errno, std::generic_category(), "cannot close the temporary file");
      },
      what);
}

}  // namespace furnace
