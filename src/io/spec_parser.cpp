// Spec file -> RunSpec: TOML parsing (toml++), then --set overrides (spec_overrides.cpp), the
// reader of each section against the scene and method catalogs (spec_reader.hpp) and the
// canonical TOML text stored in the output (spec_text.cpp). Decisions: spec_parser.hpp.
#include "io/spec_parser.hpp"

#include <fmt/format.h>
#include <toml++/toml.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "io/spec_overrides.hpp"
#include "io/spec_reader.hpp"
#include "io/spec_text.hpp"

namespace cs {
namespace {

toml::table parse_document(std::string_view text, std::string_view source_name) {
  try {
    return toml::parse(text, std::string(source_name));
  } catch (const toml::parse_error& error) {
    throw InputError(fmt::format("{}:{}:{}: malformed TOML: {}", source_name,
                                 error.source().begin.line, error.source().begin.column,
                                 error.description()));
  }
}

}  // namespace

std::string read_spec_file(const std::string& path) {
  std::error_code ignored;
  if (std::filesystem::is_directory(path, ignored))
    throw InputError(fmt::format("cannot read spec file '{}': it is a directory", path));
  std::ifstream in(path, std::ios::binary);
  if (!in)
    throw InputError(fmt::format("cannot read spec file '{}': {}", path, std::strerror(errno)));
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) throw InputError(fmt::format("cannot read spec file '{}': read error", path));
  return text.str();
}

RunSpec parse_run_spec(std::string_view toml_text, const std::vector<std::string>& overrides,
                       std::string_view source_name) {
  toml::table doc = parse_document(toml_text, source_name);
  const spec::Names grid_order = spec::apply_overrides(doc, overrides);
  RunSpec spec = spec::SpecReader(doc, source_name, grid_order).read();
  spec.spec_text = spec::canonical_text(doc, grid_order);
  return spec;
}

RunSpec load_run_spec(const std::string& path, const std::vector<std::string>& overrides) {
  return parse_run_spec(read_spec_file(path), overrides, path);
}

}  // namespace cs
