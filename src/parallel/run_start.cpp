#include "parallel/run_start.hpp"

#include <fmt/core.h>
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <optional>

#include "io/output_inspect.hpp"
#include "mpi/agreement.hpp"
#include "mpi/comm.hpp"
#include "parallel/run_identity.hpp"

namespace cs {
namespace {

// `text` with its control characters written as \xNN: a link's target is anyone's text (another
// user's link at the output's name in a shared directory), and raw it reached the terminal,
// escape sequences included (a window title set, the screen cleared). Control characters are
// C0 and DEL, and the C1 controls U+0080-U+009F as UTF-8 (a UTF-8 terminal takes U+009B for
// ESC [); a byte that is no part of valid UTF-8 is written out too (a raw 0x9B is ESC [ to an
// 8-bit terminal). Other UTF-8, a name in another script, stays as it is.
std::string printable(const std::string& text) {
  std::string out;
  std::size_t i = 0;
  while (i < text.size()) {
    const auto lead = static_cast<unsigned char>(text[i]);
    const std::size_t n = lead < 0x80           ? 1
                          : (lead >> 5) == 0x6  ? 2
                          : (lead >> 4) == 0xe  ? 3
                          : (lead >> 3) == 0x1e ? 4
                                                : 0;
    bool valid = n > 0 && i + n <= text.size();
    char32_t code = n == 1 ? lead : n == 2 ? lead & 0x1f : n == 3 ? lead & 0x0f : lead & 0x07;
    for (std::size_t k = 1; valid && k < n; ++k) {
      const auto next = static_cast<unsigned char>(text[i + k]);
      valid = (next & 0xc0) == 0x80;
      code = (code << 6) | (next & 0x3f);
    }
    // Overlong forms (C0 9B is ESC) and surrogates are no valid UTF-8.
    constexpr char32_t kLeast[5] = {0, 0, 0x80, 0x800, 0x10000};
    if (valid && n > 1)
      valid = code >= kLeast[n] && code <= 0x10ffff && (code < 0xd800 || code > 0xdfff);
    const bool control = code < 0x20 || code == 0x7f || (code >= 0x80 && code <= 0x9f);
    const std::size_t bytes = valid ? n : 1;
    if (!valid || control) {
      for (std::size_t k = 0; k < bytes; ++k)
        out += fmt::format("\\x{:02x}", static_cast<unsigned char>(text[i + k]));
    } else {
      out.append(text, i, bytes);
    }
    i += bytes;
  }
  return out;
}

void check_output_path(const SweepOptions& options) {
  namespace fs = std::filesystem;
  std::error_code error;
  const fs::file_status status = fs::status(options.output, error);
  if (fs::is_symlink(fs::symlink_status(options.output, error)) && !fs::exists(status))
    throw InputError("output '" + options.output + "' is a symbolic link to nothing ('" +
                     printable(fs::read_symlink(options.output, error).string()) +
                     "'); remove it or name another file");
  if (fs::is_directory(status))
    throw InputError("output '" + options.output + "' is a directory; name a file, e.g. -o " +
                     (fs::path(options.output) / "map.h5").string());
  if (fs::exists(status) && !fs::is_regular_file(status))
    throw InputError("output '" + options.output +
                     "' exists and is not a regular file (a device, pipe or socket); contactsweep "
                     "replaces only regular files, even with --force");
  auto directory = fs::absolute(options.output).parent_path();
  // access() alone passes a regular file for root, so the parent must be a directory too.
  if (!fs::is_directory(directory, error) || ::access(directory.c_str(), W_OK) != 0)
    throw InputError("cannot write the output '" + options.output + "': directory '" +
                     directory.string() + "' is missing or not writable");
  // In a sticky directory (/tmp, a shared scratch) only a file's owner (or the directory's)
  // may replace it: refused now rather than when the finished run is put in place.
  struct stat file {}, dir {};
  if (::lstat(options.output.c_str(), &file) == 0 && file.st_uid != ::geteuid() && ::geteuid() != 0 &&
      ::stat(directory.c_str(), &dir) == 0 && (dir.st_mode & S_ISVTX) != 0 && dir.st_uid != ::geteuid())
    throw InputError(fmt::format("output '{}' belongs to user id {} in a directory with the sticky "
                                 "bit ('{}'), where only its owner may replace it; name another file",
                                 options.output, file.st_uid, directory.string()));
}

// Rank 0 only, with the journal locked. Throws InputError when the user must choose.
StartDecision decide_start(const RunSpec& spec, const SweepOptions& options, Journal& journal,
                           const std::string& run_id) {
  if (options.force) return {Start::fresh, true, false, 0};
  const JournalContents j = journal.inspect();
  const bool output_exists = std::filesystem::exists(std::filesystem::symlink_status(options.output));
  // Read only once the output is known to be the user's own (inspect_existing_output says why).
  std::optional<ExistingOutput> existing;
  auto inspected = [&]() -> const ExistingOutput& {
    if (!existing) existing = inspect_existing_output(options.output);
    return *existing;
  };
  auto output_made_by_this_spec = [&] { return inspected().ours && inspected().spec == spec.spec_text; };
  const std::string saved = fmt::format("{} block(s) saved", j.block_files);

  if (j.manifest && j.manifest->run_id == run_id) {  // this very run, interrupted
    if (output_exists && !j.manifest->replaces_output && !inspected().ours)
      throw InputError("output '" + options.output + "' " + inspected().why_not +
                       ": it is not taken as this run's result; move it away, then --resume "
                       "finishes the run from its journal '" + journal.directory() + "' (" +
                       saved + ")");
    // Killed after its commit, unless the run was started to replace that very file (--force
    // over an output of the same spec, say from another build): then the file may be the old
    // one, and finishing from the journal is the only safe reading.
    if (output_exists && !j.manifest->replaces_output && output_made_by_this_spec())
      return {Start::complete, false, true, 0};
    if (!options.resume)
      throw InputError("an unfinished run of this spec left its journal in '" +
                       journal.directory() + "' (" + saved +
                       "); pass --resume to continue it or --force to discard it");
    if (output_exists && !j.manifest->replaces_output)
      throw InputError("output '" + options.output +
                       "' appeared after this run started and was not made by it; move it away, "
                       "then --resume finishes the run from its journal '" +
                       journal.directory() + "' (" + saved + ")");
    return {Start::resume, j.manifest->replaces_output, false, j.bytes};
  }

  if (output_exists) {
    if (!options.resume)
      throw InputError("output '" + options.output +
                       "' exists; pass --force to replace it or --resume to continue that run");
    // A journal holding neither manifest nor block is what a kill during an earlier run's
    // removal leaves: debris, removed with it. Another run's journal stays.
    const bool debris = j.directory_exists && !j.manifest && j.block_files == 0;
    if (!inspected().ours)
      throw InputError("--resume: output '" + options.output + "' " + inspected().why_not +
                       ", so it is not taken as a finished run; name another file, or pass "
                       "--force to replace it");
    if (output_made_by_this_spec()) return {Start::complete, false, debris, 0};
    throw InputError("--resume: output '" + options.output +
                     "' was not made by this spec (after --set); pass --force to replace it");
  }

  if (j.manifest || j.block_files > 0) {  // another run's unfinished work: the user decides
    std::string maker;
    if (!j.manifest)
      maker = j.manifest_problem.empty() ? "a run whose manifest is missing" : j.manifest_problem;
    else if (j.manifest->spec_text != spec.spec_text)
      maker = "a different spec (after --set)";
    else if (j.manifest->build != build_identity())
      maker = "another build of contactsweep (" + j.manifest->build + "; this is " +
              build_identity() + "), whose results may differ";
    else
      maker = "the same spec cut into other blocks";
    throw InputError(std::string(options.resume ? "--resume: " : "") + "the unfinished run in '" +
                     journal.directory() + "' (" + saved + ") was made by " + maker +
                     "; pass --force to discard it" +
                     (options.resume ? "" : ", or --resume with the spec that made it"));
  }
  return {Start::fresh, false, false, 0};  // nothing, or a journal holding no block
}

}  // namespace

StartDecision agreed_start(const RunSpec& spec, const SweepOptions& options, Journal& journal,
                           const std::string& run_id, MPI_Comm comm) {
  StartDecision d = agreed(comm, [&] {
    if (rank_of(comm) != 0) return StartDecision{};
    check_output_path(options);
    journal.lock();
    return decide_start(spec, options, journal, run_id);
  });
  std::int64_t fields[4] = {static_cast<std::int64_t>(d.start), d.replace_output,
                            d.remove_journal, d.journal_bytes};
  bcast(comm, fields, 4, MPI_INT64_T, 0);
  return {static_cast<Start>(fields[0]), fields[1] != 0, fields[2] != 0, fields[3]};
}

}  // namespace cs
