#include "parallel/run_identity.hpp"

#include <elf.h>
#include <link.h>

#include <cstring>
#include <fmt/core.h>
#include <fstream>
#include <iterator>
#include <string_view>

#include "version.hpp"

namespace cs {

std::uint64_t fnv1a(std::string_view bytes, std::uint64_t h) {
  for (unsigned char c : bytes) h = (h ^ c) * 1099511628211ull;
  return h;
}

namespace {


std::string hex(const unsigned char* bytes, std::size_t n) {
  std::string out;
  for (std::size_t i = 0; i < n; ++i) out += fmt::format("{:02x}", bytes[i]);
  return out;
}

// The object holding this very code: the contactsweep program, or the Python module
// (python/module.cpp) when the engine runs inside Python, whose main program is the interpreter.
bool holds_this_code(const dl_phdr_info* info) {
  const auto here = reinterpret_cast<ElfW(Addr)>(&fnv1a);
  for (int i = 0; i < info->dlpi_phnum; ++i) {
    const ElfW(Phdr)& segment = info->dlpi_phdr[i];
    const ElfW(Addr) start = info->dlpi_addr + segment.p_vaddr;
    if (segment.p_type == PT_LOAD && here >= start && here < start + segment.p_memsz) return true;
  }
  return false;
}

// The NT_GNU_BUILD_ID note of the object holding this code.
int find_build_id(dl_phdr_info* info, std::size_t, void* out) {
  if (!holds_this_code(info)) return 0;  // go on to the next object
  for (int i = 0; i < info->dlpi_phnum; ++i) {
    const ElfW(Phdr)& segment = info->dlpi_phdr[i];
    if (segment.p_type != PT_NOTE) continue;
    const auto* p = reinterpret_cast<const unsigned char*>(info->dlpi_addr + segment.p_vaddr);
    const auto* end = p + segment.p_memsz;
    while (p + sizeof(ElfW(Nhdr)) <= end) {
      ElfW(Nhdr) note;
      std::memcpy(&note, p, sizeof note);
      const unsigned char* name = p + sizeof note;
      const unsigned char* desc = name + ((note.n_namesz + 3) & ~3u);
      if (note.n_type == NT_GNU_BUILD_ID && note.n_namesz == 4 &&
          std::memcmp(name, "GNU", 4) == 0 && desc + note.n_descsz <= end) {
        *static_cast<std::string*>(out) = hex(desc, note.n_descsz);
        return 1;
      }
      p = desc + ((note.n_descsz + 3) & ~3u);
    }
  }
  return 1;  // the object holding this code has no build-id
}

std::string compute_build_identity() {
  std::string id;
  dl_iterate_phdr(find_build_id, &id);
  if (!id.empty()) return "build-id " + id;
  std::ifstream exe("/proc/self/exe", std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(exe)), std::istreambuf_iterator<char>());
  return fmt::format("exe-fnv1a {:016x}", fnv1a(bytes));
}

}  // namespace

const std::string& build_identity() {
  static const std::string id = std::string(kVersion) + " " + compute_build_identity();
  return id;
}

std::string run_identity(const std::string& spec_text, std::int64_t points,
                         std::int64_t block_size) {
  std::uint64_t h = fnv1a(spec_text);
  h = fnv1a(std::string_view("\0", 1), h);
  h = fnv1a(build_identity(), h);
  h = fnv1a(fmt::format("\n{} {}", points, block_size), h);
  return fmt::format("{:016x}", h);
}

}  // namespace cs
