// Every file in tests/fuzz/regressions/ (inputs the spec-parser fuzzer found, and nasty seeds)
// goes through parse_run_spec exactly as .ci/fuzz feeds it: the TOML text, then 0-2 --set
// overrides after NUL bytes (fuzz/spec_input.hpp). Each must give a RunSpec whose spec_text
// reads back to the same RunSpec, or a cs::InputError; nothing else. Under the sanitize preset
// this also catches the memory errors and undefined behaviour the fuzzer reported.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "fuzz/spec_input.hpp"

namespace cs {
namespace {

const std::filesystem::path kRegressions = CONTACTSWEEP_FUZZ_REGRESSIONS;

std::string read_bytes(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

TEST(FuzzRegressions, EveryInputGivesARunSpecOrAnInputError) {
  std::vector<std::filesystem::path> files;
  for (const auto& entry : std::filesystem::directory_iterator(kRegressions))
    if (entry.is_regular_file()) files.push_back(entry.path());
  std::sort(files.begin(), files.end());
  ASSERT_FALSE(files.empty()) << "no inputs in " << kRegressions;
  for (const auto& file : files) {
    SCOPED_TRACE(file.filename().string());
    const std::string bytes = read_bytes(file);
    ASSERT_FALSE(bytes.empty()) << "empty or unreadable: " << file;
    EXPECT_EQ(fuzz::check(fuzz::split_input(bytes)), "");
  }
}

// The layout decoding that both the fuzzer and this test rely on.
TEST(FuzzRegressions, InputSplitsIntoTomlAndUpToTwoOverrides) {
  using namespace std::string_literals;
  const auto none = fuzz::split_input("a = 1"s);
  EXPECT_EQ(none.toml, "a = 1");
  EXPECT_TRUE(none.overrides.empty());
  const auto one = fuzz::split_input("a = 1\0x.y=2"s);
  EXPECT_EQ(one.toml, "a = 1");
  EXPECT_EQ(one.overrides, std::vector<std::string>{"x.y=2"});
  const auto two = fuzz::split_input("\0x=1\0y=2\0z"s);
  EXPECT_EQ(two.toml, "");
  EXPECT_EQ(two.overrides, (std::vector<std::string>{"x=1", "y=2\0z"s}));
}

}  // namespace
}  // namespace cs
