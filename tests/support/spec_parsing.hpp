// What the spec parser's tests share (test_spec_parser.cpp, test_spec_refusals.cpp): a spec
// parsed as "test.toml", the message of the InputError it raises, two scenes' [scene] lines and
// a sweep.
#pragma once

#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "io/spec_parser.hpp"

namespace cs::test {

inline RunSpec parse(const std::string& text, const std::vector<std::string>& overrides = {}) {
  return parse_run_spec(text, overrides, "test.toml");
}

inline std::string message_of(const std::string& text,
                              const std::vector<std::string>& overrides = {}) {
  try {
    parse(text, overrides);
  } catch (const InputError& error) {
    return error.what();
  }
  return "(no InputError)";
}

inline void expect_input_error(const std::string& text, const std::string& fragment) {
  const std::string message = message_of(text);
  EXPECT_NE(message.find(fragment), std::string::npos) << message;
}

inline const std::string kDoubleWell = "[scene]\nname = \"double_well\"\n";
inline const std::string kCoupled = "[scene]\nname = \"coupled_oscillators\"\n";

// A double-well sweep over three axes, the one --set is tried on.
inline const std::string kSweep = kDoubleWell + R"(
[integrator]
h = 0.01
t_end = 100.0

[grid]
p_0 = { values = [0.0, 0.5] }
q_0 = { from = -3.0, to = 3.0, n = 512 }
gamma = { values = [0.1] }
)";

}  // namespace cs::test
