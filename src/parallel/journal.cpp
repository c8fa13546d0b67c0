#include "parallel/journal.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <climits>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <sstream>
#include <stdexcept>

#include "formula/k_formula.hpp"
#include "io/durable_file.hpp"
#include "io/log.hpp"
#include "io/owned_directory.hpp"
#include "model/run_spec.hpp"

namespace cs {
namespace {

constexpr char kBlockMagic[8] = {'C', 'S', 'J', 'B', 'L', 'K', '0', '3'};  // 03: word checksum
constexpr std::size_t kRunIdBytes = 16;  // run_identity() is 16 hex digits
constexpr const char* kManifestHeader = "contactsweep journal 2";
constexpr const char* kOldManifestHeader = "contactsweep journal";  // format 1: no identity
constexpr std::int64_t kMaxSpecBytes = std::int64_t{1} << 26;  // larger: a damaged manifest
constexpr std::size_t kMostManifestBytes = 2 * kMaxSpecBytes;  // the spec and a few lines
// A settlement record (engine/settlement_records.hpp): a point of phase space and its period.
constexpr std::size_t kMostRecordWidth = 2 * kMaxFormulaDof + 1;

// FNV-1a over the payload, a 64-bit word at a time in four interleaved streams, then the tail
// byte by byte: catches a torn or truncated block file. Each step (h ^ w)·prime is a bijection
// of h for odd prime, so a change in any one word always changes the sum. Byte by byte it took
// ~1.5 ns a byte: 10 ms of the writer's time on a 512² map.
std::uint64_t checksum(const void* data, std::size_t bytes) {
  constexpr std::uint64_t kBasis = 1469598103934665603ull, kPrime = 1099511628211ull;
  const auto* p = static_cast<const unsigned char*>(data);
  std::uint64_t stream[4] = {kBasis, kBasis ^ 1, kBasis ^ 2, kBasis ^ 3};
  std::size_t i = 0;
  for (; i + sizeof stream <= bytes; i += sizeof stream)
    for (int k = 0; k < 4; ++k) {
      std::uint64_t word;
      std::memcpy(&word, p + i + k * sizeof word, sizeof word);
      stream[k] = (stream[k] ^ word) * kPrime;
    }
  std::uint64_t sum = kBasis ^ bytes;
  for (std::uint64_t s : stream) sum = (sum ^ s) * kPrime;
  for (; i < bytes; ++i) sum = (sum ^ p[i]) * kPrime;
  return sum;
}

std::string errno_text(int error) { return std::strerror(error); }

bool all_digits(std::string_view text) {
  return !text.empty() && text.find_first_not_of("0123456789") == std::string_view::npos;
}

// The names the journal format defines: clearing a journal removes these and nothing else, so a
// file someone else put there is never deleted (the directory then stays, with a warning).
bool is_journal_entry(std::string_view name) {
  if (name.size() > 4 && name.substr(name.size() - 4) == ".tmp") name.remove_suffix(4);
  if (name == "manifest") return true;
  return name.size() > 10 && name.substr(0, 6) == "block_" && name.substr(name.size() - 4) == ".bin" &&
         all_digits(name.substr(6, name.size() - 10));
}

std::string manifest_text(const JournalManifest& m) {
  std::ostringstream s;
  s << kManifestHeader << "\nrun " << m.run_id << "\nbuild " << m.build << "\npoints " << m.points
    << "\nblock_size " << m.block_size << "\nreplaces_output " << (m.replaces_output ? 1 : 0)
    << "\nspec_bytes " << m.spec_text.size() << "\n"
    << m.spec_text;
  return s.str();
}

// "key value" on one line; false when the key differs.
bool read_field(std::istream& in, const char* key, std::string& value) {
  std::string line;
  if (!std::getline(in, line)) return false;
  const std::string prefix = std::string(key) + " ";
  if (line.rfind(prefix, 0) != 0) return false;
  value = line.substr(prefix.size());
  return true;
}

bool read_number(std::istream& in, const char* key, std::int64_t& value) {
  std::string text;
  if (!read_field(in, key, text)) return false;
  try {
    std::size_t used = 0;
    value = std::stoll(text, &used);
    return used == text.size();
  } catch (const std::exception&) {
    return false;
  }
}

// The manifest, or the reason there is none ("" when there is no manifest file at all).
std::optional<JournalManifest> read_manifest(const OwnedDirectory& dir, std::string& problem) {
  const std::string path = dir.path_of("manifest");
  struct stat status {};
  if (::fstatat(dir.fd(), "manifest", &status, AT_SYMLINK_NOFOLLOW) != 0) return std::nullopt;
  std::string bytes;
  if (!dir.read_file("manifest", bytes, kMostManifestBytes)) {
    problem = "its manifest " + path + " is not a readable file of yours";
    return std::nullopt;
  }
  std::istringstream in(bytes);
  std::string header;
  std::getline(in, header);
  if (header == kOldManifestHeader) {
    problem = "it was left by an older contactsweep whose journal did not identify its build";
    return std::nullopt;
  }
  JournalManifest m;
  std::int64_t replaces = 0, spec_bytes = 0;
  if (header != kManifestHeader || !read_field(in, "run", m.run_id) ||
      !read_field(in, "build", m.build) || !read_number(in, "points", m.points) ||
      !read_number(in, "block_size", m.block_size) ||
      !read_number(in, "replaces_output", replaces) ||
      !read_number(in, "spec_bytes", spec_bytes) || spec_bytes < 0 ||
      spec_bytes > kMaxSpecBytes) {
    problem = "its manifest " + path + " is damaged";
    return std::nullopt;
  }
  m.replaces_output = replaces != 0;
  m.spec_text.resize(static_cast<std::size_t>(spec_bytes));
  if (!in.read(m.spec_text.data(), spec_bytes) || in.peek() != EOF) {
    problem = "its manifest " + path + " is damaged";
    return std::nullopt;
  }
  return m;
}

std::string lock_holder_text() {
  char host[HOST_NAME_MAX + 1] = {};
  ::gethostname(host, sizeof host);
  const std::time_t now = std::chrono::system_clock::to_time_t(std::chrono::system_clock::now());
  char when[32] = {};
  std::strftime(when, sizeof when, "%Y-%m-%d %H:%M:%S UTC", std::gmtime(&now));
  return "pid " + std::to_string(::getpid()) + " on " + host + ", started " + when;
}

// Non-blocking write lock on the whole file. Open file description locks stay with this fd
// whatever else the process opens and closes; F_SETLK is the fallback for kernels or file
// systems without them. Returns 0 or errno.
int try_lock(int fd) {
  struct flock request {};
  request.l_type = F_WRLCK;
  request.l_whence = SEEK_SET;
  if (::fcntl(fd, F_OFD_SETLK, &request) == 0) return 0;
  if (errno != EINVAL) return errno;
  return ::fcntl(fd, F_SETLK, &request) == 0 ? 0 : errno;
}

}  // namespace

Journal::Journal(const std::string& output_path, std::string run_id)
    : directory_(output_path + ".journal"), run_id_(std::move(run_id)) {}

Journal::~Journal() {
  // Refused before it began: leave no trace, but only of our own. A run that made the directory
  // and then lost the lock to another leaves that run's lock file alone: removing it let a
  // third run lock a fresh file beside the live one, and the two wrote one output.
  if (!started_ && dir_.created() && lock_fd_ >= 0) {
    dir_.remove_file("lock");
    ::rmdir(directory_.c_str());
  }
  if (lock_fd_ >= 0) ::close(lock_fd_);
}

const OwnedDirectory& Journal::dir() const {
  std::call_once(opened_, [&] {
    dir_ = OwnedDirectory(directory_, "the journal of this output", OwnedDirectory::Create::no);
  });
  if (!dir_.is_open())
    throw std::runtime_error("the journal '" + directory_ + "' of this run is missing");
  return dir_;
}

void Journal::lock() {
  auto refuse = [&](const std::string& why) {
    throw InputError("cannot lock the journal '" + directory_ + "' of this output: " + why);
  };
  // Made here (0700) or checked: a link, another user's directory or one others can write to is
  // refused, before anything in it is read or removed.
  std::call_once(opened_, [&] {
    dir_ = OwnedDirectory(directory_, "the journal of this output", OwnedDirectory::Create::yes);
  });
  const std::string path = dir_.path_of("lock");
  // A run that finishes removes its lock file while holding it; one that we opened just before
  // may then be gone, so the lock only counts if the file is still the one named "lock".
  for (int attempt = 0; attempt < 100; ++attempt) {
    int fd = ::openat(dir_.fd(), "lock", O_RDWR | O_CREAT | O_NOFOLLOW | O_CLOEXEC, 0600);
    if (fd < 0 && errno == ENOENT) refuse("it was removed while this run started");
    if (fd < 0) refuse(path + ": " + errno_text(errno));
    if (int failure = try_lock(fd); failure != 0) {
      if (failure == ENOLCK) {  // a file system without locks (an NFS mount without lockd)
        log("contactsweep: warning: the file system of '{}' cannot lock files; nothing stops a "
            "second run on this output while this one lives", directory_);
        // Kept, unlocked, as a held lock is: a start refused now still removes the directory
        // it made (~Journal), which was left behind with its lock file.
        lock_fd_ = fd;
        return;
      }
      std::string holder(256, '\0');
      const ssize_t n = ::pread(fd, holder.data(), holder.size(), 0);
      holder.resize(n > 0 ? static_cast<std::size_t>(n) : 0);
      ::close(fd);
      if (failure == EAGAIN || failure == EACCES)
        throw InputError("another run is writing this output (" +
                         (holder.empty() ? std::string("its lock: ") + path : holder) +
                         "); wait for it to end, or choose another output");
      refuse(path + ": " + errno_text(failure));
    }
    struct stat held {}, named {};
    if (::fstat(fd, &held) != 0 ||
        ::fstatat(dir_.fd(), "lock", &named, AT_SYMLINK_NOFOLLOW) != 0 ||
        held.st_ino != named.st_ino || held.st_dev != named.st_dev) {
      ::close(fd);
      continue;
    }
    const std::string holder = lock_holder_text();
    if (::ftruncate(fd, 0) != 0 || ::pwrite(fd, holder.data(), holder.size(), 0) < 0) {
      // The lock holds all the same; only the text naming its holder is missing.
    }
    lock_fd_ = fd;
    return;
  }
  refuse("its lock file keeps disappearing");
}

JournalContents Journal::inspect() const {
  JournalContents contents;
  contents.directory_exists = dir_.is_open();
  if (!contents.directory_exists) return contents;
  contents.manifest = read_manifest(dir_, contents.manifest_problem);
  for (const std::string& name : dir_.names()) {
    if (name == "lock") continue;
    if (name.rfind("block_", 0) == 0 && is_journal_entry(name) &&
        name.substr(name.size() - 4) == ".bin")
      ++contents.block_files;
    struct stat status {};
    if (::fstatat(dir_.fd(), name.c_str(), &status, AT_SYMLINK_NOFOLLOW) == 0 &&
        S_ISREG(status.st_mode))
      contents.bytes += static_cast<std::int64_t>(status.st_size);
  }
  return contents;
}

// Blocks first, the manifest last: a journal cut short at any point still names its run for as
// long as it holds a block, and one without a manifest holds none. Only the journal's own names
// are removed, one file at a time: never a directory, never through a link.
void Journal::remove_blocks_then_manifest() const {
  for (const std::string& name : dir_.names())
    if (name != "manifest" && is_journal_entry(name)) dir_.remove_file(name);
  if (!dir_.remove_file("manifest"))
    throw std::runtime_error("cannot clear the journal '" + directory_ + "': " +
                             errno_text(errno));
}

void Journal::start(const JournalManifest& manifest) {
  remove_blocks_then_manifest();
  dir_.write_atomically("manifest", manifest_text(manifest));
  // The manifest's name on disk before any block's: after a power cut, a journal holding blocks
  // must still name its run. A directory this run made needs its own name made durable too.
  dir_.sync_names();
  if (dir_.created()) sync_directory(std::filesystem::absolute(directory_).parent_path().string());
  started_ = true;
}

void Journal::sync_saved() const { dir().sync_names(); }

std::string Journal::block_name(std::int64_t begin) {
  return "block_" + std::to_string(begin) + ".bin";
}

void Journal::save(const BlockResults& block) const {
  // Reserved whole: appending to a growing string copied a block's columns about twice more.
  std::size_t size = sizeof kBlockMagic + kRunIdBytes + 3 * sizeof(std::int64_t) + sizeof(std::uint64_t);
  for (const auto& col : block.columns) size += sizeof(std::int64_t) + col.size() * sizeof(double);
  std::string bytes;
  bytes.reserve(size);
  bytes.append(kBlockMagic, sizeof kBlockMagic);
  auto put = [&](const void* p, std::size_t n) { bytes.append(static_cast<const char*>(p), n); };
  std::string stamp = run_id_;
  stamp.resize(kRunIdBytes, ' ');
  put(stamp.data(), kRunIdBytes);
  std::int64_t header[3] = {block.range.begin, block.range.end,
                            static_cast<std::int64_t>(block.columns.size())};
  put(header, sizeof header);
  for (const auto& col : block.columns) {
    auto n = static_cast<std::int64_t>(col.size());
    put(&n, sizeof n);
  }
  for (const auto& col : block.columns)
    if (!col.empty()) put(col.data(), col.size() * sizeof(double));
  std::uint64_t sum = checksum(bytes.data(), bytes.size());
  put(&sum, sizeof sum);
  dir().write_atomically(block_name(block.range.begin), bytes);
}

bool Journal::load(BlockResults& block) const {
  const std::size_t fixed = sizeof kBlockMagic + kRunIdBytes + 3 * sizeof(std::int64_t) +
                            block.columns.size() * sizeof(std::int64_t) + sizeof(std::uint64_t);
  // The most a block of this run can hold, so that a damaged file's size (a block extended to
  // a terabyte) is never allocated: its columns, a growing one (the settlement records) at most
  // one record a point.
  std::size_t most = fixed;
  const auto points = static_cast<std::size_t>(block.range.end - block.range.begin);
  for (std::size_t k = 0; k < block.columns.size(); ++k)
    most += (k < block.grows.size() && block.grows[k] ? points * kMostRecordWidth : block.columns[k].size()) *
            sizeof(double);
  std::string bytes;
  if (!dir().read_file(block_name(block.range.begin), bytes, most)) return false;
  if (bytes.size() < fixed || std::memcmp(bytes.data(), kBlockMagic, sizeof kBlockMagic) != 0)
    return false;
  std::uint64_t sum;
  std::memcpy(&sum, bytes.data() + bytes.size() - sizeof sum, sizeof sum);
  if (sum != checksum(bytes.data(), bytes.size() - sizeof sum)) return false;
  const char* p = bytes.data() + sizeof kBlockMagic;
  std::string stamp = run_id_;
  stamp.resize(kRunIdBytes, ' ');
  if (std::memcmp(p, stamp.data(), kRunIdBytes) != 0) return false;  // another run's block
  p += kRunIdBytes;
  std::int64_t header[3];
  std::memcpy(header, p, sizeof header);
  p += sizeof header;
  if (header[0] != block.range.begin || header[1] != block.range.end ||
      header[2] != static_cast<std::int64_t>(block.columns.size()))
    return false;
  // Each column's length: the plan's, or any for a column that grows as its block runs.
  std::size_t expected = fixed;
  std::vector<std::size_t> lengths;
  for (std::size_t k = 0; k < block.columns.size(); ++k) {
    std::int64_t n;
    std::memcpy(&n, p, sizeof n);
    p += sizeof n;
    const bool grows = k < block.grows.size() && block.grows[k];
    if (n < 0 || (!grows && n != static_cast<std::int64_t>(block.columns[k].size()))) return false;
    if (static_cast<std::uint64_t>(n) > (bytes.size() - fixed) / sizeof(double)) return false;
    lengths.push_back(static_cast<std::size_t>(n));
    expected += lengths.back() * sizeof(double);
  }
  if (bytes.size() != expected) return false;
  for (std::size_t k = 0; k < block.columns.size(); ++k) block.columns[k].resize(lengths[k]);
  for (auto& col : block.columns) {
    if (col.empty()) continue;  // a growing column may be empty: its data() may be null
    std::memcpy(col.data(), p, col.size() * sizeof(double));
    p += col.size() * sizeof(double);
  }
  return true;
}

void Journal::remove() {
  remove_blocks_then_manifest();
  dir_.remove_file("lock");
  if (::rmdir(directory_.c_str()) != 0 && errno != ENOENT) {
    const int error = errno;
    std::string foreign;
    for (const std::string& name : dir_.names()) foreign += (foreign.empty() ? "" : ", ") + name;
    log("contactsweep: warning: the journal '{}' was not removed ({}){}{}", directory_,
        errno_text(error), foreign.empty() ? "" : ": it holds files contactsweep did not make: ",
        foreign);
  }
  if (lock_fd_ >= 0) ::close(lock_fd_);
  lock_fd_ = -1;
}

}  // namespace cs
