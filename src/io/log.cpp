#include "io/log.hpp"

#include <unistd.h>

#include <cerrno>
#include <string>

namespace cs {

void log_line(std::string_view line) noexcept {
  try {
    std::string text(line);
    text += '\n';
    std::size_t done = 0;
    while (done < text.size()) {
      const ssize_t n = ::write(STDERR_FILENO, text.data() + done, text.size() - done);
      if (n < 0 && errno == EINTR) continue;
      if (n <= 0) return;  // ENOSPC, EPIPE (SIGPIPE is ignored: main.cpp), EBADF: dropped
      done += static_cast<std::size_t>(n);
    }
  } catch (...) {
  }
}

}  // namespace cs
