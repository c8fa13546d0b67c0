// Messages for the user on stderr that can never stop a run. A batch job's stderr may be a full
// disk, a closed pipe or /dev/full: a finished map must still be written, so a message that
// cannot be written is dropped, never thrown (fmt::print throws, and a throw from an error
// handler aborts the program).
#pragma once

#include <fmt/core.h>

#include <string_view>
#include <utility>

namespace cs {

// Writes `line` and a newline to stderr in one write where possible; ignores every failure.
void log_line(std::string_view line) noexcept;

template <class... Args>
void log(fmt::format_string<Args...> format, Args&&... args) noexcept {
  try {
    log_line(fmt::format(format, std::forward<Args>(args)...));
  } catch (...) {  // out of memory while formatting: the message is dropped, the run goes on
  }
}

}  // namespace cs
